"""Rule phantom_dynamics: net knee moment by planar inverse dynamics."""

from exobench import phantom, runner, tables
from exobench.phantom import inverse_dynamics
from exobench.phantom.rig import Rig


def stage(smk, provenance):
    rig = Rig.from_config(phantom.settings(smk.config)["rig"])
    result = inverse_dynamics.knee_kinetics(
        tables.read_table(smk.input.angles).data, tables.read_table(smk.input.filtered).data, rig
    )
    tables.write_table(smk.output[0], result, provenance)


runner.run(snakemake, stage)
