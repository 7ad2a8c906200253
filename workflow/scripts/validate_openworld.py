"""Rule validate_openworld: per fault family the outcomes, and the registry effects' coverage
in the open-world and combined arms."""

import pandas as pd

from exobench import tables
from exobench.plumbing import runner
from exobench.selection import openworld


def stage(smk, provenance):
    rows = pd.concat([pd.read_csv(path) for path in smk.input.batches], ignore_index=True)
    summary = openworld.summary(rows)
    runner.LOG.info("open-world validation:\n%s", summary.to_string())
    tables.write_csv(smk.output.rows, rows, provenance)
    tables.write_csv(smk.output.summary, summary, provenance)


runner.run(snakemake, stage)
