# Sit-to-stand kinematics and thigh-link strength checks (seed 001).
# Placeholder until issue 7 lands: the target says so when run.


rule sts_placeholder:
    output:
        RESULTS / "sts" / "STATUS.txt",
    log:
        logfile("sts_placeholder"),
    benchmark:
        benchfile("sts_placeholder")
    params:
        message="The 'sts' rule group is a placeholder: it is built in issue 7.",
    script:
        "../scripts/placeholder.py"


rule sts:
    input:
        rules.sts_placeholder.output,
