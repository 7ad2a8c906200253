"""Rule phantom_discrepancy_figure: measured vs rigid baseline vs extended model."""

import json
from pathlib import Path

from matplotlib import pyplot as plt

from exobench import figures, runner, tables
from exobench.phantom import plots


def stage(smk, provenance):
    fig = plots.discrepancy(
        tables.read_table(smk.input.predictions).data,
        json.loads(Path(smk.input.recordings).read_text()),
        json.loads(Path(smk.input.reported).read_text()),
    )
    figures.save(fig, smk.output.png, smk.output.pdf)
    plt.close(fig)


runner.run(snakemake, stage)
