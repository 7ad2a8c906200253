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


rule phantom_acquire:
    input:
        PHANTOM_RAW / "manifest.csv",
        expand(rules.phantom_acquire_trial.output, trial=PHANTOM_TRIALS),


rule phantom:
    input:
        rules.phantom_reference_cycle.output,
        rules.phantom_calibrate.output,
        rules.phantom_acquire.input,
