# Phantom targets: the acquired files, W.S.B. et al.'s own steps and the whole group.


# Every acquired file of the run (a target of its own).
rule phantom_acquire:
    input:
        PHANTOM_RAW / "manifest.csv",
        [PHANTOM_CHAIN[kind] for kind in ("markers", "analog", "events")],
    message:
        "phantom recordings acquired"


# W.S.B. et al.'s own steps: the twin's calibration to their medians and the reproduction
# table (with lab files only when phantom.compare_seed000 asks for them).
rule phantom_seed000:
    input:
        rules.phantom_calibrate.output,
        rules.phantom_compare.output,
        rules.phantom_discrepancy_reported.output,
    message:
        "W.S.B. et al.'s own steps up to date"


# Every per-trial file is a target: a failed run removes a stage's files, and the next run then
# rebuilds them and everything after them (Snakemake leaves a missing intermediate alone while
# what follows it is up to date).
rule phantom:
    input:
        rules.phantom_reference_cycle.output,
        rules.phantom_seed000.input if PHANTOM_SEED000 else [],
        rules.phantom_acquire.input,
        PHANTOM_CHAIN.values(),
        rules.phantom_metrics.output,
        rules.phantom_statistics.output,
        rules.phantom_paired.output,
        rules.phantom_summary.output,
        rules.phantom_figures.output,
        rules.phantom_qc_figure.output,
        rules.phantom_discrepancy.output,
        rules.phantom_discrepancy_figure.output,
        rules.phantom_terms_figure.output,
        rules.phantom_verdict.output,
    message:
        "phantom group up to date"
