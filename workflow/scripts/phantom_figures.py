"""Rule phantom_figures: figures 5–11 of W.S.B. et al. as PNG (report) and PDF (papers), each with
its caption file."""

import pandas as pd

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
        pd.read_csv(smk.input.outliers),
    )
    drawn = {name: draw(drawing) for name, draw in plots.FIGURES.items()}
    figures.publish(smk.output, smk.params.figures, drawn)


runner.run(snakemake, stage)
