"""Rule phantom_reference_cycle: reference mean knee cycle to Parquet and a figure."""

from exobench import reference, runner, tables


def stage(smk, provenance):
    cycle = reference.read_mean_cycle(smk.input.csv)
    tables.write_table(smk.output.table, cycle, provenance)
    reference.plot_mean_cycle(cycle, smk.output.png, smk.output.pdf)


runner.run(snakemake, stage)
