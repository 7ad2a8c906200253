# Emulator stage 2, engine and verdict: the direct checks of the rig's assumptions, the model
# discrepancy of the recordings and the verdict in words.


rule emulator_checks:
    input:
        manifest=EMULATOR_RAW / "manifest.csv",
        samples=EMULATOR_CHAIN["samples"],
        qc=rules.emulator_summary.output.qc,
    output:
        in_report(
            EMULATOR / "assumption_checks.csv",
            "emulator",
            "emulator_checks",
            "Discrepancy",
        ),
    log:
        logfile("emulator_checks"),
    benchmark:
        benchfile("emulator_checks")
    priority: 2
    resources:
        mem_mb=1000,
        runtime=5,
    params:
        code=code("emulator_checks.py"),
        trials=EMULATOR_TRIALS,
        checks=setting("emulator/checks"),
        sensors=setting("emulator/sensors"),
        transmission=setting("emulator/transmission"),
        controller=setting("emulator/controller"),
        activity_tolerance_s=setting("emulator/analysis/activity_tolerance_s"),
    message:
        "direct checks of the emulator rig's assumptions on the recordings"
    script:
        "../scripts/emulator_checks.py"


rule emulator_discrepancy:
    input:
        manifest=EMULATOR_RAW / "manifest.csv",
        samples=EMULATOR_CHAIN["samples"],
        qc=rules.emulator_summary.output.qc,
        checks=rules.emulator_checks.output[0],
        reported=REFERENCE / "seed002_reported.csv",
    output:
        report=in_report(
            EMULATOR / "discrepancy.json",
            "emulator",
            "emulator_discrepancy",
            "Discrepancy",
        ),
    log:
        logfile("emulator_discrepancy"),
    benchmark:
        benchfile("emulator_discrepancy")
    priority: 2
    resources:
        mem_mb=1000,
        runtime=10,
    params:
        code=code("emulator_discrepancy.py"),
        trials=EMULATOR_TRIALS,
        equilibrium_deg=setting("emulator/controller/equilibrium_deg"),
        direction_blend_deg_per_s=setting(
            "emulator/controller/direction_blend_deg_per_s"
        ),
        torque_filter_Hz=setting("emulator/controller/torque_filter_Hz"),
        engine=setting("discrepancy"),
        seed=setting("seed"),
        transmission=setting("emulator/transmission"),
    message:
        "model discrepancy of the emulator recordings"
    script:
        "../scripts/emulator_discrepancy.py"


rule emulator_verdict:
    input:
        report=rules.emulator_discrepancy.output.report,
        checks=rules.emulator_checks.output[0],
        comparison=EMULATOR / "heer_comparison.csv",
    output:
        summary=in_report(
            EMULATOR / "summary.md", "emulator", "emulator_verdict", "Discrepancy"
        ),
        tests=in_report(
            EMULATOR / "residual_tests.md",
            "emulator",
            "emulator_verdict",
            "Discrepancy",
        ),
    log:
        logfile("emulator_verdict"),
    benchmark:
        benchfile("emulator_verdict")
    resources:
        mem_mb=500,
        runtime=5,
    params:
        code=code("emulator_verdict.py"),
        source=source_spec("emulator", ["emulator.effects", "emulator.sensors"]),
        # the twin's effects as set (the headline with the twin)
        effects=setting("emulator/effects") if SYNTHETIC else {},
        # the recorded torque's low-pass the verdict's energy gap may name
        torque_filter_Hz=setting("emulator/controller/torque_filter_Hz"),
    message:
        "the verdict in words: summary.md"
    script:
        "../scripts/emulator_verdict.py"
