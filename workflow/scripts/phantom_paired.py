"""Rule phantom_paired: the design run, analysed as run: per metric Friedman, the mixed model
y ~ spring + (1 | trajectory) and trial as a random effect (or the one-trial confound); the paired
Wilcoxon tests of every spring pair."""

from exobench import tables
from exobench.phantom.chain.metrics import METRIC_COLUMNS
from exobench.phantom.study import paired
from exobench.plumbing import runner


def stage(smk, provenance):
    metrics = tables.read_table(smk.input.metrics).data
    alpha = smk.params.alpha
    omnibus, pairs = paired.test_all(metrics, METRIC_COLUMNS, alpha, smk.params.bound_share)
    runner.LOG.info(
        "Friedman p < %g in %d of %d metrics; Wilcoxon pairs with adjusted p < %g: %d of %d",
        alpha,
        int((omnibus["friedman_p"] < alpha).sum()),
        len(omnibus),
        alpha,
        int((pairs["p_adjusted"] < alpha).sum()),
        len(pairs),
    )
    tables.write_csv(smk.output.paired, omnibus, provenance)
    tables.write_csv(smk.output.wilcoxon, pairs, provenance)


runner.run(snakemake, stage)
