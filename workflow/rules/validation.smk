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
        logfile("validate_discrepancy_batch_{batch}"),
    benchmark:
        benchfile("validate_discrepancy_batch_{batch}")
    script:
        "../scripts/validate_discrepancy_batch.py"


rule validate_discrepancy:
    input:
        expand(rules.validate_discrepancy_batch.output, batch=VALIDATION_BATCHES),
    output:
        rows=VALIDATION / "discrepancy.csv",
        summary=VALIDATION / "summary.csv",
        png=RESULTS / "figures" / "validation" / "discrepancy.png",
        pdf=RESULTS / "figures" / "validation" / "discrepancy.pdf",
    log:
        logfile("validate_discrepancy"),
    benchmark:
        benchfile("validate_discrepancy")
    script:
        "../scripts/validate_discrepancy.py"
