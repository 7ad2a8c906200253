"""Rule phantom_angles: sagittal knee angles of phantom and exoskeleton, spring length."""

from exobench import tables
from exobench.phantom.chain import angles
from exobench.plumbing import provenance, runner


def stage(smk, record):
    for path, out in zip(smk.input.markers, smk.output.angles, strict=True):
        filtered = tables.read_table(path).data
        tables.write_table(
            out, angles.knee_angles(filtered), provenance.restrict(record, [path], smk.config)
        )


runner.run(snakemake, stage)
