# Validation of the discrepancy engine on emulator recordings with hidden effects drawn at
# random from the emulator registry (not in the default target): snakemake validate_emulator
EMULATOR_VALIDATION = RESULTS / "validation" / "emulator"
EMULATOR_VALIDATION_BATCHES = range(int(config["emulator"]["validation"]["batches"]))


rule validate_emulator_batch:
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
        code=code("validate_emulator_batch.py"),
        emulator=setting("emulator"),
        engine=setting("discrepancy"),
        seed=setting("seed"),
    message:
        "emulator validation batch {wildcards.batch}"
    script:
        "../scripts/validate_emulator_batch.py"


rule validate_emulator:
    input:
        batches=expand(
            rules.validate_emulator_batch.output, batch=EMULATOR_VALIDATION_BATCHES
        ),
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
    params:
        code=code("validate_emulator.py"),
    message:
        "emulator validation summarised"
    script:
        "../scripts/validate_emulator.py"


# The open-world and combined arms on recordings of the independent generator (not in the default
# target): snakemake validate_emulator_openworld --cores 2
EMULATOR_OPENWORLD = EMULATOR_VALIDATION / "openworld"
EMULATOR_OPENWORLD_BATCHES = range(
    int(config["emulator"]["validation"]["openworld"]["batches"])
)


rule validate_emulator_openworld_batch:
    output:
        EMULATOR_OPENWORLD / "cases" / "batch{batch}.csv",
    log:
        logfile("validate_emulator_openworld_batch", "batch{batch}"),
    benchmark:
        benchfile("validate_emulator_openworld_batch", "batch{batch}")
    resources:
        mem_mb=1500,
        runtime=120,
    params:
        code=code("validate_emulator_openworld_batch.py"),
        emulator=setting("emulator"),
        engine=setting("discrepancy"),
        seed=setting("seed"),
    message:
        "emulator open-world batch {wildcards.batch}: independent recordings, faults outside the registry and combined effects"
    script:
        "../scripts/validate_emulator_openworld_batch.py"


rule validate_emulator_openworld:
    input:
        batches=expand(
            rules.validate_emulator_openworld_batch.output,
            batch=EMULATOR_OPENWORLD_BATCHES,
        ),
    output:
        rows=EMULATOR_OPENWORLD / "cases.csv",
        summary=EMULATOR_OPENWORLD / "summary.csv",
        readings=EMULATOR_OPENWORLD / "by_reading.csv",
        png=RESULTS / "figures" / "validation" / "emulator_openworld.png",
        pdf=RESULTS / "figures" / "validation" / "emulator_openworld.pdf",
    log:
        logfile("validate_emulator_openworld"),
    benchmark:
        benchfile("validate_emulator_openworld")
    resources:
        mem_mb=1000,
        runtime=5,
    params:
        code=code("validate_emulator_openworld.py"),
    message:
        "emulator open-world and combined arms summarised"
    script:
        "../scripts/validate_emulator_openworld.py"
