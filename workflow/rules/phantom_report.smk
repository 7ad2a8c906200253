# Phantom stage 3, report and figures: curves, statistics, summary, the reproduction table and
# every figure with its caption.


rule phantom_curves:
    input:
        **PHANTOM_KINETICS,
        metrics=rules.phantom_metrics.output.metrics,
    output:
        in_report(PHANTOM / "curves.parquet", "phantom", "phantom_curves", "Tables"),
    log:
        logfile("phantom_curves"),
    benchmark:
        benchfile("phantom_curves")
    priority: 2
    resources:
        mem_mb=1000,
        runtime=10,
    params:
        code=code("phantom_curves.py"),
        trials=PHANTOM_TRIALS,
        points=400,
    message:
        "mean and SD curves over the gait cycle per spring"
    script:
        "../scripts/phantom_curves.py"


rule phantom_statistics:
    input:
        metrics=rules.phantom_metrics.output.metrics,
    output:
        kruskal=in_report(
            PHANTOM / "stats" / "kruskal.csv", "phantom", "phantom_tables", "Tables"
        ),
        notation=in_report(
            PHANTOM / "stats" / "notation.csv", "phantom", "phantom_tables", "Tables"
        ),
        dunn=[
            in_report(
                PHANTOM / "stats" / "dunn" / f"{metric}.csv",
                "phantom",
                "phantom_tables",
                "Dunn tests",
                metric=metric,
            )
            for metric in PHANTOM_METRICS
        ],
    log:
        logfile("phantom_statistics"),
    benchmark:
        benchfile("phantom_statistics")
    priority: 2
    resources:
        mem_mb=1000,
        runtime=10,
    params:
        code=code("phantom_statistics.py"),
        statistics=setting("phantom/statistics"),
        seed=setting("seed"),
    message:
        "Kruskal-Wallis and Dunn tests across springs, with effect sizes"
    script:
        "../scripts/phantom_statistics.py"


# The design run, analysed as run: the same trajectories at every spring (paired), one trial per
# spring unless the twin repeats them (docs/phantom.md).
rule phantom_paired:
    input:
        metrics=rules.phantom_metrics.output.metrics,
    output:
        paired=in_report(
            PHANTOM / "stats" / "paired.csv", "phantom", "phantom_tables", "Tables"
        ),
        wilcoxon=in_report(
            PHANTOM / "stats" / "wilcoxon.csv", "phantom", "phantom_tables", "Tables"
        ),
    log:
        logfile("phantom_paired"),
    benchmark:
        benchfile("phantom_paired")
    priority: 2
    resources:
        mem_mb=1000,
        runtime=10,
    params:
        code=code("phantom_paired.py"),
        alpha=setting("phantom/statistics/alpha"),
        bound_share=setting("phantom/statistics/variance_bound_share"),
    message:
        "Friedman, Wilcoxon and mixed models of the paired design"
    script:
        "../scripts/phantom_paired.py"


rule phantom_summary:
    input:
        metrics=rules.phantom_metrics.output.metrics,
    output:
        in_report(PHANTOM / "summary.csv", "phantom", "phantom_tables", "Tables"),
    log:
        logfile("phantom_summary"),
    benchmark:
        benchfile("phantom_summary")
    priority: 1
    resources:
        mem_mb=1000,
        runtime=5,
    params:
        code=code("phantom_summary.py"),
        slope_validity=setting("phantom/statistics/slope_validity"),
    message:
        "median, quartiles, mean, SD and n per spring and metric"
    script:
        "../scripts/phantom_summary.py"


rule phantom_figures:
    input:
        curves=rules.phantom_curves.output[0],
        summary=rules.phantom_summary.output[0],
        notation=rules.phantom_statistics.output.notation,
        outliers=rules.phantom_metrics.output.outliers,
    output:
        **figure_outputs("phantom", PHANTOM_FIGURES, PHANTOM_PAPER_FIGURES),
    log:
        logfile("phantom_figures"),
    benchmark:
        benchfile("phantom_figures")
    priority: 1
    resources:
        mem_mb=1000,
        runtime=10,
    params:
        code=code("phantom_figures.py"),
        figures=PHANTOM_PAPER_FIGURES,
        protocol=setting("phantom/protocol"),
        alpha=setting("phantom/statistics/alpha"),
    message:
        "figures 5-11 of W.S.B. et al. with their captions"
    script:
        "../scripts/phantom_figures.py"


rule phantom_discrepancy_figure:
    input:
        # W.S.B. et al.'s medians beside the recordings, when the run compares with them
        **(
            {
                "reported": rules.phantom_discrepancy_reported.output[0],
                "paper": REFERENCE / "seed000_reported.csv",
            }
            if PHANTOM_SEED000
            else {}
        ),
        predictions=rules.phantom_discrepancy.output.predictions,
        recordings=rules.phantom_discrepancy.output.recordings,
        # panel (a): the peak stance moment as summary.csv gives it (figure 6's strides)
        summary=rules.phantom_summary.output[0],
    output:
        **figure_outputs(
            "phantom", PHANTOM_FIGURES, ["discrepancy"], "Model discrepancy"
        ),
    log:
        logfile("phantom_discrepancy_figure"),
    benchmark:
        benchfile("phantom_discrepancy_figure")
    resources:
        mem_mb=1000,
        runtime=5,
    params:
        code=code("phantom_discrepancy_figure.py"),
        figures=["discrepancy"],
        protocol={
            key: setting(f"phantom/protocol/{key}")
            for key in ("work_window_s", "stride_time_s")
        },
    message:
        "figure of measured vs rigid theory vs extended model"
    script:
        "../scripts/phantom_discrepancy_figure.py"


rule phantom_terms_figure:
    input:
        terms=rules.phantom_discrepancy.output.terms,
        predictions=rules.phantom_discrepancy.output.predictions,
        recordings=rules.phantom_discrepancy.output.recordings,
    output:
        **figure_outputs(
            "phantom", PHANTOM_FIGURES, ["discrepancy_terms"], "Model discrepancy"
        ),
    log:
        logfile("phantom_terms_figure"),
    benchmark:
        benchfile("phantom_terms_figure")
    resources:
        mem_mb=1000,
        runtime=5,
    params:
        code=code("phantom_terms_figure.py"),
        figures=["discrepancy_terms"],
    message:
        "figure of what the extended model leaves and the terms discovered"
    script:
        "../scripts/phantom_terms_figure.py"


rule phantom_qc_figure:
    input:
        manifest=PHANTOM_RAW / "manifest.csv",
        qc=PHANTOM_CHAIN["qc"],
        strides=PHANTOM_CHAIN["strides"],
    output:
        **figure_outputs("phantom", PHANTOM_FIGURES, ["qc"], "Quality control"),
    log:
        logfile("phantom_qc_figure"),
    benchmark:
        benchfile("phantom_qc_figure")
    resources:
        mem_mb=1000,
        runtime=5,
    params:
        code=code("phantom_qc_figure.py"),
        figures=["qc"],
        trials=PHANTOM_TRIALS,
        max_gap_frames=setting("phantom/chain/max_gap_frames"),
        # the lab's own channel labels (contract name -> label), shown instead of the contract's
        # (the twin writes the contract's)
        labels={} if SYNTHETIC else setting("phantom/rig/labels"),
    message:
        "figure of the glitches repaired or left as gaps and the strides kept"
    script:
        "../scripts/phantom_qc_figure.py"
