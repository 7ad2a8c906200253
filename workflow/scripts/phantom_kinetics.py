"""Rule phantom_kinetics: power partition of the analysed strides (contract table, per trial)."""

from exobench import tables
from exobench.phantom.chain import kinetics
from exobench.plumbing import provenance, runner


def stage(smk, record):
    inp = smk.input
    for paths in zip(
        inp.angles, inp.moments, inp.filtered, inp.strides, smk.output.kinetics, strict=True
    ):
        *sources, out = paths
        table = kinetics.kinetics_table(*(tables.read_table(path).data for path in sources))
        tables.write_table(out, table, provenance.restrict(record, sources, smk.config))


runner.run(snakemake, stage)
