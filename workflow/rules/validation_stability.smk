# Validation of the parameter stability on the twins (not in the default target): recordings
# with a rig constant changed in one trial, or in none, analysed with the model a right
# selection leaves, per group. snakemake validate_stability --cores 2
STABILITY = RESULTS / "validation" / "stability"
STABILITY_BATCHES = range(int(config["validation"]["stability"]["batches"]))


rule validate_stability_phantom_batch:
    input:
        cycle=REFERENCE / "phantom_knee_flexion_mean_cycle.csv",
        code=code("validate_stability_phantom_batch.py"),
    output:
        STABILITY / "cases" / "phantom_batch{batch}.csv",
    log:
        logfile("validate_stability_phantom_batch", "batch{batch}"),
    benchmark:
        benchfile("validate_stability_phantom_batch", "batch{batch}")
    resources:
        mem_mb=1500,
        runtime=120,
    params:
        group=lookup(dpath="phantom", within=config),
        engine=lookup(dpath="discrepancy", within=config),
        stability=lookup(dpath="validation/stability", within=config),
        seed=lookup(dpath="seed", within=config),
    message:
        "stability validation, phantom batch {wildcards.batch}: trials with a constant changed in one or none"
    script:
        "../scripts/validate_stability_phantom_batch.py"


rule validate_stability_phantom:
    input:
        batches=expand(
            rules.validate_stability_phantom_batch.output, batch=STABILITY_BATCHES
        ),
        code=code("validate_stability_phantom.py"),
    output:
        rows=STABILITY / "phantom_cases.csv",
        summary=STABILITY / "phantom_summary.csv",
    log:
        logfile("validate_stability_phantom"),
    benchmark:
        benchfile("validate_stability_phantom")
    resources:
        mem_mb=1000,
        runtime=5,
    message:
        "parameter stability on the phantom twin: false alarms and detection summarised"
    script:
        "../scripts/validate_stability_phantom.py"


rule validate_stability_emulator_batch:
    input:
        code=code("validate_stability_emulator_batch.py"),
    output:
        STABILITY / "cases" / "emulator_batch{batch}.csv",
    log:
        logfile("validate_stability_emulator_batch", "batch{batch}"),
    benchmark:
        benchfile("validate_stability_emulator_batch", "batch{batch}")
    resources:
        mem_mb=1500,
        runtime=120,
    params:
        group=lookup(dpath="emulator", within=config),
        engine=lookup(dpath="discrepancy", within=config),
        stability=lookup(dpath="validation/stability", within=config),
        seed=lookup(dpath="seed", within=config),
    message:
        "stability validation, emulator batch {wildcards.batch}: conditions with a constant changed in one or none"
    script:
        "../scripts/validate_stability_emulator_batch.py"


rule validate_stability_emulator:
    input:
        batches=expand(
            rules.validate_stability_emulator_batch.output, batch=STABILITY_BATCHES
        ),
        code=code("validate_stability_emulator.py"),
    output:
        rows=STABILITY / "emulator_cases.csv",
        summary=STABILITY / "emulator_summary.csv",
    log:
        logfile("validate_stability_emulator"),
    benchmark:
        benchfile("validate_stability_emulator")
    resources:
        mem_mb=1000,
        runtime=5,
    message:
        "parameter stability on the emulator twin: false alarms and detection summarised"
    script:
        "../scripts/validate_stability_emulator.py"


rule validate_stability:
    input:
        rules.validate_stability_phantom.output,
        rules.validate_stability_emulator.output,
    message:
        "the parameter stability validated on both twins"
