"""Rule phantom_angles: sagittal knee angles of phantom and exoskeleton, spring length."""

from exobench import runner, tables
from exobench.phantom import angles


def stage(smk, provenance):
    filtered = tables.read_table(smk.input[0]).data
    tables.write_table(smk.output[0], angles.knee_angles(filtered), provenance)


runner.run(snakemake, stage)
