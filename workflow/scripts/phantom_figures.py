"""Rule phantom_figures: seed 000 figures 5–11 as PNG (report) and PDF (papers)."""

import pandas as pd
from matplotlib import pyplot as plt

from exobench import figures, runner, tables
from exobench.phantom import plots


def stage(smk, provenance):
    drawing = plots.Figures(
        tables.read_table(smk.input.curves).data,
        pd.read_csv(smk.input.summary),
        pd.read_csv(smk.input.notation, keep_default_na=False),
        smk.params.protocol,
    )
    for name, draw in plots.FIGURES.items():
        fig = draw(drawing)
        figures.save(fig, smk.output[f"{name}_png"], smk.output[f"{name}_pdf"])
        plt.close(fig)


runner.run(snakemake, stage)
