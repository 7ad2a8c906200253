# Sit-to-stand, second stage: the thigh link's strength (closed forms and finite elements), the
# figures and the verdict (summary.md). The motion laws and their loads: sts.smk.


rule sts_beam:
    input:
        loads=rules.sts_loads.output.loads,
        reported=REFERENCE / "seed001_reported.csv",
    output:
        in_report(STS / "beam_check.json", "sts", "sts_beam", "Strength"),
    log:
        logfile("sts_beam"),
    benchmark:
        benchfile("sts_beam")
    priority: 1
    resources:
        mem_mb=500,
        runtime=5,
    params:
        code=code("sts_beam.py"),
        thigh_link=setting("sts/thigh_link"),
        design_load_N=setting("sts/design_load_N"),
        l_BC_mm=setting("sts/links_mm/l_BC"),
    message:
        "thigh-link strength, stiffness, buckling and fatigue"
    script:
        "../scripts/sts_beam.py"


rule sts_fe:
    input:
        reported=REFERENCE / "seed001_reported.csv",
    output:
        report=in_report(STS / "fe.json", "sts", "sts_fe", "Strength"),
        field=in_report(STS / "fe_field.parquet", "sts", "sts_fe", "Strength"),
        mesh=in_report(STS / "fe_mesh.parquet", "sts", "sts_fe", "Strength"),
        sections=in_report(STS / "sections.csv", "sts", "sts_fe", "Strength"),
    log:
        logfile("sts_fe"),
    benchmark:
        benchfile("sts_fe")
    priority: 1
    resources:
        mem_mb=1500,
        runtime=5,
    params:
        code=code("sts_fe.py"),
        thigh_link=setting("sts/thigh_link"),
        design_load_N=setting("sts/design_load_N"),
        l_BC_mm=setting("sts/links_mm/l_BC"),
        fe=setting("sts/fe"),
        sections=setting("sts/sections"),
    message:
        "the thigh link by finite elements, its mesh convergence and the study's three numbers"
    script:
        "../scripts/sts_fe.py"


# The group's figures (the sts_figures rule draws each, a caption beside it).
STS_FIGURE_NAMES = ["paths", "torques", "modules", "thigh", "fe"]


rule sts_figures:
    input:
        **STS_LAWS,
        loads=rules.sts_loads.output.loads,
        comparison=rules.sts_loads.output.comparison,
        modules=rules.sts_modules.output.torques,
        beam=rules.sts_beam.output[0],
        fe=rules.sts_fe.output.report,
        field=rules.sts_fe.output.field,
        mesh=rules.sts_fe.output.mesh,
    output:
        **figure_outputs("sts", STS_FIGURES, STS_FIGURE_NAMES),
    log:
        logfile("sts_figures"),
    benchmark:
        benchfile("sts_figures")
    priority: 1
    resources:
        mem_mb=1000,
        runtime=5,
    params:
        code=code("sts_figures.py"),
        figures=STS_FIGURE_NAMES,
    message:
        "sit-to-stand figures with their captions"
    script:
        "../scripts/sts_figures.py"


rule sts_verdict:
    input:
        checks=rules.sts_checks.output.checks,
        readings=rules.sts_checks.output.readings,
        postures=rules.sts_kinematics.output.postures,
        modules=rules.sts_modules.output.fit,
        fe=rules.sts_fe.output.report,
        sections=rules.sts_fe.output.sections,
        reported=REFERENCE / "seed001_reported.csv",
    output:
        summary=in_report(STS / "summary.md", "sts", "sts_verdict", "Verdict"),
        comparison=in_report(
            STS / "study_comparison.csv", "sts", "sts_verdict", "Verdict"
        ),
    log:
        logfile("sts_verdict"),
    benchmark:
        benchfile("sts_verdict")
    resources:
        mem_mb=500,
        runtime=5,
    params:
        code=code("sts_verdict.py"),
        design_load_N=setting("sts/design_load_N"),
        links_mm=setting("sts/links_mm"),
        thigh_link=setting("sts/thigh_link"),
        sections=setting("sts/sections"),
    message:
        "the verdict in words (summary.md) and the study's numbers beside the project's"
    script:
        "../scripts/sts_verdict.py"


rule sts:
    input:
        rules.sts_kinematics.output,
        rules.sts_loads.output,
        rules.sts_modules.output,
        rules.sts_checks.output,
        rules.sts_beam.output,
        rules.sts_fe.output,
        rules.sts_figures.output,
        rules.sts_verdict.output,
    message:
        "sit-to-stand group up to date"
