"""Rule validate_emulator: coverage, false positives and detection limits over all cases."""

import pandas as pd
from matplotlib import pyplot as plt

from exobench import figures, tables
from exobench.emulator.validation import twin_arm as validation
from exobench.plumbing import runner


def stage(smk, provenance):
    rows = pd.concat([pd.read_csv(path) for path in smk.input.batches], ignore_index=True)
    summary = validation.summary(rows)
    runner.LOG.info("emulator validation summary:\n%s", summary.to_string())
    tables.write_csv(smk.output.rows, rows, provenance)
    tables.write_csv(smk.output.summary, summary, provenance)
    fig = validation.figure(rows, summary)
    figures.save(fig, smk.output.png, smk.output.pdf)
    plt.close(fig)


runner.run(snakemake, stage)
