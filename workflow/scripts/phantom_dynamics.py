"""Rule phantom_dynamics: net knee moment by planar inverse dynamics (per trial)."""

from exobench import tables
from exobench.phantom.chain import inverse_dynamics
from exobench.phantom.rig import Rig
from exobench.plumbing import provenance, runner


def stage(smk, record):
    rig = Rig.from_config(smk.params.rig)
    for angles, filtered, out in zip(
        smk.input.angles, smk.input.filtered, smk.output.moments, strict=True
    ):
        result = inverse_dynamics.knee_kinetics(
            tables.read_table(angles).data, tables.read_table(filtered).data, rig
        )
        tables.write_table(out, result, provenance.restrict(record, [angles, filtered], smk.config))


runner.run(snakemake, stage)
