# Validation of the parameter stability on both twins (not in the default target): recordings
# with a rig constant changed in one trial, or in none, analysed with the model a right
# selection leaves. snakemake validate_stability --cores 2
STABILITY = RESULTS / "validation" / "stability"
STABILITY_BATCHES = range(int(config["validation"]["stability"]["batches"]))


rule validate_stability_batch:
    input:
        cycle=REFERENCE / "phantom_knee_flexion_mean_cycle.csv",
    output:
        STABILITY / "cases" / "{group}_batch{batch}.csv",
    log:
        logfile("validate_stability_batch", "{group}_batch{batch}"),
    benchmark:
        benchfile("validate_stability_batch", "{group}_batch{batch}")
    wildcard_constraints:
        group="phantom|emulator",
    resources:
        mem_mb=1500,
        runtime=120,
    params:
        code=code("validate_stability_batch.py"),
        phantom=setting("phantom"),
        emulator=setting("emulator"),
        engine=setting("discrepancy"),
        stability=setting("validation/stability"),
        seed=setting("seed"),
    message:
        "stability validation, {wildcards.group} batch {wildcards.batch}: trials with a constant changed in one or none"
    script:
        "../scripts/validate_stability_batch.py"


rule validate_stability:
    input:
        batches=expand(
            rules.validate_stability_batch.output,
            group=["phantom", "emulator"],
            batch=STABILITY_BATCHES,
        ),
    output:
        rows=STABILITY / "cases.csv",
        summary=STABILITY / "summary.csv",
    log:
        logfile("validate_stability"),
    benchmark:
        benchfile("validate_stability")
    resources:
        mem_mb=1000,
        runtime=5,
    params:
        code=code("validate_stability.py"),
    message:
        "parameter stability: false alarms and detection summarised"
    script:
        "../scripts/validate_stability.py"
