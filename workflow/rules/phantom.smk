# Phantom + passive knee exoskeleton (seed 000): calibration → digital twin (synthetic) or lab
# files → acquisition.
rule phantom_reference_cycle:
    input:
        csv=REFERENCE / "phantom_knee_flexion_mean_cycle.csv",
    output:
        table=PHANTOM / "reference" / "mean_cycle.parquet",
        png=report(
            PHANTOM_FIGURES / "reference_mean_cycle.png",
            caption="../report/phantom_reference_cycle.rst",
            category="Phantom",
            subcategory="Reference data",
        ),
        pdf=PHANTOM_FIGURES / "reference_mean_cycle.pdf",
    log:
        logfile("phantom_reference_cycle"),
    benchmark:
        benchfile("phantom_reference_cycle")
    script:
        "../scripts/phantom_reference.py"


rule phantom_calibrate:
    input:
        cycle=REFERENCE / "phantom_knee_flexion_mean_cycle.csv",
        reported=REFERENCE / "seed000_reported.csv",
    output:
        fit=PHANTOM / "calibration" / "fit.json",
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
    script:
        "../scripts/phantom_calibrate.py"


if SYNTHETIC:

    rule phantom_twin:
        input:
            cycle=REFERENCE / "phantom_knee_flexion_mean_cycle.csv",
            fit=rules.phantom_calibrate.output.fit,
        output:
            manifest=PHANTOM_RAW / "manifest.csv",
            c3d=expand(PHANTOM_RAW / "{trial}.c3d", trial=PHANTOM_TRIALS),
            truth=expand(
                PHANTOM_RAW / "truth" / "{trial}.parquet", trial=PHANTOM_TRIALS
            ),
            stamp=PHANTOM_RAW / phantom_twin.STAMP,
        log:
            logfile("phantom_twin"),
        benchmark:
            benchfile("phantom_twin")
        script:
            "../scripts/phantom_twin.py"


rule phantom_acquire_trial:
    input:
        manifest=PHANTOM_RAW / "manifest.csv",
        c3d=PHANTOM_RAW / "{trial}.c3d",
    output:
        markers=PHANTOM / "acquired" / "{trial}_markers.parquet",
        analog=PHANTOM / "acquired" / "{trial}_analog.parquet",
    log:
        logfile("phantom_acquire_trial_{trial}"),
    benchmark:
        benchfile("phantom_acquire_trial_{trial}")
    script:
        "../scripts/phantom_acquire.py"


rule phantom_filter:
    input:
        markers=rules.phantom_acquire_trial.output.markers,
        analog=rules.phantom_acquire_trial.output.analog,
    output:
        PHANTOM / "filtered" / "{trial}.parquet",
    log:
        logfile("phantom_filter_{trial}"),
    benchmark:
        benchfile("phantom_filter_{trial}")
    script:
        "../scripts/phantom_filter.py"


rule phantom_angles:
    input:
        rules.phantom_filter.output,
    output:
        PHANTOM / "angles" / "{trial}.parquet",
    log:
        logfile("phantom_angles_{trial}"),
    benchmark:
        benchfile("phantom_angles_{trial}")
    script:
        "../scripts/phantom_angles.py"


rule phantom_strides:
    input:
        manifest=PHANTOM_RAW / "manifest.csv",
        cycle=rules.phantom_reference_cycle.output.table,
        filtered=rules.phantom_filter.output,
        angles=rules.phantom_angles.output,
    output:
        PHANTOM / "strides" / "{trial}.parquet",
    log:
        logfile("phantom_strides_{trial}"),
    benchmark:
        benchfile("phantom_strides_{trial}")
    script:
        "../scripts/phantom_strides.py"


rule phantom_dynamics:
    input:
        angles=rules.phantom_angles.output,
        filtered=rules.phantom_filter.output,
    output:
        PHANTOM / "moments" / "{trial}.parquet",
    log:
        logfile("phantom_dynamics_{trial}"),
    benchmark:
        benchfile("phantom_dynamics_{trial}")
    script:
        "../scripts/phantom_dynamics.py"


rule phantom_kinetics:
    input:
        angles=rules.phantom_angles.output,
        moments=rules.phantom_dynamics.output,
        filtered=rules.phantom_filter.output,
        strides=rules.phantom_strides.output,
    output:
        PHANTOM / "kinetics" / "{trial}.parquet",
    log:
        logfile("phantom_kinetics_{trial}"),
    benchmark:
        benchfile("phantom_kinetics_{trial}")
    script:
        "../scripts/phantom_kinetics.py"


rule phantom_metrics:
    input:
        manifest=PHANTOM_RAW / "manifest.csv",
        strides=expand(rules.phantom_strides.output, trial=PHANTOM_TRIALS),
        kinetics=expand(rules.phantom_kinetics.output, trial=PHANTOM_TRIALS),
    output:
        PHANTOM / "metrics.parquet",
    log:
        logfile("phantom_metrics"),
    benchmark:
        benchfile("phantom_metrics")
    params:
        trials=PHANTOM_TRIALS,
    script:
        "../scripts/phantom_metrics.py"


rule phantom_acquire:
    input:
        PHANTOM_RAW / "manifest.csv",
        expand(rules.phantom_acquire_trial.output, trial=PHANTOM_TRIALS),


rule phantom:
    input:
        rules.phantom_reference_cycle.output,
        rules.phantom_calibrate.output,
        rules.phantom_acquire.input,
        rules.phantom_metrics.output,
