# The results folder's index (<results_dir>/index.md): one line per summary, table and figure,
# from the registry exobench.plumbing.results_index.ENTRIES. Included last: its inputs are every
# group's targets, so it runs after them and fails, naming the files, when the folder holds one
# no entry describes (a new output needs its line in the registry).


rule results_index:
    input:
        rules.phantom.input,
        rules.sts.input,
        rules.emulator.input,
    output:
        in_report(RESULTS / "index.md", "workflow", "results_index", "Index"),
    log:
        logfile("results_index"),
    benchmark:
        benchfile("results_index")
    resources:
        mem_mb=500,
        runtime=5,
    params:
        code=code("results_index.py"),
    message:
        "the results folder's index: index.md"
    script:
        "../scripts/results_index.py"
