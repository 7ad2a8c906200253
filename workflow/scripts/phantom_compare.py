"""Rule phantom_compare: every number W.S.B. et al. report against the reproduced one (role,
tolerance, reason), their significance statements against the reproduced tests (unpaired as
theirs, paired as the design ran, "not different" as equivalence) and, with the twin, its
prediction of each number against the chain's measurement of its recordings."""

from pathlib import Path

import pandas as pd

from exobench import tables
from exobench.errors import InputError
from exobench.phantom import reference
from exobench.phantom.chain.metrics import METRIC_COLUMNS, SLOPES
from exobench.phantom.study import comparison, method_check, paired, significance, statistics
from exobench.phantom.twin import truth
from exobench.plumbing import runner


def twin_side(smk, metrics, reported, chain, draws):
    """The twin's calibration targets and medians, and, with its truth, the method check."""
    seed = smk.params.seed
    twin = comparison.medians(
        tables.read_table(smk.input.strides).data, METRIC_COLUMNS, draws, seed
    )
    if "truth" not in smk.input.keys():
        return None, twin, None, None
    true = truth.aligned(metrics, tables.read_table(smk.input.truth).data)
    for slope in SLOPES:  # the same strides: no true slope where the chain's was refused
        true.loc[metrics[slope].isna(), slope] = float("nan")
    true_medians = comparison.medians(true, METRIC_COLUMNS, draws, seed)
    numbers = method_check.predicted(reported, twin, chain)
    method = method_check.check(numbers, twin, chain, true_medians, smk.params.comparison["alpha"])
    targets = comparison.calibration_targets(pd.read_csv(smk.input.residuals))
    return targets, twin, method, true


def stage(smk, provenance):
    metrics = tables.read_table(smk.input.metrics).data
    reported = reference.read_reported(smk.input.reported)
    settings = smk.params.comparison
    chain = comparison.medians(metrics, METRIC_COLUMNS, settings["bootstrap"], smk.params.seed)
    targets, twin, method, true = twin_side(smk, metrics, reported, chain, settings["bootstrap"])
    table = comparison.compare(reported, chain, settings["alpha"], targets, twin, method)
    misses = table[~table["within_tolerance"]]
    runner.LOG.info(
        "%d of %d numbers reproduced within tolerance", len(table) - len(misses), len(table)
    )
    tables.write_csv(smk.output.table, table, provenance)
    if method is not None:
        runner.LOG.info("method check: %d of %d differ", method["beyond"].sum(), len(method))
        tables.write_csv(smk.output.method, method, provenance)
    statements = reference.read_significance(smk.input.significance)
    dunn = {Path(p).stem: pd.read_csv(p) for p in smk.input.dunn}
    true_p = None
    if true is not None:
        kept = statistics.included(true)
        true_p = {
            m: statistics.bonferroni_matrix(kept[m], kept[statistics.SPRING])
            for m in statements["metric"].unique()
        }
    study_n = float(reported.loc[reported["metric"] == "strides_kept", "value"].iloc[0])
    wilcoxon = pd.read_csv(smk.input.wilcoxon)
    compared = significance.compare(
        statements,
        dunn,
        pd.read_csv(smk.input.kruskal),
        {m: rows for m, rows in wilcoxon.groupby("metric")},
        pd.read_csv(smk.input.paired),
        equivalence(metrics, statements, paired.margins(smk.params.equivalence)),
        {"alpha": smk.params.alpha, "study_n": study_n, "power": smk.params.power},
        true_p,
    )
    tables.write_csv(smk.output.significance, compared, provenance)


def equivalence(metrics, statements, margins):
    """Paired TOST of every pair a statement calls not different, within its metric's margin."""
    out = {}
    for entry in statements.to_dict("records"):
        named = reference.pairs(entry["not_different"])
        if not named:
            continue
        metric = entry["metric"]
        if metric not in margins:
            raise InputError("config", f"phantom.statistics.equivalence.margins.{metric}",
                             "a margin with its source for every metric called not different",
                             "missing")  # fmt: skip
        margin, source = margins[metric]
        wide = paired.matched(metrics, metric)
        for a, b in named:
            test = paired.tost(wide, a, b, margin)
            out[(metric, a, b)] = {"tost_margin": margin, "tost_margin_source": source,
                                   "tost_p": test["tost_p"]}  # fmt: skip
    return out


runner.run(snakemake, stage)
