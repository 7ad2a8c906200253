# Phantom stage 1, recordings and chain: the reference cycle, the twin's calibration and recordings
# (synthetic) or the lab's files, then each trial's chain (acquisition, filtering, angles,
# strides, inverse dynamics, power partition) and the per-stride metrics.


rule phantom_reference_cycle:
    input:
        csv=REFERENCE / "phantom_knee_flexion_mean_cycle.csv",
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
    priority: 8
    resources:
        mem_mb=500,
        runtime=5,
    params:
        code=code("phantom_reference.py"),
        figures=["reference_mean_cycle"],
    message:
        "read and plot the reference mean knee cycle"
    script:
        "../scripts/phantom_reference.py"


rule phantom_calibrate:
    input:
        cycle=REFERENCE / "phantom_knee_flexion_mean_cycle.csv",
        reported=REFERENCE / "seed000_reported.csv",
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
        code=code("phantom_calibrate.py"),
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
        output:
            manifest=PHANTOM_RAW / "manifest.csv",
            c3d=expand(PHANTOM_RAW / "{trial}.c3d", trial=PHANTOM_ALL_TRIALS),
            truth=expand(
                PHANTOM_RAW / "truth" / "{trial}.parquet", trial=PHANTOM_ALL_TRIALS
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
            code=code("phantom_twin.py"),
            rig=PHANTOM_RIG,
            protocol=setting("phantom/protocol"),
            twin=setting("phantom/twin"),
            seed=setting("seed"),
        message:
            "the phantom digital twin writes its recordings"
        script:
            "../scripts/phantom_twin.py"


# Per-trial chain: one job per trial (a cluster runs the trials in parallel, a rerun redoes only
# the trials whose inputs changed, a bad trial fails its own job), each stage's table to its own
# Parquet file (acquired/, filtered/, angles/, strides/, qc/, moments/, kinetics/).
rule phantom_chain:
    input:
        manifest=PHANTOM_RAW / "manifest.csv",
        c3d=phantom_recording,
        cycle=rules.phantom_reference_cycle.output.table,
    output:
        markers=PHANTOM / "acquired" / "{trial}_markers.parquet",
        analog=PHANTOM / "acquired" / "{trial}_analog.parquet",
        events=PHANTOM / "acquired" / "{trial}_events.parquet",
        filtered_markers=PHANTOM / "filtered" / "{trial}_markers.parquet",
        filtered_analog=PHANTOM / "filtered" / "{trial}_analog.parquet",
        angles=PHANTOM / "angles" / "{trial}.parquet",
        strides=reported_trial("strides", "phantom_strides"),
        qc=reported_trial("qc", "phantom_strides"),
        moments=PHANTOM / "moments" / "{trial}.parquet",
        kinetics=PHANTOM / "kinetics" / "{trial}.parquet",
    log:
        logfile("phantom_chain", "{trial}"),
    benchmark:
        benchfile("phantom_chain", "{trial}")
    wildcard_constraints:
        trial=PHANTOM_TRIAL_PATTERN,
    priority: 8
    resources:
        mem_mb=2000,
        runtime=10,
    params:
        code=code("phantom_chain.py"),
        stride_time_s=setting("phantom/protocol/stride_time_s"),
        min_spring_force_N=setting("phantom/protocol/min_spring_force_N"),
        # a lab's label map; the twin writes the contract's labels (config_checks warns)
        labels={} if SYNTHETIC else setting("phantom/rig/labels"),
        chain=setting("phantom/chain"),
        # segment lengths and masses: the unit-slip checks and the inverse dynamics
        rig=PHANTOM_RIG,
    message:
        "the chain of phantom trial {wildcards.trial}: acquisition to power partition"
    script:
        "../scripts/phantom_chain.py"


rule phantom_metrics:
    input:
        **PHANTOM_KINETICS,
        manifest=PHANTOM_RAW / "manifest.csv",
        strides=PHANTOM_CHAIN["strides"],
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
        code=code("phantom_metrics.py"),
        trials=PHANTOM_TRIALS,
        protocol=setting("phantom/protocol"),
        robust_z=setting("phantom/statistics/outlier_robust_z"),
        slope_validity=setting("phantom/statistics/slope_validity"),
    message:
        "per-stride stance flexion, peak moment, stiffness and work; outliers named"
    script:
        "../scripts/phantom_metrics.py"
