"""Rule phantom_discrepancy_figure: measured vs rigid baseline vs extended model (and the model
fitted to W.S.B. et al.'s medians, when the run compares with them)."""

import json
from pathlib import Path

from matplotlib import pyplot as plt

from exobench import figures, runner, tables
from exobench.phantom.report import discovery_plots, discrepancy_captions


def stage(smk, provenance):
    tables_in = (
        tables.read_table(smk.input.predictions).data,
        json.loads(Path(smk.input.recordings).read_text()),
        json.loads(Path(smk.input.reported).read_text())
        if "reported" in smk.input.keys()  # a lab run compares with the study when asked
        else None,
    )
    fig = discovery_plots.discrepancy(*tables_in)
    figures.save(fig, smk.output.png, smk.output.pdf)
    figures.write_caption(smk.output.caption, *discrepancy_captions.discrepancy(*tables_in))
    plt.close(fig)


runner.run(snakemake, stage)
