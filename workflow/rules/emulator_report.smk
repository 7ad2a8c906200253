# Emulator stage 3, report and figures: Heer's motor and transmission budget, Heer's numbers beside
# the project's, and the figures with their captions.


rule emulator_budget:
    input:
        samples=EMULATOR_CHAIN["samples"],
        reported=REFERENCE / "seed002_reported.csv",
    output:
        in_report(
            EMULATOR / "budget.json",
            "emulator",
            "emulator_budget",
            "Motor and transmission",
        ),
    log:
        logfile("emulator_budget"),
    benchmark:
        benchfile("emulator_budget")
    resources:
        mem_mb=500,
        runtime=5,
    params:
        code=code("emulator_budget.py"),
        budget=setting("emulator/budget"),
        transmission=setting("emulator/transmission"),
    message:
        "motor and transmission budget"
    script:
        "../scripts/emulator_budget.py"


rule emulator_compare:
    input:
        reported=REFERENCE / "seed002_reported.csv",
        summary=rules.emulator_summary.output.summary,
        steps=rules.emulator_summary.output.steps,
        qc=rules.emulator_summary.output.qc,
        samples=EMULATOR_CHAIN["samples"],
        budget=rules.emulator_budget.output[0],
    output:
        in_report(
            EMULATOR / "heer_comparison.csv",
            "emulator",
            "emulator_comparison",
            "Tables",
        ),
    log:
        logfile("emulator_compare"),
    benchmark:
        benchfile("emulator_compare")
    resources:
        mem_mb=1000,
        runtime=5,
    params:
        code=code("emulator_compare.py"),
        trials=EMULATOR_TRIALS,
        acquisition=setting("acquisition"),
        budget=setting("emulator/budget"),
        # the twin's effects as set (a count drop planted makes its energy a setting)
        effects=setting("emulator/effects") if SYNTHETIC else {},
        equilibrium_deg=setting("emulator/controller/equilibrium_deg"),
        comparison=setting("emulator/comparison"),
        torque_filter_Hz=setting("emulator/controller/torque_filter_Hz"),
        velocity_cutoff_Hz=setting("emulator/controller/velocity_cutoff_Hz"),
        match_window_s=setting("emulator/analysis/match_window_s"),
    message:
        "Heer's numbers beside the project's: heer_comparison.csv"
    script:
        "../scripts/emulator_compare.py"


rule emulator_figures:
    input:
        manifest=EMULATOR_RAW / "manifest.csv",
        summary=rules.emulator_summary.output.summary,
        steps=rules.emulator_summary.output.steps,
        qc=rules.emulator_summary.output.qc,
        samples=EMULATOR_CHAIN["samples"],
        reported=REFERENCE / "seed002_reported.csv",
    output:
        **figure_outputs("emulator", EMULATOR_FIGURES, EMULATOR_FIGURE_NAMES),
    log:
        logfile("emulator_figures"),
    benchmark:
        benchfile("emulator_figures")
    priority: 1
    resources:
        mem_mb=1000,
        runtime=10,
    params:
        code=code("emulator_figures.py"),
        figures=EMULATOR_FIGURE_NAMES,
        trials=EMULATOR_TRIALS,
    message:
        "emulator figures with their captions"
    script:
        "../scripts/emulator_figures.py"


# The per-trial files are targets too: a failed run removes them, and the next run then rebuilds
# them and everything after them (Snakemake leaves a missing intermediate alone while what
# follows it is up to date).
rule emulator:
    input:
        EMULATOR_CHAIN.values(),
        rules.emulator_summary.output,
        rules.emulator_discrepancy.output,
        rules.emulator_verdict.output,
        rules.emulator_budget.output,
        rules.emulator_compare.output,
        rules.emulator_figures.output,
    message:
        "emulator group up to date"
