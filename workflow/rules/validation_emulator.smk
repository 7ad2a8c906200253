# Validation of the discrepancy engine on emulator recordings with hidden effects drawn at
# random from the emulator registry (not in the default target): snakemake validate_emulator
EMULATOR_VALIDATION = RESULTS / "validation" / "emulator"
EMULATOR_VALIDATION_BATCHES = range(int(config["emulator"]["validation"]["batches"]))


rule validate_emulator_batch:
    input:
        code=code("validate_emulator_batch.py"),
    output:
        EMULATOR_VALIDATION / "cases" / "batch{batch}.csv",
    log:
        logfile("validate_emulator_batch", "batch{batch}"),
    benchmark:
        benchfile("validate_emulator_batch", "batch{batch}")
    resources:
        mem_mb=1500,
        runtime=60,
    params:
        emulator=lookup(dpath="emulator", within=config),
        engine=lookup(dpath="discrepancy", within=config),
        seed=lookup(dpath="seed", within=config),
    message:
        "emulator validation batch {wildcards.batch}"
    script:
        "../scripts/validate_emulator_batch.py"


rule validate_emulator:
    input:
        batches=expand(
            rules.validate_emulator_batch.output, batch=EMULATOR_VALIDATION_BATCHES
        ),
        code=code("validate_emulator.py"),
    output:
        rows=EMULATOR_VALIDATION / "discrepancy.csv",
        summary=EMULATOR_VALIDATION / "summary.csv",
        png=RESULTS / "figures" / "validation" / "emulator.png",
        pdf=RESULTS / "figures" / "validation" / "emulator.pdf",
    log:
        logfile("validate_emulator"),
    benchmark:
        benchfile("validate_emulator")
    resources:
        mem_mb=1000,
        runtime=5,
    message:
        "emulator validation summarised"
    script:
        "../scripts/validate_emulator.py"
