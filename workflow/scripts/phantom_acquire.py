"""Rule phantom_acquire_trial: one C3D trial, checked against RIG.md, to Parquet."""

from pathlib import Path

from exobench import runner
from exobench.phantom import acquire


def stage(smk, provenance):
    row = acquire.acquire(
        Path(smk.input.manifest),
        smk.wildcards.trial,
        smk.output.markers,
        smk.output.analog,
        provenance,
        float(smk.config["phantom"]["protocol"]["stride_time_s"]),
    )
    runner.LOG.info("acquired %s", row)


runner.run(snakemake, stage)
