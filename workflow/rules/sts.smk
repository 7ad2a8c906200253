# Sit-to-stand kinematics, joint loads, module tuning and the checks of the motion laws (“Kinematic
# and force analysis”, docs/rig.md §2). Model-only group: everything follows from the config and
# the numbers the study reports. The thigh link's strength, the figures and the verdict:
# sts_strength.smk.

STS = RESULTS / "sts"
STS_FIGURES = RESULTS / "figures" / "sts"
# the motion laws and their trajectory files (exobench.sts.motion.LAWS)
STS_LAWS = {
    "piecewise": STS / "trajectories.parquet",
    "smooth": STS / "trajectories_smooth.parquet",
    "corrected": STS / "trajectories_corrected.parquet",
    "corrected_study_seat": STS / "trajectories_corrected_study_seat.parquet",
}
# the motion-law settings every law is built from (exobench.sts.corrected.configured_laws)
STS_LAW_SETTINGS = {
    key: setting(f"sts/{key}")
    for key in (
        "sample_rate_Hz",
        "links_mm",
        "study_law",
        "readings",
        "body",
        "checks",
        "corrected",
    )
}


rule sts_kinematics:
    output:
        piecewise=in_report(
            STS_LAWS["piecewise"], "sts", "sts_kinematics", "Kinematics"
        ),
        smooth=in_report(STS_LAWS["smooth"], "sts", "sts_kinematics", "Kinematics"),
        corrected=in_report(
            STS_LAWS["corrected"], "sts", "sts_kinematics", "Kinematics"
        ),
        corrected_study_seat=in_report(
            STS_LAWS["corrected_study_seat"], "sts", "sts_kinematics", "Kinematics"
        ),
        verification=in_report(
            STS / "verification.json", "sts", "sts_kinematics", "Kinematics"
        ),
        postures=in_report(
            STS / "corrected_laws.json", "sts", "sts_kinematics", "Kinematics"
        ),
    log:
        logfile("sts_kinematics"),
    benchmark:
        benchfile("sts_kinematics")
    priority: 1
    resources:
        mem_mb=500,
        runtime=5,
    params:
        **STS_LAW_SETTINGS,
        code=code("sts_kinematics.py"),
    message:
        "sit-to-stand kinematics of every motion law and their check"
    script:
        "../scripts/sts_kinematics.py"


rule sts_loads:
    input:
        **STS_LAWS,
    output:
        loads=STS / "loads.parquet",
        comparison=in_report(
            STS / "motion_comparison.json", "sts", "sts_loads", "Loads"
        ),
    log:
        logfile("sts_loads"),
    benchmark:
        benchfile("sts_loads")
    priority: 1
    resources:
        mem_mb=500,
        runtime=5,
    params:
        code=code("sts_loads.py"),
        links_mm=setting("sts/links_mm"),
        design_load_N=setting("sts/design_load_N"),
        link_masses_kg=setting("sts/link_masses_kg"),
        modules=setting("sts/modules"),
    message:
        "joint loads of the sit-to-stand motion under the design load"
    script:
        "../scripts/sts_loads.py"


rule sts_modules:
    input:
        **STS_LAWS,
        loads=rules.sts_loads.output.loads,
    output:
        fit=in_report(STS / "spring_damper.json", "sts", "sts_modules", "Loads"),
        torques=in_report(STS / "spring_damper.parquet", "sts", "sts_modules", "Loads"),
    log:
        logfile("sts_modules"),
    benchmark:
        benchfile("sts_modules")
    priority: 1
    resources:
        mem_mb=500,
        runtime=10,
    params:
        code=code("sts_modules.py"),
        tuning=setting("sts/tuning"),
        modules=setting("sts/modules"),
    message:
        "tune the spring-damper modules on the study's and the corrected laws"
    script:
        "../scripts/sts_modules.py"


rule sts_checks:
    input:
        user_laws=config["sts"]["user_laws"],
    output:
        checks=in_report(STS / "checks.csv", "sts", "sts_checks", "Checks"),
        readings=in_report(STS / "readings.json", "sts", "sts_checks", "Checks"),
    log:
        logfile("sts_checks"),
    benchmark:
        benchfile("sts_checks")
    resources:
        mem_mb=500,
        runtime=5,
    params:
        **STS_LAW_SETTINGS,
        code=code("sts_checks.py"),
    message:
        "every reading of the study's law and every other law through the same checks"
    script:
        "../scripts/sts_checks.py"
