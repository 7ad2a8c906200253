"""Statistics stage of seed 000 §2.5: Kruskal–Wallis across springs, Dunn's post hoc tests."""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np
import pandas as pd

# scipy.stats and scikit_posthocs (which pulls in statsmodels) are imported where the tests run:
# the rules that only need SPRING, included() or summary() start seconds faster.

SPRING = "spring_stiffness_N_per_m"


def kruskal(values: pd.Series, groups: pd.Series) -> dict[str, float]:
    """Kruskal–Wallis H (tie-corrected), degrees of freedom, p and n over the groups."""
    samples = [v.to_numpy() for _, v in values.groupby(groups, sort=True)]
    from scipy import stats

    statistic, p = stats.kruskal(*samples)
    return {"H": float(statistic), "df": len(samples) - 1, "p": float(p), "n": int(values.size)}


def dunn(values: pd.Series, groups: pd.Series, p_adjust: str = "bonferroni") -> pd.DataFrame:
    """Two-sided Dunn p-values (adjusted) between every pair of groups, groups sorted."""
    frame = pd.DataFrame({"value": values.to_numpy(), "group": groups.to_numpy()})
    import scikit_posthocs

    matrix = scikit_posthocs.posthoc_dunn(
        frame, val_col="value", group_col="group", p_adjust=p_adjust
    )
    order = sorted(matrix.index)
    return matrix.loc[order, order]


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


def included(metrics: pd.DataFrame) -> pd.DataFrame:
    """Strides kept for the statistics: included ones (seed 000 §2.4)."""
    return metrics[metrics["included"].astype(bool)]


def test_all(metrics: pd.DataFrame, columns: Sequence[str], alpha: float):
    """Kruskal–Wallis table, Dunn matrices and significance marks for every metric column."""
    kept = included(metrics)
    rows, matrices, marks = [], {}, []
    for column in columns:
        data = kept[[column, SPRING]].dropna()
        rows.append({"metric": column, **kruskal(data[column], data[SPRING])})
        matrices[column] = dunn(data[column], data[SPRING])
        for spring, mark in notation(matrices[column], alpha).items():
            marks.append({"metric": column, SPRING: spring, "notation": mark})
    return pd.DataFrame(rows), matrices, pd.DataFrame(marks)


def summary(metrics: pd.DataFrame, columns: Sequence[str]) -> pd.DataFrame:
    """Median, quartiles, IQR, mean, SD and n per spring and metric (included strides)."""
    kept = included(metrics)
    rows = []
    for column in columns:
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
                }
            )
    return pd.DataFrame(rows)
