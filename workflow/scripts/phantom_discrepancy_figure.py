"""Rule phantom_discrepancy_figure: the measured peak stance moment per spring (summary.csv),
each model's error, every estimate and the work loops, measured vs rigid baseline vs extended
model (and W.S.B. et al.'s medians with the model fitted to them, when the run compares
with them)."""

import json
from pathlib import Path

import pandas as pd

from exobench import figures, tables
from exobench.phantom.report import discovery_plots, discrepancy_captions
from exobench.plumbing import runner


def stage(smk, provenance):
    compared = "reported" in smk.input.keys()  # a lab run compares with seed 000 when asked
    paper = pd.read_csv(smk.input.paper) if compared else None
    tables_in = (
        tables.read_table(smk.input.predictions).data,
        json.loads(Path(smk.input.recordings).read_text()),
        pd.read_csv(smk.input.summary),
        smk.params.protocol,
        json.loads(Path(smk.input.reported).read_text()) if compared else None,
        None if paper is None else paper[paper["metric"] == discovery_plots.PEAK],
    )
    drawn = (
        discovery_plots.discrepancy(*tables_in),
        discrepancy_captions.discrepancy(*tables_in),
    )
    figures.publish(smk.output, smk.params.figures, {"discrepancy": drawn})


runner.run(snakemake, stage)
