# Knee exoskeleton emulator: energy stored per step in an emulated clutched spring (Heer,
# docs/rig.md §3). Recordings come from the twin (acquisition: synthetic) or any lab (files).


if SYNTHETIC:

    rule emulator_twin:
        input:
            code=code("emulator_twin.py"),
        output:
            manifest=EMULATOR_RAW / "manifest.csv",
            brace=expand(EMULATOR_RAW / "{trial}_brace.csv", trial=EMULATOR_TRIALS),
            mocap=expand(EMULATOR_RAW / "{trial}_mocap.csv", trial=EMULATOR_TRIALS),
            truth=expand(EMULATOR_RAW / "truth" / "{trial}.json", trial=EMULATOR_TRIALS),
            stamp=EMULATOR_RAW / stamp.STAMP,
        log:
            logfile("emulator_twin"),
        benchmark:
            benchfile("emulator_twin")
        resources:
            mem_mb=1000,
            runtime=30,
        params:
            protocol=lookup(dpath="emulator/protocol", within=config),
            gait=lookup(dpath="emulator/gait", within=config),
            controller=lookup(dpath="emulator/controller", within=config),
            transmission=lookup(dpath="emulator/transmission", within=config),
            effects=lookup(dpath="emulator/effects", within=config),
            sensors=lookup(dpath="emulator/sensors", within=config),
            seed=lookup(dpath="seed", within=config),
        message:
            "the emulator digital twin writes its recordings"
        script:
            "../scripts/emulator_twin.py"


# One job analyses every trial (a trial's work is smaller than a job's start-up), still one
# file per trial and output.
rule emulator_trial:
    input:
        unpack(emulator_recordings),
        manifest=EMULATOR_RAW / "manifest.csv",
        code=code("emulator_trial.py"),
    output:
        samples=emulator_trial_files("samples"),
        steps=emulator_trial_files("steps"),
        qc=emulator_trial_files("qc", "json"),
    log:
        logfile("emulator_trial"),
    benchmark:
        benchfile("emulator_trial")
    resources:
        mem_mb=1000,
        runtime=10,
    params:
        trials=EMULATOR_TRIALS,
        analysis=lookup(dpath="emulator/analysis", within=config),
        controller=lookup(dpath="emulator/controller", within=config),
        duration_s=lookup(dpath="emulator/protocol/duration_s", within=config),
        # a lab's column map; the twin writes the contract's columns (config_checks warns)
        columns={} if SYNTHETIC else lookup(dpath="emulator/columns", within=config),
        seed=lookup(dpath="seed", within=config),
    message:
        "events, steps, energy per step and sensor checks of every trial"
    script:
        "../scripts/emulator_trial.py"


rule emulator_summary:
    input:
        manifest=EMULATOR_RAW / "manifest.csv",
        steps=rules.emulator_trial.output.steps,
        qc=rules.emulator_trial.output.qc,
        code=code("emulator_summary.py"),
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
    resources:
        mem_mb=500,
        runtime=5,
    params:
        trials=EMULATOR_TRIALS,
        fault_threshold_deg=lookup(
            dpath="emulator/analysis/fault_threshold_deg", within=config
        ),
    message:
        "energy per step per condition and the session's quality checks"
    script:
        "../scripts/emulator_summary.py"


rule emulator_discrepancy:
    input:
        manifest=EMULATOR_RAW / "manifest.csv",
        samples=rules.emulator_trial.output.samples,
        qc=rules.emulator_summary.output.qc,
        reported=REFERENCE / "seed002_reported.csv",
        code=code("emulator_discrepancy.py"),
    output:
        report=report(
            EMULATOR / "discrepancy.json",
            caption="../report/emulator_discrepancy.rst",
            category="Emulator",
            subcategory="Discrepancy",
        ),
    log:
        logfile("emulator_discrepancy"),
    benchmark:
        benchfile("emulator_discrepancy")
    resources:
        mem_mb=1000,
        runtime=10,
    params:
        trials=EMULATOR_TRIALS,
        equilibrium_deg=lookup(
            dpath="emulator/controller/equilibrium_deg", within=config
        ),
        direction_blend_deg_per_s=lookup(
            dpath="emulator/controller/direction_blend_deg_per_s", within=config
        ),
        engine=lookup(dpath="discrepancy", within=config),
        seed=lookup(dpath="seed", within=config),
        transmission=lookup(dpath="emulator/transmission", within=config),
    message:
        "model discrepancy of the emulator recordings"
    script:
        "../scripts/emulator_discrepancy.py"


rule emulator_verdict:
    input:
        report=rules.emulator_discrepancy.output.report,
        code=code("emulator_verdict.py"),
    output:
        summary=report(
            EMULATOR / "summary.md",
            caption="../report/emulator_verdict.rst",
            category="Emulator",
            subcategory="Discrepancy",
        ),
        tests=report(
            EMULATOR / "residual_tests.md",
            caption="../report/emulator_verdict.rst",
            category="Emulator",
            subcategory="Discrepancy",
        ),
    log:
        logfile("emulator_verdict"),
    benchmark:
        benchfile("emulator_verdict")
    resources:
        mem_mb=500,
        runtime=5,
    params:
        source=source_spec("emulator", ["emulator.effects", "emulator.sensors"]),
        # the twin's effects as set (the headline with the twin)
        effects=lookup(dpath="emulator/effects", within=config) if SYNTHETIC else {},
    message:
        "the verdict in words: summary.md"
    script:
        "../scripts/emulator_verdict.py"


rule emulator_budget:
    input:
        samples=rules.emulator_trial.output.samples,
        reported=REFERENCE / "seed002_reported.csv",
        code=code("emulator_budget.py"),
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
    resources:
        mem_mb=500,
        runtime=5,
    params:
        budget=lookup(dpath="emulator/budget", within=config),
        transmission=lookup(dpath="emulator/transmission", within=config),
    message:
        "motor and transmission budget"
    script:
        "../scripts/emulator_budget.py"


rule emulator_figures:
    input:
        manifest=EMULATOR_RAW / "manifest.csv",
        summary=rules.emulator_summary.output.summary,
        steps=rules.emulator_summary.output.steps,
        qc=rules.emulator_summary.output.qc,
        samples=rules.emulator_trial.output.samples,
        code=code("emulator_figures.py"),
    output:
        energy_png=report(
            EMULATOR_FIGURES / "energy_per_step.png",
            caption="../report/emulator_figure_energy_per_step.rst",
            category="Emulator",
            subcategory="Figures",
        ),
        energy_pdf=EMULATOR_FIGURES / "energy_per_step.pdf",
        energy_caption=EMULATOR_FIGURES / "energy_per_step.caption.md",
        curves_png=report(
            EMULATOR_FIGURES / "angle_torque.png",
            caption="../report/emulator_figure_angle_torque.rst",
            category="Emulator",
            subcategory="Figures",
        ),
        curves_pdf=EMULATOR_FIGURES / "angle_torque.pdf",
        curves_caption=EMULATOR_FIGURES / "angle_torque.caption.md",
        encoder_png=report(
            EMULATOR_FIGURES / "encoder_vs_mocap.png",
            caption="../report/emulator_figure_encoder_vs_mocap.rst",
            category="Emulator",
            subcategory="Figures",
        ),
        encoder_pdf=EMULATOR_FIGURES / "encoder_vs_mocap.pdf",
        encoder_caption=EMULATOR_FIGURES / "encoder_vs_mocap.caption.md",
    log:
        logfile("emulator_figures"),
    benchmark:
        benchfile("emulator_figures")
    resources:
        mem_mb=1000,
        runtime=10,
    params:
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
        rules.emulator_trial.output,
        rules.emulator_summary.output,
        rules.emulator_discrepancy.output,
        rules.emulator_verdict.output,
        rules.emulator_budget.output,
        rules.emulator_figures.output,
    message:
        "emulator group up to date"
