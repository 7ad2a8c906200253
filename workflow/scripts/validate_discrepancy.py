"""Rule validate_discrepancy: coverage, false positives and detection limits over all cases."""

import pandas as pd
from matplotlib import pyplot as plt

from exobench import figures, tables
from exobench.phantom.validation import figure, twin_arm
from exobench.plumbing import runner


def stage(smk, provenance):
    rows = pd.concat([pd.read_csv(path) for path in smk.input.batches], ignore_index=True)
    summary = twin_arm.summary(rows)
    runner.LOG.info("validation summary:\n%s", summary.to_string())
    tables.write_csv(smk.output.rows, rows, provenance)
    tables.write_csv(smk.output.summary, summary, provenance)
    fig = figure.figure(rows, summary, pd.read_csv(smk.input.openworld_rows),
                        pd.read_csv(smk.input.openworld))  # fmt: skip
    figures.save(fig, smk.output.png, smk.output.pdf)
    plt.close(fig)


runner.run(snakemake, stage)
