# Emulator stage 1, recordings and chain: the twin's recordings (synthetic), events, steps and energy
# per step of every trial, and the per-condition summary with the session's quality checks.

if SYNTHETIC:

    rule emulator_twin:
        input:
            code=code("emulator_twin.py"),
        output:
            manifest=EMULATOR_RAW / "manifest.csv",
            brace=expand(EMULATOR_RAW / "{trial}_brace.csv", trial=EMULATOR_TRIALS),
            mocap=expand(EMULATOR_RAW / "{trial}_mocap.csv", trial=EMULATOR_TRIALS),
            truth=expand(EMULATOR_RAW / "truth" / "{trial}.json", trial=EMULATOR_TRIALS),
            stamp=EMULATOR_RAW / stamp.STAMP,
        log:
            logfile("emulator_twin"),
        benchmark:
            benchfile("emulator_twin")
        priority: 4
        resources:
            mem_mb=1000,
            runtime=30,
        params:
            protocol=setting("emulator/protocol"),
            gait=setting("emulator/gait"),
            controller=setting("emulator/controller"),
            transmission=setting("emulator/transmission"),
            effects=setting("emulator/effects"),
            sensors=setting("emulator/sensors"),
            seed=setting("seed"),
        message:
            "the emulator digital twin writes its recordings"
        script:
            "../scripts/emulator_twin.py"


# One job analyses every trial (a trial's work is smaller than a job's start-up), still one
# file per trial and output.
rule emulator_trial:
    input:
        unpack(emulator_recordings),
        manifest=EMULATOR_RAW / "manifest.csv",
        code=code("emulator_trial.py"),
    output:
        samples=emulator_trial_files("samples"),
        steps=emulator_trial_files("steps"),
        qc=emulator_trial_files("qc", "json"),
    log:
        logfile("emulator_trial"),
    benchmark:
        benchfile("emulator_trial")
    priority: 3
    resources:
        mem_mb=1000,
        runtime=10,
    params:
        trials=EMULATOR_TRIALS,
        analysis=setting("emulator/analysis"),
        controller=setting("emulator/controller"),
        duration_s=setting("emulator/protocol/duration_s"),
        # a lab's column map; the twin writes the contract's columns (config_checks warns)
        columns={} if SYNTHETIC else setting("emulator/columns"),
        seed=setting("seed"),
    message:
        "events, steps, energy per step and sensor checks of every trial"
    script:
        "../scripts/emulator_trial.py"


rule emulator_summary:
    input:
        manifest=EMULATOR_RAW / "manifest.csv",
        steps=rules.emulator_trial.output.steps,
        qc=rules.emulator_trial.output.qc,
        code=code("emulator_summary.py"),
    output:
        steps=in_report(
            EMULATOR / "energy_per_step.parquet",
            "emulator",
            "emulator_tables",
            "Tables",
        ),
        summary=in_report(
            EMULATOR / "summary.csv", "emulator", "emulator_tables", "Tables"
        ),
        qc=in_report(EMULATOR / "qc.json", "emulator", "emulator_tables", "Tables"),
    log:
        logfile("emulator_summary"),
    benchmark:
        benchfile("emulator_summary")
    priority: 2
    resources:
        mem_mb=500,
        runtime=5,
    params:
        trials=EMULATOR_TRIALS,
        fault_threshold_deg=setting("emulator/analysis/fault_threshold_deg"),
    message:
        "energy per step per condition and the session's quality checks"
    script:
        "../scripts/emulator_summary.py"
