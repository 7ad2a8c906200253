# Phantom + passive knee exoskeleton (seed 000).


rule phantom_reference_cycle:
    input:
        csv=REFERENCE / "phantom_knee_flexion_mean_cycle.csv",
    output:
        table=RESULTS / "phantom" / "reference" / "mean_cycle.parquet",
        png=report(
            RESULTS / "figures" / "phantom" / "reference_mean_cycle.png",
            caption="../report/phantom_reference_cycle.rst",
            category="Phantom",
            subcategory="Reference data",
        ),
        pdf=RESULTS / "figures" / "phantom" / "reference_mean_cycle.pdf",
    log:
        logfile("phantom_reference_cycle"),
    benchmark:
        benchfile("phantom_reference_cycle")
    script:
        "../scripts/phantom_reference.py"


rule phantom:
    input:
        rules.phantom_reference_cycle.output,
