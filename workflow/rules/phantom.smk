# Phantom + passive knee exoskeleton (W.S.B. et al.): calibration → digital twin (synthetic) or lab
# files → acquisition.
# Scheduling: the phantom chain (calibrate → twin → acquire → filter → angles → strides →
# dynamics → kinetics, then the engine, statistics and figures) is the workflow's longest path.
# Its rules carry `priority`: whenever a core frees, a ready phantom job takes it before the
# emulator and sit-to-stand jobs, which fill the other core. After the kinetics, the branch to
# the figures (metrics, statistics, curves, summary, comparison, figures: 2) goes first and the
# engine (1) takes the next free core; the two branches take about as long.
# The protocol keys the calibration's metrics read (the strides it simulates are its own block's,
# so the recordings' length does not rerun it).
CALIBRATION_PROTOCOL = (
    "stride_time_s",
    "clutch_on_pct",
    "clutch_off_pct",
    "work_window_s",
    "min_spring_force_N",
)


rule phantom_reference_cycle:
    input:
        csv=REFERENCE / "phantom_knee_flexion_mean_cycle.csv",
        code=code("phantom_reference.py"),
    output:
        table=report(
            PHANTOM / "reference" / "mean_cycle.parquet",
            caption="../report/phantom_reference_table.rst",
            category="Phantom",
            subcategory="Reference data",
        ),
        png=report(
            PHANTOM_FIGURES / "reference_mean_cycle.png",
            caption="../report/phantom_reference_cycle.rst",
            category="Phantom",
            subcategory="Reference data",
        ),
        pdf=PHANTOM_FIGURES / "reference_mean_cycle.pdf",
        caption=PHANTOM_FIGURES / "reference_mean_cycle.caption.md",
    log:
        logfile("phantom_reference_cycle"),
    benchmark:
        benchfile("phantom_reference_cycle")
    resources:
        mem_mb=500,
        runtime=5,
    message:
        "read and plot the reference mean knee cycle"
    script:
        "../scripts/phantom_reference.py"


rule phantom_calibrate:
    input:
        cycle=REFERENCE / "phantom_knee_flexion_mean_cycle.csv",
        reported=REFERENCE / "seed000_reported.csv",
        code=code("phantom_calibrate.py"),
    output:
        fit=report(
            PHANTOM / "calibration" / "fit.json",
            caption="../report/phantom_calibration.rst",
            category="Phantom",
            subcategory="Digital twin",
        ),
        residuals=report(
            PHANTOM / "calibration" / "residuals.csv",
            caption="../report/phantom_calibration.rst",
            category="Phantom",
            subcategory="Digital twin",
        ),
    log:
        logfile("phantom_calibrate"),
    benchmark:
        benchfile("phantom_calibrate")
    priority: 1
    resources:
        mem_mb=1000,
        runtime=30,
    params:
        rig=PHANTOM_RIG,
        protocol={
            key: lookup(dpath=f"phantom/protocol/{key}", within=config)
            for key in CALIBRATION_PROTOCOL
        },
        twin=lookup(dpath="phantom/twin", within=config),
        calibration=lookup(dpath="phantom/calibration", within=config),
        seed=lookup(dpath="seed", within=config),
    message:
        "fit the phantom twin's effects to the medians W.S.B. et al. report"
    script:
        "../scripts/phantom_calibrate.py"


if SYNTHETIC:

    rule phantom_twin:
        input:
            cycle=REFERENCE / "phantom_knee_flexion_mean_cycle.csv",
            fit=rules.phantom_calibrate.output.fit,
            code=code("phantom_twin.py"),
        output:
            manifest=PHANTOM_RAW / "manifest.csv",
            c3d=expand(PHANTOM_RAW / "{trial}.c3d", trial=PHANTOM_TRIALS),
            truth=expand(
                PHANTOM_RAW / "truth" / "{trial}.parquet", trial=PHANTOM_TRIALS
            ),
            stamp=PHANTOM_RAW / stamp.STAMP,
        log:
            logfile("phantom_twin"),
        benchmark:
            benchfile("phantom_twin")
        priority: 1
        resources:
            mem_mb=2000,
            runtime=30,
        params:
            rig=PHANTOM_RIG,
            protocol=lookup(dpath="phantom/protocol", within=config),
            twin=lookup(dpath="phantom/twin", within=config),
            seed=lookup(dpath="seed", within=config),
        message:
            "the phantom digital twin writes its recordings"
        script:
            "../scripts/phantom_twin.py"


# Per-trial stages: one job per stage over every trial (a trial's work is smaller than a job's
# start-up), still one Parquet file per trial and stage.
rule phantom_acquire_trial:
    input:
        manifest=PHANTOM_RAW / "manifest.csv",
        c3d=PHANTOM_C3D,
        code=code("phantom_acquire.py"),
    output:
        markers=phantom_trial_files("acquired", "_markers"),
        analog=phantom_trial_files("acquired", "_analog"),
        events=phantom_trial_files("acquired", "_events"),
    log:
        logfile("phantom_acquire_trial"),
    benchmark:
        benchfile("phantom_acquire_trial")
    priority: 1
    resources:
        mem_mb=1000,
        runtime=10,
    params:
        trials=PHANTOM_TRIALS,
        stride_time_s=lookup(dpath="phantom/protocol/stride_time_s", within=config),
        # a lab's label map; the twin writes the contract's labels (config_checks warns)
        labels={} if SYNTHETIC else lookup(dpath="phantom/rig/labels", within=config),
        glitches=lookup(dpath="phantom/chain/glitches", within=config),
        max_gap_frames=lookup(dpath="phantom/chain/max_gap_frames", within=config),
        unit_slips=lookup(dpath="phantom/chain/unit_slips", within=config),
        sync_threshold_V=lookup(dpath="phantom/chain/sync_threshold_V", within=config),
        # the segment lengths and masses the unit-slip checks compare the recording with
        rig=PHANTOM_RIG,
    message:
        "read and check the phantom C3D recordings"
    script:
        "../scripts/phantom_acquire.py"


rule phantom_filter:
    input:
        markers=rules.phantom_acquire_trial.output.markers,
        analog=rules.phantom_acquire_trial.output.analog,
        code=code("phantom_filter.py"),
    output:
        markers=phantom_trial_files("filtered", "_markers"),
        analog=phantom_trial_files("filtered", "_analog"),
    log:
        logfile("phantom_filter"),
    benchmark:
        benchfile("phantom_filter")
    priority: 1
    resources:
        mem_mb=2000,
        runtime=10,
    params:
        chain=lookup(dpath="phantom/chain", within=config),
    message:
        "fill marker gaps and low-pass filter every trial"
    script:
        "../scripts/phantom_filter.py"


rule phantom_angles:
    input:
        markers=rules.phantom_filter.output.markers,
        code=code("phantom_angles.py"),
    output:
        angles=phantom_trial_files("angles"),
    log:
        logfile("phantom_angles"),
    benchmark:
        benchfile("phantom_angles")
    priority: 1
    resources:
        mem_mb=2000,
        runtime=10,
    message:
        "knee angles, spring length and joint centres of every trial"
    script:
        "../scripts/phantom_angles.py"


rule phantom_strides:
    input:
        manifest=PHANTOM_RAW / "manifest.csv",
        cycle=rules.phantom_reference_cycle.output.table,
        filtered=rules.phantom_filter.output.analog,
        angles=rules.phantom_angles.output.angles,
        events=rules.phantom_acquire_trial.output.events,
        code=code("phantom_strides.py"),
    output:
        strides=reported_trials("strides", "../report/phantom_strides.rst"),
        qc=reported_trials("qc", "../report/phantom_strides.rst"),
    log:
        logfile("phantom_strides"),
    benchmark:
        benchfile("phantom_strides")
    priority: 1
    resources:
        mem_mb=1000,
        runtime=10,
    params:
        trials=PHANTOM_TRIALS,
        chain=lookup(dpath="phantom/chain", within=config),
        min_spring_force_N=lookup(
            dpath="phantom/protocol/min_spring_force_N", within=config
        ),
    message:
        "find the strides of every trial and which are analysed"
    script:
        "../scripts/phantom_strides.py"


rule phantom_dynamics:
    input:
        angles=rules.phantom_angles.output.angles,
        filtered=rules.phantom_filter.output.analog,
        code=code("phantom_dynamics.py"),
    output:
        moments=phantom_trial_files("moments"),
    log:
        logfile("phantom_dynamics"),
    benchmark:
        benchfile("phantom_dynamics")
    priority: 1
    resources:
        mem_mb=2000,
        runtime=10,
    params:
        rig=PHANTOM_RIG,
    message:
        "inverse dynamics of the phantom knee, every trial"
    script:
        "../scripts/phantom_dynamics.py"


rule phantom_kinetics:
    input:
        angles=rules.phantom_angles.output.angles,
        moments=rules.phantom_dynamics.output.moments,
        filtered=rules.phantom_filter.output.analog,
        strides=rules.phantom_strides.output.strides,
        code=code("phantom_kinetics.py"),
    output:
        kinetics=phantom_trial_files("kinetics"),
    log:
        logfile("phantom_kinetics"),
    benchmark:
        benchfile("phantom_kinetics")
    priority: 1
    resources:
        mem_mb=2000,
        runtime=10,
    message:
        "power partition of the analysed strides, every trial"
    script:
        "../scripts/phantom_kinetics.py"


rule phantom_metrics:
    input:
        manifest=PHANTOM_RAW / "manifest.csv",
        strides=rules.phantom_strides.output.strides,
        kinetics=rules.phantom_kinetics.output.kinetics,
        code=code("phantom_metrics.py"),
    output:
        report(
            PHANTOM / "metrics.parquet",
            caption="../report/phantom_metrics.rst",
            category="Phantom",
            subcategory="Tables",
        ),
    log:
        logfile("phantom_metrics"),
    benchmark:
        benchfile("phantom_metrics")
    priority: 2
    resources:
        mem_mb=1000,
        runtime=10,
    params:
        trials=PHANTOM_TRIALS,
        protocol=lookup(dpath="phantom/protocol", within=config),
    message:
        "per-stride stance flexion, peak moment, stiffness and work"
    script:
        "../scripts/phantom_metrics.py"


rule phantom_curves:
    input:
        metrics=rules.phantom_metrics.output[0],
        kinetics=rules.phantom_kinetics.output.kinetics,
        code=code("phantom_curves.py"),
    output:
        report(
            PHANTOM / "curves.parquet",
            caption="../report/phantom_curves.rst",
            category="Phantom",
            subcategory="Tables",
        ),
    log:
        logfile("phantom_curves"),
    benchmark:
        benchfile("phantom_curves")
    priority: 2
    resources:
        mem_mb=1000,
        runtime=10,
    params:
        trials=PHANTOM_TRIALS,
        points=400,
    message:
        "mean and SD curves over the gait cycle per spring"
    script:
        "../scripts/phantom_curves.py"


rule phantom_statistics:
    input:
        metrics=rules.phantom_metrics.output[0],
        code=code("phantom_statistics.py"),
    output:
        kruskal=report(
            PHANTOM / "stats" / "kruskal.csv",
            caption="../report/phantom_tables.rst",
            category="Phantom",
            subcategory="Tables",
        ),
        notation=report(
            PHANTOM / "stats" / "notation.csv",
            caption="../report/phantom_tables.rst",
            category="Phantom",
            subcategory="Tables",
        ),
        dunn=[
            report(
                PHANTOM / "stats" / "dunn" / f"{metric}.csv",
                caption="../report/phantom_tables.rst",
                category="Phantom",
                subcategory="Dunn tests",
                labels={"metric": metric},
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
        alpha=0.05,
    message:
        "Kruskal-Wallis and Dunn tests across springs"
    script:
        "../scripts/phantom_statistics.py"


rule phantom_summary:
    input:
        metrics=rules.phantom_metrics.output[0],
        code=code("phantom_summary.py"),
    output:
        report(
            PHANTOM / "summary.csv",
            caption="../report/phantom_tables.rst",
            category="Phantom",
            subcategory="Tables",
        ),
    log:
        logfile("phantom_summary"),
    benchmark:
        benchfile("phantom_summary")
    priority: 2
    resources:
        mem_mb=1000,
        runtime=5,
    message:
        "median, quartiles, mean, SD and n per spring and metric"
    script:
        "../scripts/phantom_summary.py"


rule phantom_compare:
    input:
        metrics=rules.phantom_metrics.output[0],
        reported=REFERENCE / "seed000_reported.csv",
        code=code("phantom_compare.py"),
    output:
        report(
            PHANTOM / "paper_comparison.csv",
            caption="../report/phantom_tables.rst",
            category="Phantom",
            subcategory="Tables",
        ),
    log:
        logfile("phantom_compare"),
    benchmark:
        benchfile("phantom_compare")
    priority: 2
    resources:
        mem_mb=1000,
        runtime=5,
    message:
        "reproduced numbers against W.S.B. et al.'s"
    script:
        "../scripts/phantom_compare.py"


rule phantom_figures:
    input:
        curves=rules.phantom_curves.output[0],
        summary=rules.phantom_summary.output[0],
        notation=rules.phantom_statistics.output.notation,
        code=code("phantom_figures.py"),
    output:
        fig05_kinematics_png=report(
            PHANTOM_FIGURES / "fig05_kinematics.png",
            caption="../report/phantom_fig05_kinematics.rst",
            category="Phantom",
            subcategory="Figures",
        ),
        fig05_kinematics_pdf=PHANTOM_FIGURES / "fig05_kinematics.pdf",
        fig05_kinematics_caption=PHANTOM_FIGURES / "fig05_kinematics.caption.md",
        fig06_kinetics_png=report(
            PHANTOM_FIGURES / "fig06_kinetics.png",
            caption="../report/phantom_fig06_kinetics.rst",
            category="Phantom",
            subcategory="Figures",
        ),
        fig06_kinetics_pdf=PHANTOM_FIGURES / "fig06_kinetics.pdf",
        fig06_kinetics_caption=PHANTOM_FIGURES / "fig06_kinetics.caption.md",
        fig07_assistance_png=report(
            PHANTOM_FIGURES / "fig07_assistance.png",
            caption="../report/phantom_fig07_assistance.rst",
            category="Phantom",
            subcategory="Figures",
        ),
        fig07_assistance_pdf=PHANTOM_FIGURES / "fig07_assistance.pdf",
        fig07_assistance_caption=PHANTOM_FIGURES / "fig07_assistance.caption.md",
        fig08_power_by_spring_png=report(
            PHANTOM_FIGURES / "fig08_power_by_spring.png",
            caption="../report/phantom_fig08_power_by_spring.rst",
            category="Phantom",
            subcategory="Figures",
        ),
        fig08_power_by_spring_pdf=PHANTOM_FIGURES / "fig08_power_by_spring.pdf",
        fig08_power_by_spring_caption=PHANTOM_FIGURES
        / "fig08_power_by_spring.caption.md",
        fig09_power_by_component_png=report(
            PHANTOM_FIGURES / "fig09_power_by_component.png",
            caption="../report/phantom_fig09_power_by_component.rst",
            category="Phantom",
            subcategory="Figures",
        ),
        fig09_power_by_component_pdf=PHANTOM_FIGURES / "fig09_power_by_component.pdf",
        fig09_power_by_component_caption=PHANTOM_FIGURES
        / "fig09_power_by_component.caption.md",
        fig10_work_png=report(
            PHANTOM_FIGURES / "fig10_work.png",
            caption="../report/phantom_fig10_work.rst",
            category="Phantom",
            subcategory="Figures",
        ),
        fig10_work_pdf=PHANTOM_FIGURES / "fig10_work.pdf",
        fig10_work_caption=PHANTOM_FIGURES / "fig10_work.caption.md",
        fig11_relative_work_png=report(
            PHANTOM_FIGURES / "fig11_relative_work.png",
            caption="../report/phantom_fig11_relative_work.rst",
            category="Phantom",
            subcategory="Figures",
        ),
        fig11_relative_work_pdf=PHANTOM_FIGURES / "fig11_relative_work.pdf",
        fig11_relative_work_caption=PHANTOM_FIGURES / "fig11_relative_work.caption.md",
    log:
        logfile("phantom_figures"),
    benchmark:
        benchfile("phantom_figures")
    priority: 2
    resources:
        mem_mb=1000,
        runtime=10,
    params:
        protocol=lookup(dpath="phantom/protocol", within=config),
        alpha=rules.phantom_statistics.params.alpha,
    message:
        "figures 5-11 of W.S.B. et al. with their captions"
    script:
        "../scripts/phantom_figures.py"


rule phantom_discrepancy:
    input:
        manifest=PHANTOM_RAW / "manifest.csv",
        kinetics=rules.phantom_kinetics.output.kinetics,
        strides=rules.phantom_strides.output.strides,
        code=code("phantom_discrepancy.py"),
    output:
        recordings=report(
            PHANTOM / "discrepancy.json",
            caption="../report/phantom_discrepancy_outputs.rst",
            category="Phantom",
            subcategory="Model discrepancy",
        ),
        predictions=report(
            PHANTOM / "discrepancy_predictions.parquet",
            caption="../report/phantom_discrepancy_outputs.rst",
            category="Phantom",
            subcategory="Model discrepancy",
        ),
        terms=report(
            PHANTOM / "discrepancy_terms.parquet",
            caption="../report/phantom_discrepancy_outputs.rst",
            category="Phantom",
            subcategory="Model discrepancy",
        ),
    log:
        logfile("phantom_discrepancy"),
    benchmark:
        benchfile("phantom_discrepancy")
    priority: 1
    # One thread: two worker processes made it only 1.2× faster while holding both cores; a
    # cluster run can give it more (--set-threads phantom_discrepancy=4).
    threads: 1
    resources:
        mem_mb=1000,
        runtime=30,
    params:
        trials=PHANTOM_TRIALS,
        rig=PHANTOM_RIG,
        discrepancy=lookup(dpath="phantom/discrepancy", within=config),
        chain=lookup(dpath="phantom/chain", within=config),
        engine=lookup(dpath="discrepancy", within=config),
        seed=lookup(dpath="seed", within=config),
    message:
        "model discrepancy of the phantom recordings"
    script:
        "../scripts/phantom_discrepancy.py"


# W.S.B. et al.'s medians as the data: the same engine on the numbers the paper reports, each
# held out in turn (the mean cycle gives the knee's flexion at the clutch's engagement).
rule phantom_discrepancy_reported:
    input:
        reported=REFERENCE / "seed000_reported.csv",
        cycle=REFERENCE / "phantom_knee_flexion_mean_cycle.csv",
        code=code("phantom_discrepancy_reported.py"),
    output:
        report(
            PHANTOM / "discrepancy_reported.json",
            caption="../report/phantom_discrepancy_outputs.rst",
            category="Phantom",
            subcategory="Model discrepancy",
        ),
    log:
        logfile("phantom_discrepancy_reported"),
    benchmark:
        benchfile("phantom_discrepancy_reported")
    priority: 1
    resources:
        mem_mb=1000,
        runtime=10,
    params:
        rig=PHANTOM_RIG,
        clutch_on_pct=lookup(dpath="phantom/protocol/clutch_on_pct", within=config),
        engine=lookup(dpath="discrepancy", within=config),
        seed=lookup(dpath="seed", within=config),
    message:
        "model discrepancy of the medians W.S.B. et al. report"
    script:
        "../scripts/phantom_discrepancy_reported.py"


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
        code=code("phantom_discrepancy_figure.py"),
    output:
        png=report(
            PHANTOM_FIGURES / "discrepancy.png",
            caption="../report/phantom_discrepancy.rst",
            category="Phantom",
            subcategory="Model discrepancy",
        ),
        pdf=PHANTOM_FIGURES / "discrepancy.pdf",
        caption=PHANTOM_FIGURES / "discrepancy.caption.md",
    log:
        logfile("phantom_discrepancy_figure"),
    benchmark:
        benchfile("phantom_discrepancy_figure")
    priority: 1
    resources:
        mem_mb=1000,
        runtime=5,
    params:
        protocol={
            key: lookup(dpath=f"phantom/protocol/{key}", within=config)
            for key in ("work_window_s", "stride_time_s")
        },
    message:
        "figure of measured vs rigid theory vs extended model"
    script:
        "../scripts/phantom_discrepancy_figure.py"


rule phantom_checks:
    input:
        manifest=PHANTOM_RAW / "manifest.csv",
        kinetics=rules.phantom_kinetics.output.kinetics,
        strides=rules.phantom_strides.output.strides,
        angles=rules.phantom_angles.output.angles,
        metrics=rules.phantom_metrics.output[0],
        code=code("phantom_checks.py"),
    output:
        report(
            PHANTOM / "assumption_checks.csv",
            caption="../report/phantom_checks.rst",
            category="Phantom",
            subcategory="Model discrepancy",
        ),
    log:
        logfile("phantom_checks"),
    benchmark:
        benchfile("phantom_checks")
    priority: 1
    resources:
        mem_mb=1000,
        runtime=5,
    params:
        trials=PHANTOM_TRIALS,
        rig=PHANTOM_RIG,
        checks=lookup(dpath="phantom/checks", within=config),
        window_pct=lookup(dpath="phantom/discrepancy/window_pct", within=config),
        swing_pct=lookup(dpath="phantom/discrepancy/noise_pct", within=config),
    message:
        "direct checks of the rig's assumptions on the recordings"
    script:
        "../scripts/phantom_checks.py"


rule phantom_verdict:
    input:
        # W.S.B. et al.'s medians and the twin's calibration to them, when the run compares with
        # them (they fit some of the same parameters); the calibration, with the twin (its
        # effects were set from it)
        **(
            {
                "reported": rules.phantom_discrepancy_reported.output[0],
                "residuals": rules.phantom_calibrate.output.residuals,
            }
            if PHANTOM_SEED000
            else {}
        ),
        **(
            {"fit": rules.phantom_calibrate.output.fit}
            if SYNTHETIC or PHANTOM_SEED000
            else {}
        ),
        recordings=rules.phantom_discrepancy.output.recordings,
        checks=rules.phantom_checks.output[0],
        predictions=rules.phantom_discrepancy.output.predictions,
        code=code("phantom_verdict.py"),
    output:
        summary=report(
            PHANTOM / "summary.md",
            caption="../report/phantom_verdict.rst",
            category="Phantom",
            subcategory="Model discrepancy",
        ),
        tests=report(
            PHANTOM / "residual_tests.md",
            caption="../report/phantom_verdict.rst",
            category="Phantom",
            subcategory="Model discrepancy",
        ),
    log:
        logfile("phantom_verdict"),
    benchmark:
        benchfile("phantom_verdict")
    priority: 1
    resources:
        mem_mb=500,
        runtime=5,
    params:
        source=source_spec("phantom", ["phantom.twin"], "calibration/fit.json"),
        # the twin's effects as set (with the twin, or to name what the calibration fitted)
        effects=(
            lookup(dpath="phantom/twin/effects", within=config)
            if SYNTHETIC or PHANTOM_SEED000
            else {}
        ),
    message:
        "the verdict in words: summary.md"
    script:
        "../scripts/phantom_verdict.py"


rule phantom_terms_figure:
    input:
        terms=rules.phantom_discrepancy.output.terms,
        predictions=rules.phantom_discrepancy.output.predictions,
        recordings=rules.phantom_discrepancy.output.recordings,
        code=code("phantom_terms_figure.py"),
    output:
        png=report(
            PHANTOM_FIGURES / "discrepancy_terms.png",
            caption="../report/phantom_discrepancy_terms.rst",
            category="Phantom",
            subcategory="Model discrepancy",
        ),
        pdf=PHANTOM_FIGURES / "discrepancy_terms.pdf",
        caption=PHANTOM_FIGURES / "discrepancy_terms.caption.md",
    log:
        logfile("phantom_terms_figure"),
    benchmark:
        benchfile("phantom_terms_figure")
    priority: 1
    resources:
        mem_mb=1000,
        runtime=5,
    message:
        "figure of what the extended model leaves and the terms discovered"
    script:
        "../scripts/phantom_terms_figure.py"


rule phantom_qc_figure:
    input:
        manifest=PHANTOM_RAW / "manifest.csv",
        qc=rules.phantom_strides.output.qc,
        strides=rules.phantom_strides.output.strides,
        code=code("phantom_qc_figure.py"),
    output:
        png=report(
            PHANTOM_FIGURES / "qc.png",
            caption="../report/phantom_qc.rst",
            category="Phantom",
            subcategory="Quality control",
        ),
        pdf=PHANTOM_FIGURES / "qc.pdf",
        caption=PHANTOM_FIGURES / "qc.caption.md",
    log:
        logfile("phantom_qc_figure"),
    benchmark:
        benchfile("phantom_qc_figure")
    priority: 2
    resources:
        mem_mb=1000,
        runtime=5,
    params:
        trials=PHANTOM_TRIALS,
        max_gap_frames=lookup(dpath="phantom/chain/max_gap_frames", within=config),
        # the lab's own channel labels (contract name -> label), shown instead of the contract's
        # (the twin writes the contract's)
        labels={} if SYNTHETIC else lookup(dpath="phantom/rig/labels", within=config),
    message:
        "figure of the glitches repaired or left as gaps and the strides kept"
    script:
        "../scripts/phantom_qc_figure.py"


rule phantom_acquire:
    input:
        PHANTOM_RAW / "manifest.csv",
        rules.phantom_acquire_trial.output,
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
        rules.phantom_filter.output,
        rules.phantom_angles.output,
        rules.phantom_strides.output,
        rules.phantom_dynamics.output,
        rules.phantom_kinetics.output,
        rules.phantom_metrics.output,
        rules.phantom_statistics.output,
        rules.phantom_summary.output,
        rules.phantom_figures.output,
        rules.phantom_qc_figure.output,
        rules.phantom_discrepancy.output,
        rules.phantom_discrepancy_figure.output,
        rules.phantom_terms_figure.output,
        rules.phantom_verdict.output,
    message:
        "phantom group up to date"
