"""Rule phantom_terms_figure: what the extended model leaves in the knee moment, and the
residual each discovered term explains, before and after."""

import json
from pathlib import Path

from matplotlib import pyplot as plt

from exobench import figures, tables
from exobench.phantom.report import discovery_plots, discrepancy_captions
from exobench.plumbing import runner


def stage(smk, provenance):
    report = json.loads(Path(smk.input.recordings).read_text())
    predictions = tables.read_table(smk.input.predictions).data
    terms = tables.read_table(smk.input.terms).data
    fig = discovery_plots.terms_figure(terms, predictions, report)
    figures.save(fig, smk.output.png, smk.output.pdf)
    figures.write_caption(smk.output.caption, *discrepancy_captions.terms(predictions, report))
    plt.close(fig)


runner.run(snakemake, stage)
