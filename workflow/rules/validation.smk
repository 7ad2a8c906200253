# Validation of the discrepancy engine on many twin recordings with hidden effects drawn at
# random (not part of the default target): snakemake validate_discrepancy --cores 2
VALIDATION = RESULTS / "validation"
VALIDATION_BATCHES = range(int(config["validation"]["batches"]))


rule validate_discrepancy_batch:
    input:
        cycle=REFERENCE / "phantom_knee_flexion_mean_cycle.csv",
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
        code=code("validate_discrepancy_batch.py"),
        phantom=setting("phantom"),
        engine=setting("discrepancy"),
        validation=setting("validation"),
        seed=setting("seed"),
    message:
        "validation batch {wildcards.batch}: twin recordings with hidden effects"
    script:
        "../scripts/validate_discrepancy_batch.py"


OPENWORLD_BATCHES = range(int(config["validation"]["openworld"]["batches"]))


rule validate_openworld_batch:
    input:
        cycle=REFERENCE / "phantom_knee_flexion_mean_cycle.csv",
    output:
        VALIDATION / "openworld" / "cases" / "batch{batch}.csv",
    log:
        logfile("validate_openworld_batch", "batch{batch}"),
    benchmark:
        benchfile("validate_openworld_batch", "batch{batch}")
    resources:
        mem_mb=1500,
        runtime=60,
    params:
        code=code("validate_openworld_batch.py"),
        phantom=setting("phantom"),
        engine=setting("discrepancy"),
        validation=setting("validation"),
        seed=setting("seed"),
    message:
        "validation batch {wildcards.batch}: independent recordings, faults outside the registry and combined effects"
    script:
        "../scripts/validate_openworld_batch.py"


rule validate_openworld:
    input:
        batches=expand(rules.validate_openworld_batch.output, batch=OPENWORLD_BATCHES),
    output:
        rows=VALIDATION / "openworld" / "cases.csv",
        summary=VALIDATION / "openworld" / "summary.csv",
    log:
        logfile("validate_openworld"),
    benchmark:
        benchfile("validate_openworld")
    resources:
        mem_mb=1000,
        runtime=5,
    params:
        code=code("validate_openworld.py"),
    message:
        "open-world and combined arms summarised"
    script:
        "../scripts/validate_openworld.py"


rule validate_discrepancy:
    input:
        batches=expand(
            rules.validate_discrepancy_batch.output, batch=VALIDATION_BATCHES
        ),
        # the emulator's and the open-world arms' tables beside the phantom's
        emulator=rules.validate_emulator.output.summary,
        openworld=rules.validate_openworld.output.summary,
        openworld_rows=rules.validate_openworld.output.rows,
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
    params:
        code=code("validate_discrepancy.py"),
    message:
        "validation of the discrepancy engine summarised"
    script:
        "../scripts/validate_discrepancy.py"
