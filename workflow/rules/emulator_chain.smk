# Emulator stage 1, recordings and chain: the twin's recordings (synthetic), events, steps and energy
# per step of every trial, and the per-condition summary with the session's quality checks.

if SYNTHETIC:

    rule emulator_twin:
        output:
            manifest=EMULATOR_RAW / "manifest.csv",
            brace=expand(EMULATOR_RAW / "{trial}_brace.csv", trial=EMULATOR_ALL_TRIALS),
            mocap=expand(EMULATOR_RAW / "{trial}_mocap.csv", trial=EMULATOR_ALL_TRIALS),
            truth=expand(
                EMULATOR_RAW / "truth" / "{trial}.json", trial=EMULATOR_ALL_TRIALS
            ),
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
            code=code("emulator_twin.py"),
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


# One job per trial (a cluster runs the trials in parallel, a rerun redoes only the trials whose
# inputs changed, a bad trial fails its own job): events, steps, energy and the sensor checks.
rule emulator_trial:
    input:
        unpack(emulator_recording),
        manifest=EMULATOR_RAW / "manifest.csv",
    output:
        samples=EMULATOR / "samples" / "{trial}.parquet",
        steps=EMULATOR / "steps" / "{trial}.parquet",
        qc=EMULATOR / "qc" / "{trial}.json",
    log:
        logfile("emulator_trial", "{trial}"),
    benchmark:
        benchfile("emulator_trial", "{trial}")
    wildcard_constraints:
        trial=EMULATOR_TRIAL_PATTERN,
    priority: 3
    resources:
        mem_mb=1000,
        runtime=10,
    params:
        code=code("emulator_trial.py"),
        analysis=setting("emulator/analysis"),
        controller=setting("emulator/controller"),
        transmission=setting("emulator/transmission"),
        duration_s=setting("emulator/protocol/duration_s"),
        # a lab's column map; the twin writes the contract's columns (config_checks warns)
        columns={} if SYNTHETIC else setting("emulator/columns"),
        mat_channels={} if SYNTHETIC else setting("emulator/mat_channels"),
        seed=setting("seed"),
    message:
        "events, steps, energy per step and sensor checks of emulator trial {wildcards.trial}"
    script:
        "../scripts/emulator_trial.py"


rule emulator_summary:
    input:
        manifest=EMULATOR_RAW / "manifest.csv",
        steps=EMULATOR_CHAIN["steps"],
        qc=EMULATOR_CHAIN["qc"],
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
        code=code("emulator_summary.py"),
        trials=EMULATOR_TRIALS,
        fault_threshold_deg=setting("emulator/analysis/fault_threshold_deg"),
        calibration=setting("emulator/transmission_calibrated"),
    message:
        "energy per step per condition and the session's quality checks"
    script:
        "../scripts/emulator_summary.py"
