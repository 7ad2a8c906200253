"""Rule validate_stability_emulator: per constant, the false-alarm rate where nothing changed and
the detection where one trial's constant did, by size."""

import pandas as pd

from exobench import selection, tables
from exobench.emulator.validation import stability
from exobench.plumbing import runner


def stage(smk, provenance):
    rows = pd.concat([pd.read_csv(path) for path in smk.input.batches], ignore_index=True)
    summary = selection.stability_summary(rows, stability.spreads())
    runner.LOG.info("parameter stability, emulator:\n%s", summary.to_string())
    tables.write_csv(smk.output.rows, rows, provenance)
    tables.write_csv(smk.output.summary, summary, provenance)


runner.run(snakemake, stage)
