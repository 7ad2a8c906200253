# Sit-to-stand kinematics, joint loads and thigh-link strength checks (“Kinematic and force
# analysis”, docs/rig.md §2). Model-only group: everything follows from the config and the
# numbers the study reports.

STS = RESULTS / "sts"
STS_FIGURES = RESULTS / "figures" / "sts"


rule sts_kinematics:
    input:
        code=code("sts_kinematics.py"),
    output:
        piecewise=in_report(
            STS / "trajectories.parquet", "sts", "sts_kinematics", "Kinematics"
        ),
        smooth=in_report(
            STS / "trajectories_smooth.parquet", "sts", "sts_kinematics", "Kinematics"
        ),
        verification=in_report(
            STS / "verification.json", "sts", "sts_kinematics", "Kinematics"
        ),
    log:
        logfile("sts_kinematics"),
    benchmark:
        benchfile("sts_kinematics")
    resources:
        mem_mb=500,
        runtime=5,
    params:
        sample_rate_Hz=lookup(dpath="sts/sample_rate_Hz", within=config),
        links_mm=lookup(dpath="sts/links_mm", within=config),
    message:
        "sit-to-stand kinematics of both motion laws and their check"
    script:
        "../scripts/sts_kinematics.py"


rule sts_loads:
    input:
        piecewise=rules.sts_kinematics.output.piecewise,
        smooth=rules.sts_kinematics.output.smooth,
        code=code("sts_loads.py"),
    output:
        loads=STS / "loads.parquet",
        comparison=in_report(
            STS / "motion_comparison.json", "sts", "sts_loads", "Loads"
        ),
    log:
        logfile("sts_loads"),
    benchmark:
        benchfile("sts_loads")
    resources:
        mem_mb=500,
        runtime=5,
    params:
        links_mm=lookup(dpath="sts/links_mm", within=config),
        design_load_N=lookup(dpath="sts/design_load_N", within=config),
        link_masses_kg=lookup(dpath="sts/link_masses_kg", within=config),
        modules=lookup(dpath="sts/modules", within=config),
    message:
        "joint loads of the sit-to-stand motion under the design load"
    script:
        "../scripts/sts_loads.py"


rule sts_modules:
    input:
        piecewise=rules.sts_kinematics.output.piecewise,
        smooth=rules.sts_kinematics.output.smooth,
        loads=rules.sts_loads.output.loads,
        code=code("sts_modules.py"),
    output:
        fit=in_report(STS / "spring_damper.json", "sts", "sts_modules", "Loads"),
        torques=in_report(STS / "spring_damper.parquet", "sts", "sts_modules", "Loads"),
    log:
        logfile("sts_modules"),
    benchmark:
        benchfile("sts_modules")
    resources:
        mem_mb=500,
        runtime=10,
    params:
        tuning=lookup(dpath="sts/tuning", within=config),
        modules=lookup(dpath="sts/modules", within=config),
    message:
        "tune the spring-damper modules"
    script:
        "../scripts/sts_modules.py"


rule sts_beam:
    input:
        loads=rules.sts_loads.output.loads,
        reported=REFERENCE / "seed001_reported.csv",
        code=code("sts_beam.py"),
    output:
        in_report(STS / "beam_check.json", "sts", "sts_beam", "Strength"),
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


# The group's figures (the sts_figures rule draws each, a caption beside it).
STS_FIGURE_NAMES = [
    "paths",
    "torques",
    "modules",
    "thigh",
]


rule sts_figures:
    input:
        piecewise=rules.sts_kinematics.output.piecewise,
        smooth=rules.sts_kinematics.output.smooth,
        loads=rules.sts_loads.output.loads,
        comparison=rules.sts_loads.output.comparison,
        modules=rules.sts_modules.output.torques,
        beam=rules.sts_beam.output[0],
        code=code("sts_figures.py"),
    output:
        **figure_outputs("sts", STS_FIGURES, STS_FIGURE_NAMES),
    log:
        logfile("sts_figures"),
    benchmark:
        benchfile("sts_figures")
    resources:
        mem_mb=1000,
        runtime=5,
    params:
        figures=STS_FIGURE_NAMES,
    message:
        "sit-to-stand figures with their captions"
    script:
        "../scripts/sts_figures.py"


rule sts:
    input:
        rules.sts_kinematics.output,
        rules.sts_loads.output,
        rules.sts_modules.output,
        rules.sts_beam.output,
        rules.sts_figures.output,
    message:
        "sit-to-stand group up to date"
