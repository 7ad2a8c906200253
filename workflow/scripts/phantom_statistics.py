"""Rule phantom_statistics: Kruskal–Wallis (with ε², its largest value and its interval, η²_H),
Dunn in long form (z, p unadjusted and Bonferroni-adjusted, Cliff's δ with its interval at the
Bonferroni level) and significance marks, as the study did and without each metric's outliers."""

from pathlib import Path

from exobench import tables
from exobench.phantom.chain.metrics import METRIC_COLUMNS
from exobench.phantom.study import statistics
from exobench.plumbing import runner


def stage(smk, provenance):
    metrics = tables.read_table(smk.input.metrics).data
    settings = smk.params.statistics
    kruskal, dunn, marks = statistics.test_all(
        metrics, METRIC_COLUMNS, settings["alpha"], settings["bootstrap"], smk.params.seed
    )
    tables.write_csv(smk.output.kruskal, kruskal, provenance)
    tables.write_csv(smk.output.notation, marks, provenance)
    for path in smk.output.dunn:
        tables.write_csv(path, dunn[Path(path).stem], provenance)


runner.run(snakemake, stage)
