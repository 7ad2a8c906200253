"""Rule phantom_summary: median, IQR, mean, SD and n per spring and metric, the outliers and the
slope values the validity rule left out."""

from exobench import tables
from exobench.phantom.chain.metrics import METRIC_COLUMNS
from exobench.phantom.study import statistics
from exobench.plumbing import runner


def stage(smk, provenance):
    metrics = tables.read_table(smk.input.metrics).data
    tables.write_csv(
        smk.output[0],
        statistics.summary(metrics, METRIC_COLUMNS, smk.params.slope_validity),
        provenance,
    )


runner.run(snakemake, stage)
