"""Rule phantom_terms_figure: what the extended model leaves in the knee moment, and the
residual each discovered term explains, before and after."""

import json
from pathlib import Path

from exobench import figures, tables
from exobench.phantom.report import discovery_plots, discrepancy_captions
from exobench.plumbing import runner


def stage(smk, provenance):
    report = json.loads(Path(smk.input.recordings).read_text())
    predictions = tables.read_table(smk.input.predictions).data
    terms = tables.read_table(smk.input.terms).data
    drawn = (
        discovery_plots.terms_figure(terms, predictions, report),
        discrepancy_captions.terms(predictions, report),
    )
    figures.publish(smk.output, smk.params.figures, {"discrepancy_terms": drawn})


runner.run(snakemake, stage)
