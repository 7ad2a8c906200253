"""Placeholder rule: says that its group is not built yet, in the log and a status file."""

from exobench import atomic, runner


def stage(smk, provenance):
    runner.LOG.warning(smk.params.message)
    atomic.write_text(smk.output[0], smk.params.message + "\n")


runner.run(snakemake, stage)
