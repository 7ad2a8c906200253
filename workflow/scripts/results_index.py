"""Rule results_index: index.md, one line per summary, table and figure of the results folder,
refusing a file that no entry of the registry describes."""

from pathlib import Path

from exobench import tables
from exobench.plumbing import results_index, runner


def stage(smk, provenance):
    path = Path(smk.output[0])
    tables.write_document(path, results_index.build(path.parent), provenance)


# the index names files and reads none: its inputs (every target) only order it, unhashed
runner.run(snakemake, stage, hashed=False)
