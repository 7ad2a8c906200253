"""Rule phantom_kinetics: power partition of the analysed strides (contract table)."""

from exobench import runner, tables
from exobench.phantom import kinetics


def stage(smk, provenance):
    table = kinetics.kinetics_table(
        tables.read_table(smk.input.angles).data,
        tables.read_table(smk.input.moments).data,
        tables.read_table(smk.input.filtered).data,
        tables.read_table(smk.input.strides).data,
    )
    tables.write_table(smk.output[0], table, provenance)


runner.run(snakemake, stage)
