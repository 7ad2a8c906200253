# Phantom stage 4, W.S.B. et al.'s own steps checked: their numbers against the reproduced ones,
# their significance statements against the reproduced tests and, with the twin, its prediction
# of each number against the chain's measurement of its recordings (the method checking itself,
# with the twin's true per-stride metrics to say which side is wrong).

if SYNTHETIC:

    rule phantom_truth_metrics:
        input:
            truth=phantom_trial_files_in(PHANTOM_RAW / "truth"),
            manifest=PHANTOM_RAW / "manifest.csv",
        output:
            PHANTOM / "method" / "truth_metrics.parquet",
        log:
            logfile("phantom_truth_metrics"),
        benchmark:
            benchfile("phantom_truth_metrics")
        resources:
            mem_mb=1000,
            runtime=5,
        params:
            code=code("phantom_truth_metrics.py"),
            trials=PHANTOM_TRIALS,
            protocol=setting("phantom/protocol"),
        message:
            "the twin's true per-stride metrics (for the method check)"
        script:
            "../scripts/phantom_truth_metrics.py"


rule phantom_compare:
    input:
        **({"truth": rules.phantom_truth_metrics.output[0]} if SYNTHETIC else {}),
        metrics=rules.phantom_metrics.output.metrics,
        reported=REFERENCE / "seed000_reported.csv",
        significance=REFERENCE / "seed000_significance.csv",
        kruskal=rules.phantom_statistics.output.kruskal,
        dunn=rules.phantom_statistics.output.dunn,
        paired=rules.phantom_paired.output.paired,
        wilcoxon=rules.phantom_paired.output.wilcoxon,
        residuals=rules.phantom_calibrate.output.residuals,
        strides=rules.phantom_calibrate.output.strides,
    output:
        **(
            {
                "method": in_report(
                    PHANTOM / "method_check.csv", "phantom", "phantom_tables", "Tables"
                )
            }
            if SYNTHETIC
            else {}
        ),
        table=in_report(
            PHANTOM / "paper_comparison.csv", "phantom", "phantom_tables", "Tables"
        ),
        significance=in_report(
            PHANTOM / "significance_comparison.csv",
            "phantom",
            "phantom_tables",
            "Tables",
        ),
    log:
        logfile("phantom_compare"),
    benchmark:
        benchfile("phantom_compare")
    resources:
        mem_mb=1000,
        runtime=5,
    params:
        code=code("phantom_compare.py"),
        comparison=setting("phantom/comparison"),
        alpha=setting("phantom/statistics/alpha"),
        equivalence=setting("phantom/statistics/equivalence"),
        power=setting("phantom/statistics/power"),
        seed=setting("seed"),
    message:
        "reproduced numbers and significance against W.S.B. et al.'s; twin against chain"
    script:
        "../scripts/phantom_compare.py"
