# Knee exoskeleton emulator, energy stored per step (seed 002).
# Placeholder until issue 8 lands: the target says so when run.


rule emulator_placeholder:
    output:
        RESULTS / "emulator" / "STATUS.txt",
    log:
        logfile("emulator_placeholder"),
    benchmark:
        benchfile("emulator_placeholder")
    params:
        message="The 'emulator' rule group is a placeholder: it is built in issue 8.",
    script:
        "../scripts/placeholder.py"


rule emulator:
    input:
        rules.emulator_placeholder.output,
