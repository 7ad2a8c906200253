"""Rule phantom_reference_cycle: reference mean knee cycle to Parquet and a figure."""

from exobench import figures, tables
from exobench.phantom import reference
from exobench.plumbing import runner


def stage(smk, provenance):
    cycle = reference.read_mean_cycle(smk.input.csv)
    tables.write_table(smk.output.table, cycle, provenance)
    fig, caption = reference.mean_cycle_figure(cycle)
    figures.save(fig, smk.output.png, smk.output.pdf)
    figures.write_caption(smk.output.caption, *caption)


runner.run(snakemake, stage)
