"""Statistics stage of seed 000 §2.5: Kruskal–Wallis across springs (with ε² and its largest
value for the groups' sizes), Dunn's post hoc tests between every pair (z, p unadjusted and
Bonferroni-adjusted, Cliff's δ with its interval at the Bonferroni level), the study's marks.
These treat the springs as independent samples, as the study did; the paired analysis of the
design that was run is ``phantom.study.paired``.

Each test is run twice: on every included stride, outliers kept, as W.S.B. et al. did
(``as_study``), and without the strides flagged as outliers in that metric (``without_outliers``,
the sensitivity analysis; ``phantom.study.outliers``).
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np
import pandas as pd

from exobench.phantom.study import effect_sizes
from exobench.phantom.study.kept import SPRING, included

# scipy.stats and statsmodels are imported where the tests run: the rules that only need summary()
# start seconds faster.

P_ADJUST = "bonferroni"  # the study's correction (§2.5)
ANALYSES = {
    "as_study": "every included stride, outliers kept (as W.S.B. et al.)",
    "without_outliers": "the strides flagged as outliers in the metric left out (sensitivity)",
}
DUNN_COLUMNS = ["metric", "analysis", "spring_a_N_per_m", "spring_b_N_per_m", "n_a", "n_b", "z",
                "p_unadjusted", "p_adjusted", "p_adjust_method", "cliffs_delta",
                "cliffs_delta_ci_low", "cliffs_delta_ci_high", "cliffs_delta_ci_level"]  # fmt: skip


def kruskal(values: pd.Series, groups: pd.Series) -> dict[str, float]:
    """H, df, p, n, ε² = H/(n − 1) ≤ (n³ − Σnᵢ³)/(n(n² − 1)), η²_H = (H − k + 1)/(n − k)."""
    samples = [v.to_numpy() for _, v in values.groupby(groups, sort=True)]
    from scipy import stats

    statistic, p = stats.kruskal(*samples)
    n = int(values.size)
    k = len(samples)
    return {"H": float(statistic), "df": k - 1, "p": float(p), "n": n,
            "epsilon2": float(effect_sizes.epsilon_squared(statistic, n)),
            "epsilon2_max": effect_sizes.epsilon_squared_max([v.size for v in samples]),
            "eta2_H": float(effect_sizes.eta_squared_h(statistic, k, n))}  # fmt: skip


def dunn_z(values: pd.Series, groups: pd.Series) -> pd.DataFrame:
    """Dunn's z of every pair (column group minus row group), groups sorted: (R̄_b − R̄_a)/σ,
    σ² = [n(n+1)/12 − Σ(t³ − t)/(12(n − 1))]·(1/n_a + 1/n_b), ranks over all groups pooled."""
    x = values.to_numpy(float)
    ranks = values.astype(float).rank(method="average")
    n = x.size
    _, ties = np.unique(x, return_counts=True)
    spread = n * (n + 1) / 12.0 - np.sum(ties**3 - ties) / (12.0 * (n - 1))
    mean = ranks.groupby(groups.to_numpy()).mean().sort_index()
    size = ranks.groupby(groups.to_numpy()).size().sort_index().to_numpy(float)
    sigma = np.sqrt(spread * (1.0 / size[:, None] + 1.0 / size[None, :]))
    z = (mean.to_numpy()[None, :] - mean.to_numpy()[:, None]) / sigma
    return pd.DataFrame(z, index=mean.index, columns=mean.index)


def dunn_table(values: pd.Series, groups: pd.Series, alpha: float = 0.05,
               p_adjust: str = P_ADJUST) -> pd.DataFrame:  # fmt: skip
    """Dunn's z and p = 2Φ(−|z|) per pair, adjusted over m, Cliff's δ with its 1 − α/m interval."""
    from scipy.stats import norm
    from statsmodels.stats.multitest import multipletests

    z = dunn_z(values, groups)
    samples = {g: v.to_numpy(float) for g, v in values.groupby(groups.to_numpy(), sort=True)}
    labels = list(z.index)
    pairs = [(a, b) for i, a in enumerate(labels) for b in labels[i + 1 :]]
    table = pd.DataFrame({
        "spring_a_N_per_m": [a for a, _ in pairs], "spring_b_N_per_m": [b for _, b in pairs],
        "n_a": [samples[a].size for a, _ in pairs], "n_b": [samples[b].size for _, b in pairs],
        "z": [float(z.loc[a, b]) for a, b in pairs],
    })  # fmt: skip
    table["p_unadjusted"] = 2.0 * norm.sf(table["z"].abs().to_numpy())
    table["p_adjusted"] = multipletests(table["p_unadjusted"], method=p_adjust)[1]
    table["p_adjust_method"] = p_adjust
    theta = np.array([effect_sizes.mann_whitney_theta(samples[a], samples[b]) for a, b in pairs])
    level = 1.0 - alpha / max(len(pairs), 1)
    delta = effect_sizes.cliffs_delta(
        theta, table["n_a"].to_numpy(), table["n_b"].to_numpy(), level
    )
    table["cliffs_delta"], table["cliffs_delta_ci_low"], table["cliffs_delta_ci_high"] = delta
    table["cliffs_delta_ci_level"] = level
    return table


def bonferroni_matrix(values: pd.Series, groups: pd.Series) -> pd.DataFrame:
    """Bonferroni-adjusted two-sided Dunn p of every pair from :func:`dunn_z`, min(1, m·2Φ(−|z|))
    over the m pairs: scikit-posthocs' values (``tests/test_phantom_statistics.py``) without its
    import, for a decision on other values of the same strides."""
    from math import erfc, sqrt

    z = dunn_z(values, groups)
    k = len(z)
    two_sided = np.vectorize(lambda v: erfc(abs(v) / sqrt(2.0)))(z.to_numpy())
    p = np.minimum(1.0, k * (k - 1) / 2 * two_sided)
    return pd.DataFrame(p, index=z.index, columns=z.columns)


def adjusted_matrix(table: pd.DataFrame) -> pd.DataFrame:
    """The adjusted p of a long Dunn table as a symmetric matrix (1 on the diagonal)."""
    labels = sorted(set(table["spring_a_N_per_m"]) | set(table["spring_b_N_per_m"]))
    matrix = pd.DataFrame(1.0, index=labels, columns=labels)
    for a, b, p in table[["spring_a_N_per_m", "spring_b_N_per_m", "p_adjusted"]].itertuples(
        index=False
    ):
        matrix.loc[a, b] = matrix.loc[b, a] = p
    return matrix


def notation(matrix: pd.DataFrame, alpha: float) -> dict[object, str]:
    """Seed 000's marks per group: (i) = differs from group i (1-based), (*) = from all others."""
    labels = list(matrix.index)
    marks = {}
    for row, label in enumerate(labels):
        differs = [
            col for col in range(len(labels)) if col != row and matrix.iloc[row, col] < alpha
        ]
        if len(labels) > 1 and len(differs) == len(labels) - 1:
            marks[label] = "(*)"
        else:
            marks[label] = "".join(f"({col + 1})" for col in differs)
    return marks


def flagged(metrics: pd.DataFrame, metric: str) -> pd.Series:
    """Whether each stride is an outlier in ``metric`` (the table's ``outlier_metrics``)."""
    if "outlier_metrics" not in metrics:
        return pd.Series(False, index=metrics.index)
    names = metrics["outlier_metrics"].fillna("").astype(str)
    return names.map(lambda listed: metric in listed.split(";"))


def analysed(metrics: pd.DataFrame, column: str, analysis: str) -> pd.DataFrame:
    """The strides one analysis tests (:data:`ANALYSES`): the metric and the spring."""
    kept = included(metrics)
    if analysis == "without_outliers":
        kept = kept[~flagged(kept, column)]
    return kept[[column, SPRING]].dropna()


def test_all(metrics: pd.DataFrame, columns: Sequence[str], alpha: float, draws: int,
             seed: int):  # fmt: skip
    """Kruskal–Wallis rows, Dunn tables and marks per metric, as the study and without outliers."""
    rows, tables, marks = [], {}, []
    for index, column in enumerate(columns):
        parts = []
        every = len(analysed(metrics, column, "as_study"))
        for code, analysis in enumerate(ANALYSES):
            data = analysed(metrics, column, analysis)
            removed = every - len(data)
            if analysis != "as_study" and removed == 0:
                continue
            rng = np.random.default_rng([seed, index, code])
            codes = pd.factorize(data[SPRING], sort=True)[0]
            low, high = effect_sizes.effect_interval(data[column].to_numpy(), codes, draws, rng)
            test = kruskal(data[column], data[SPRING])
            rows.append({"metric": column, "analysis": analysis, **test, "epsilon2_ci_low": low,
                         "epsilon2_ci_high": high, "outliers_left_out": removed})  # fmt: skip
            pairs = dunn_table(data[column], data[SPRING], alpha)
            parts.append(pairs.assign(metric=column, analysis=analysis))
            if analysis == "as_study":
                for spring, mark in notation(adjusted_matrix(pairs), alpha).items():
                    marks.append({"metric": column, SPRING: spring, "notation": mark})
        tables[column] = pd.concat(parts, ignore_index=True)[DUNN_COLUMNS]
    return pd.DataFrame(rows), tables, pd.DataFrame(marks)


def summary(metrics: pd.DataFrame, columns: Sequence[str], validity=None) -> pd.DataFrame:
    """Median, quartiles, IQR, mean, SD, n, outliers and invalid slopes per spring and metric."""
    from exobench.phantom.chain.metrics import invalid_counts

    kept = included(metrics)
    left_out = {}
    if validity is not None:
        table = invalid_counts(metrics, validity)
        left_out = {(m, s): n for m, s, n in table.itertuples(index=False)}
    rows = []
    for column in columns:
        outlying = flagged(kept, column)
        for spring, values in kept.groupby(SPRING, sort=True)[column]:
            v = values.dropna().to_numpy()
            q1, median, q3 = np.percentile(v, [25, 50, 75]) if v.size else (np.nan,) * 3
            rows.append(
                {
                    "metric": column,
                    SPRING: spring,
                    "median": median,
                    "q1": q1,
                    "q3": q3,
                    "iqr": q3 - q1,
                    "mean": float(np.mean(v)) if v.size else np.nan,
                    "sd": float(np.std(v, ddof=1)) if v.size > 1 else np.nan,
                    "n": int(v.size),
                    "outliers": int(outlying.loc[values.index].sum()),
                    "invalid": int(left_out.get((column, spring), 0)),
                }
            )
    return pd.DataFrame(rows)
