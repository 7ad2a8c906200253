"""Rule phantom_statistics: Kruskal–Wallis, Dunn (Bonferroni) and significance marks."""

from pathlib import Path

from exobench import tables
from exobench.phantom.chain.metrics import METRIC_COLUMNS
from exobench.phantom.study import statistics
from exobench.plumbing import runner


def stage(smk, provenance):
    metrics = tables.read_table(smk.input.metrics).data
    kruskal, matrices, marks = statistics.test_all(metrics, METRIC_COLUMNS, smk.params.alpha)
    tables.write_csv(smk.output.kruskal, kruskal, provenance)
    tables.write_csv(smk.output.notation, marks, provenance)
    for path in smk.output.dunn:
        tables.write_csv(path, matrices[Path(path).stem], provenance, index=True)


runner.run(snakemake, stage)
