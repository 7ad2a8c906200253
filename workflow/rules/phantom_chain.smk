# Phantom stage 1, recordings and chain: the reference cycle, the twin's calibration and recordings
# (synthetic) or the lab's files, then acquisition, filtering, angles, strides, inverse dynamics,
# power partition and per-stride metrics.


rule phantom_reference_cycle:
    input:
        csv=REFERENCE / "phantom_knee_flexion_mean_cycle.csv",
        code=code("phantom_reference.py"),
    output:
        **figure_outputs(
            "phantom", PHANTOM_FIGURES, ["reference_mean_cycle"], "Reference data"
        ),
        table=in_report(
            PHANTOM / "reference" / "mean_cycle.parquet",
            "phantom",
            "phantom_reference_table",
            "Reference data",
        ),
    log:
        logfile("phantom_reference_cycle"),
    benchmark:
        benchfile("phantom_reference_cycle")
    priority: 4
    resources:
        mem_mb=500,
        runtime=5,
    params:
        figures=["reference_mean_cycle"],
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
        fit=in_report(
            PHANTOM / "calibration" / "fit.json",
            "phantom",
            "phantom_calibration",
            "Digital twin",
        ),
        residuals=in_report(
            PHANTOM / "calibration" / "residuals.csv",
            "phantom",
            "phantom_calibration",
            "Digital twin",
        ),
        # the fitted twin's simulated strides: the spread behind each of its medians
        strides=PHANTOM / "calibration" / "strides.parquet",
    log:
        logfile("phantom_calibrate"),
    benchmark:
        benchfile("phantom_calibrate")
    priority: 11
    resources:
        mem_mb=1000,
        runtime=30,
    params:
        rig=PHANTOM_RIG,
        protocol={
            key: setting(f"phantom/protocol/{key}") for key in CALIBRATION_PROTOCOL
        },
        twin=setting("phantom/twin"),
        calibration=setting("phantom/calibration"),
        seed=setting("seed"),
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
        priority: 9
        resources:
            mem_mb=2000,
            runtime=30,
        params:
            rig=PHANTOM_RIG,
            protocol=setting("phantom/protocol"),
            twin=setting("phantom/twin"),
            seed=setting("seed"),
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
    priority: 8
    resources:
        mem_mb=1000,
        runtime=10,
    params:
        trials=PHANTOM_TRIALS,
        stride_time_s=setting("phantom/protocol/stride_time_s"),
        # a lab's label map; the twin writes the contract's labels (config_checks warns)
        labels={} if SYNTHETIC else setting("phantom/rig/labels"),
        glitches=setting("phantom/chain/glitches"),
        max_gap_frames=setting("phantom/chain/max_gap_frames"),
        unit_slips=setting("phantom/chain/unit_slips"),
        sync_threshold_V=setting("phantom/chain/sync_threshold_V"),
        read_timeout_s=setting("phantom/chain/read_timeout_s"),
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
    priority: 6
    resources:
        mem_mb=2000,
        runtime=10,
    params:
        chain=setting("phantom/chain"),
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
    priority: 5
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
        strides=reported_trials("strides", "phantom_strides"),
        qc=reported_trials("qc", "phantom_strides"),
    log:
        logfile("phantom_strides"),
    benchmark:
        benchfile("phantom_strides")
    priority: 4
    resources:
        mem_mb=1000,
        runtime=10,
    params:
        trials=PHANTOM_TRIALS,
        chain=setting("phantom/chain"),
        min_spring_force_N=setting("phantom/protocol/min_spring_force_N"),
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
    priority: 5
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
    priority: 4
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
        metrics=in_report(
            PHANTOM / "metrics.parquet", "phantom", "phantom_metrics", "Tables"
        ),
        outliers=in_report(
            PHANTOM / "outliers.csv", "phantom", "phantom_metrics", "Tables"
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
        protocol=setting("phantom/protocol"),
        robust_z=setting("phantom/statistics/outlier_robust_z"),
    message:
        "per-stride stance flexion, peak moment, stiffness and work; outliers named"
    script:
        "../scripts/phantom_metrics.py"
