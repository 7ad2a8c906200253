"""Rule phantom_acquire_trial: every C3D trial, checked against RIG.md, to Parquet."""

from pathlib import Path

from exobench import provenance, runner
from exobench.phantom import acquire


def stage(smk, record):
    out = smk.output
    for trial, c3d, markers, analog in zip(
        smk.params.trials, smk.input.c3d, out.markers, out.analog, strict=True
    ):
        row = acquire.acquire(
            Path(smk.input.manifest),
            trial,
            markers,
            analog,
            provenance.restrict(record, [smk.input.manifest, c3d], smk.config),
            float(smk.params.stride_time_s),
        )
        runner.LOG.info("acquired %s", row)


runner.run(snakemake, stage)
