"""Rule phantom_summary: median, IQR, mean, SD and n per spring and metric."""

from exobench import tables
from exobench.phantom.chain.metrics import METRIC_COLUMNS
from exobench.phantom.study import statistics
from exobench.plumbing import runner


def stage(smk, provenance):
    metrics = tables.read_table(smk.input.metrics).data
    tables.write_csv(smk.output[0], statistics.summary(metrics, METRIC_COLUMNS), provenance)


runner.run(snakemake, stage)
