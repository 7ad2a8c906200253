"""Rule validate_stability: per group and constant, the false-alarm rate where nothing changed
and the detection where one trial's constant did, by size."""

import pandas as pd

from exobench import selection, tables
from exobench.emulator.validation import stability as emulator
from exobench.phantom.validation import stability as phantom
from exobench.plumbing import runner


def stage(smk, provenance):
    rows = pd.concat([pd.read_csv(path, comment="#") for path in smk.input.batches],
                     ignore_index=True)  # fmt: skip
    summary = selection.stability_summary(rows, {**phantom.SPREADS, **emulator.SPREADS})
    runner.LOG.info("parameter stability:\n%s", summary.to_string())
    tables.write_csv(smk.output.rows, rows, provenance)
    tables.write_csv(smk.output.summary, summary, provenance)


runner.run(snakemake, stage)
