# Knee exoskeleton emulator: energy stored per step in an emulated clutched spring (seed 002,
# RIG.md §3). Recordings come from the twin (acquisition: synthetic) or any lab (files).


if SYNTHETIC:

    rule emulator_twin:
        output:
            manifest=EMULATOR_RAW / "manifest.csv",
            brace=expand(EMULATOR_RAW / "{trial}_brace.csv", trial=EMULATOR_TRIALS),
            mocap=expand(EMULATOR_RAW / "{trial}_mocap.csv", trial=EMULATOR_TRIALS),
            truth=expand(EMULATOR_RAW / "truth" / "{trial}.json", trial=EMULATOR_TRIALS),
            stamp=EMULATOR_RAW / emulator_twin.STAMP,
        log:
            logfile("emulator_twin"),
        benchmark:
            benchfile("emulator_twin")
        script:
            "../scripts/emulator_twin.py"


rule emulator_trial:
    input:
        unpack(emulator_recording),
        manifest=EMULATOR_RAW / "manifest.csv",
    output:
        samples=EMULATOR / "samples" / "{trial}.parquet",
        steps=EMULATOR / "steps" / "{trial}.parquet",
        qc=EMULATOR / "qc" / "{trial}.json",
    log:
        logfile("emulator_trial_{trial}"),
    benchmark:
        benchfile("emulator_trial_{trial}")
    params:
        truth=lambda wc: (
            str(EMULATOR_RAW / "truth" / f"{wc.trial}.json") if SYNTHETIC else None
        ),
    script:
        "../scripts/emulator_trial.py"


rule emulator_summary:
    input:
        manifest=EMULATOR_RAW / "manifest.csv",
        steps=expand(rules.emulator_trial.output.steps, trial=EMULATOR_TRIALS),
        qc=expand(rules.emulator_trial.output.qc, trial=EMULATOR_TRIALS),
    output:
        steps=report(
            EMULATOR / "energy_per_step.parquet",
            caption="../report/emulator_tables.rst",
            category="Emulator",
            subcategory="Tables",
        ),
        summary=report(
            EMULATOR / "summary.csv",
            caption="../report/emulator_tables.rst",
            category="Emulator",
            subcategory="Tables",
        ),
        qc=report(
            EMULATOR / "qc.json",
            caption="../report/emulator_tables.rst",
            category="Emulator",
            subcategory="Tables",
        ),
    log:
        logfile("emulator_summary"),
    benchmark:
        benchfile("emulator_summary")
    params:
        trials=EMULATOR_TRIALS,
    script:
        "../scripts/emulator_summary.py"


rule emulator_discrepancy:
    input:
        manifest=EMULATOR_RAW / "manifest.csv",
        samples=expand(rules.emulator_trial.output.samples, trial=EMULATOR_TRIALS),
        qc=rules.emulator_summary.output.qc,
        reported=REFERENCE / "seed002_reported.csv",
    output:
        report(
            EMULATOR / "discrepancy.json",
            caption="../report/emulator_discrepancy.rst",
            category="Emulator",
            subcategory="Discrepancy",
        ),
    log:
        logfile("emulator_discrepancy"),
    benchmark:
        benchfile("emulator_discrepancy")
    params:
        trials=EMULATOR_TRIALS,
    script:
        "../scripts/emulator_discrepancy.py"


rule emulator_budget:
    input:
        samples=expand(rules.emulator_trial.output.samples, trial=EMULATOR_TRIALS),
        reported=REFERENCE / "seed002_reported.csv",
    output:
        report(
            EMULATOR / "budget.json",
            caption="../report/emulator_budget.rst",
            category="Emulator",
            subcategory="Motor and transmission",
        ),
    log:
        logfile("emulator_budget"),
    benchmark:
        benchfile("emulator_budget")
    script:
        "../scripts/emulator_budget.py"


rule emulator_figures:
    input:
        manifest=EMULATOR_RAW / "manifest.csv",
        summary=rules.emulator_summary.output.summary,
        steps=rules.emulator_summary.output.steps,
        qc=rules.emulator_summary.output.qc,
        samples=expand(rules.emulator_trial.output.samples, trial=EMULATOR_TRIALS),
    output:
        energy_png=report(
            EMULATOR_FIGURES / "energy_per_step.png",
            caption="../report/emulator_figures.rst",
            category="Emulator",
            subcategory="Figures",
        ),
        energy_pdf=EMULATOR_FIGURES / "energy_per_step.pdf",
        curves_png=report(
            EMULATOR_FIGURES / "angle_torque.png",
            caption="../report/emulator_figures.rst",
            category="Emulator",
            subcategory="Figures",
        ),
        curves_pdf=EMULATOR_FIGURES / "angle_torque.pdf",
        encoder_png=report(
            EMULATOR_FIGURES / "encoder_vs_mocap.png",
            caption="../report/emulator_figures.rst",
            category="Emulator",
            subcategory="Figures",
        ),
        encoder_pdf=EMULATOR_FIGURES / "encoder_vs_mocap.pdf",
        activity_png=report(
            EMULATOR_FIGURES / "activity_vs_table61.png",
            caption="../report/emulator_figures.rst",
            category="Emulator",
            subcategory="Figures",
        ),
        activity_pdf=EMULATOR_FIGURES / "activity_vs_table61.pdf",
    log:
        logfile("emulator_figures"),
    benchmark:
        benchfile("emulator_figures")
    params:
        trials=EMULATOR_TRIALS,
    script:
        "../scripts/emulator_figures.py"


rule emulator:
    input:
        rules.emulator_summary.output,
        rules.emulator_discrepancy.output,
        rules.emulator_budget.output,
        rules.emulator_figures.output,
