"""Rule phantom_reference_cycle: reference mean knee cycle to Parquet and a figure."""

from exobench import figures, tables
from exobench.phantom import reference
from exobench.plumbing import runner


def stage(smk, provenance):
    cycle = reference.read_mean_cycle(smk.input.csv)
    tables.write_table(smk.output.table, cycle, provenance)
    drawn = {"reference_mean_cycle": reference.mean_cycle_figure(cycle)}
    figures.publish(smk.output, smk.params.figures, drawn)


runner.run(snakemake, stage)
