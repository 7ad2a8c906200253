"""Rule validate_emulator_openworld: per fault family the outcomes, the registry effects' coverage
in the open-world and combined arms, and their figure."""

import pandas as pd

from exobench import figures, tables
from exobench.emulator.validation import openworld
from exobench.plumbing import runner
from exobench.selection import openworld as scoring


def stage(smk, provenance):
    rows = pd.concat([pd.read_csv(path) for path in smk.input.batches], ignore_index=True)
    summary = scoring.summary(rows)
    runner.LOG.info("emulator open-world validation:\n%s", summary.to_string())
    tables.write_csv(smk.output.rows, rows, provenance)
    tables.write_csv(smk.output.summary, summary, provenance)
    readings = openworld.by_reading(rows)
    runner.LOG.info("per reading variant:\n%s", readings.to_string())
    tables.write_csv(smk.output.readings, readings, provenance)
    fig, axes = figures.new_figure(width=6.5, height=6.0)
    scoring.outcome_panel(axes[0, 0], openworld.ARM, rows, summary)
    figures.save(fig, smk.output.png, smk.output.pdf)


runner.run(snakemake, stage)
