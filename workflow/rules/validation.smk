# Validation of the discrepancy engine on many twin recordings with hidden effects drawn at
# random (not part of the default target): snakemake validate_discrepancy --cores 2
VALIDATION = RESULTS / "validation"
VALIDATION_BATCHES = range(int(config["validation"]["batches"]))


rule validate_discrepancy_batch:
    input:
        cycle=REFERENCE / "phantom_knee_flexion_mean_cycle.csv",
        code=code("validate_discrepancy_batch.py"),
    output:
        VALIDATION / "cases" / "batch{batch}.csv",
    log:
        logfile("validate_discrepancy_batch", "batch{batch}"),
    benchmark:
        benchfile("validate_discrepancy_batch", "batch{batch}")
    resources:
        mem_mb=1500,
        runtime=60,
    params:
        phantom=lookup(dpath="phantom", within=config),
        engine=lookup(dpath="discrepancy", within=config),
        validation=lookup(dpath="validation", within=config),
        seed=lookup(dpath="seed", within=config),
    script:
        "../scripts/validate_discrepancy_batch.py"


rule validate_discrepancy:
    input:
        batches=expand(
            rules.validate_discrepancy_batch.output, batch=VALIDATION_BATCHES
        ),
        code=code("validate_discrepancy.py"),
        # the emulator's table beside the phantom's (validation_emulator.smk)
        emulator=rules.validate_emulator.output.summary,
    output:
        rows=VALIDATION / "discrepancy.csv",
        summary=VALIDATION / "summary.csv",
        png=RESULTS / "figures" / "validation" / "discrepancy.png",
        pdf=RESULTS / "figures" / "validation" / "discrepancy.pdf",
    log:
        logfile("validate_discrepancy"),
    benchmark:
        benchfile("validate_discrepancy")
    resources:
        mem_mb=1000,
        runtime=5,
    script:
        "../scripts/validate_discrepancy.py"
