"""Rule phantom_statistics: Kruskal–Wallis (with ε², its largest value and its interval, η²_H),
Dunn in long form (z, p unadjusted and Bonferroni-adjusted, Cliff's δ with its interval at the
Bonferroni level) and significance marks, as the study did and without each metric's outliers;
beside them the paired analysis of the design run (Friedman, mixed model, trial model per
metric; Wilcoxon pairs)."""

from exobench.plumbing import jobserver

jobserver.delegate()

from pathlib import Path

from exobench import tables
from exobench.phantom.chain.metrics import METRIC_COLUMNS
from exobench.phantom.study import paired, statistics
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
    omnibus, pairs = paired.test_all(metrics, METRIC_COLUMNS, settings["alpha"])
    runner.LOG.info(
        "paired: Friedman p < %g in %d of %d metrics; Wilcoxon pairs adjusted p < %g: %d of %d",
        settings["alpha"],
        int((omnibus["friedman_p"] < settings["alpha"]).sum()),
        len(omnibus),
        settings["alpha"],
        int((pairs["p_adjusted"] < settings["alpha"]).sum()),
        len(pairs),
    )
    tables.write_csv(smk.output.paired, omnibus, provenance)
    tables.write_csv(smk.output.wilcoxon, pairs, provenance)


runner.run(snakemake, stage)
