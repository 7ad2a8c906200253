"""Rule phantom_figures: figures 5–11 of W.S.B. et al. as PNG (report) and PDF (papers), each with
its caption file."""

import pandas as pd
from matplotlib import pyplot as plt

from exobench import figures, tables
from exobench.phantom.report import plots
from exobench.plumbing import runner


def stage(smk, provenance):
    drawing = plots.Figures(
        tables.read_table(smk.input.curves).data,
        pd.read_csv(smk.input.summary),
        pd.read_csv(smk.input.notation, keep_default_na=False),
        smk.params.protocol,
        smk.params.alpha,
    )
    for name, draw in plots.FIGURES.items():
        fig, caption = draw(drawing)
        figures.save(fig, smk.output[f"{name}_png"], smk.output[f"{name}_pdf"])
        figures.write_caption(smk.output[f"{name}_caption"], *caption)
        plt.close(fig)


runner.run(snakemake, stage)
