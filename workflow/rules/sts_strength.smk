# Sit-to-stand, second stage: the thigh link's strength (closed forms and finite elements), the
# figures and the verdict (summary.md). The motion laws and their loads: sts.smk.


rule sts_beam:
    input:
        loads=rules.sts_loads.output.loads,
        reported=REFERENCE / "seed001_reported.csv",
        code=code("sts_beam.py"),
    output:
        report(
            STS / "beam_check.json",
            caption="../report/sts_beam.rst",
            category="Sit-to-stand",
            subcategory="Strength",
        ),
    log:
        logfile("sts_beam"),
    benchmark:
        benchfile("sts_beam")
    resources:
        mem_mb=500,
        runtime=5,
    params:
        thigh_link=lookup(dpath="sts/thigh_link", within=config),
        design_load_N=lookup(dpath="sts/design_load_N", within=config),
        l_BC_mm=lookup(dpath="sts/links_mm/l_BC", within=config),
    message:
        "thigh-link strength, stiffness, buckling and fatigue"
    script:
        "../scripts/sts_beam.py"


rule sts_fe:
    input:
        reported=REFERENCE / "seed001_reported.csv",
        code=code("sts_fe.py"),
    output:
        report=report(
            STS / "fe.json",
            caption="../report/sts_fe.rst",
            category="Sit-to-stand",
            subcategory="Strength",
        ),
        field=report(
            STS / "fe_field.parquet",
            caption="../report/sts_fe.rst",
            category="Sit-to-stand",
            subcategory="Strength",
        ),
        mesh=report(
            STS / "fe_mesh.parquet",
            caption="../report/sts_fe.rst",
            category="Sit-to-stand",
            subcategory="Strength",
        ),
    log:
        logfile("sts_fe"),
    benchmark:
        benchfile("sts_fe")
    resources:
        mem_mb=1500,
        runtime=5,
    params:
        thigh_link=lookup(dpath="sts/thigh_link", within=config),
        design_load_N=lookup(dpath="sts/design_load_N", within=config),
        l_BC_mm=lookup(dpath="sts/links_mm/l_BC", within=config),
        fe=lookup(dpath="sts/fe", within=config),
    message:
        "the thigh link by finite elements, its mesh convergence and the study's three numbers"
    script:
        "../scripts/sts_fe.py"


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
        code=code("sts_figures.py"),
    output:
        paths_png=report(
            STS_FIGURES / "paths.png",
            caption="../report/sts_figure_paths.rst",
            category="Sit-to-stand",
            subcategory="Figures",
        ),
        paths_pdf=STS_FIGURES / "paths.pdf",
        paths_caption=STS_FIGURES / "paths.caption.md",
        torques_png=report(
            STS_FIGURES / "torques.png",
            caption="../report/sts_figure_torques.rst",
            category="Sit-to-stand",
            subcategory="Figures",
        ),
        torques_pdf=STS_FIGURES / "torques.pdf",
        torques_caption=STS_FIGURES / "torques.caption.md",
        modules_png=report(
            STS_FIGURES / "modules.png",
            caption="../report/sts_figure_modules.rst",
            category="Sit-to-stand",
            subcategory="Figures",
        ),
        modules_pdf=STS_FIGURES / "modules.pdf",
        modules_caption=STS_FIGURES / "modules.caption.md",
        thigh_png=report(
            STS_FIGURES / "thigh.png",
            caption="../report/sts_figure_thigh.rst",
            category="Sit-to-stand",
            subcategory="Figures",
        ),
        thigh_pdf=STS_FIGURES / "thigh.pdf",
        thigh_caption=STS_FIGURES / "thigh.caption.md",
        fe_png=report(
            STS_FIGURES / "fe.png",
            caption="../report/sts_figure_fe.rst",
            category="Sit-to-stand",
            subcategory="Figures",
        ),
        fe_pdf=STS_FIGURES / "fe.pdf",
        fe_caption=STS_FIGURES / "fe.caption.md",
    log:
        logfile("sts_figures"),
    benchmark:
        benchfile("sts_figures")
    resources:
        mem_mb=1000,
        runtime=5,
    message:
        "sit-to-stand figures with their captions"
    script:
        "../scripts/sts_figures.py"


rule sts_verdict:
    input:
        checks=rules.sts_checks.output[0],
        postures=rules.sts_kinematics.output.postures,
        modules=rules.sts_modules.output.fit,
        fe=rules.sts_fe.output.report,
        code=code("sts_verdict.py"),
    output:
        report(
            STS / "summary.md",
            caption="../report/sts_verdict.rst",
            category="Sit-to-stand",
            subcategory="Verdict",
        ),
    log:
        logfile("sts_verdict"),
    benchmark:
        benchfile("sts_verdict")
    resources:
        mem_mb=500,
        runtime=5,
    message:
        "the verdict in words: summary.md"
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
