"""Reproduction table: every number seed 000 reports against the workflow's result."""

from __future__ import annotations

import numpy as np
import pandas as pd

from exobench.phantom.study.statistics import SPRING, included

COLUMNS = ["metric", SPRING, "reported", "reproduced", "unit", "abs_error", "rel_error", "source"]


def reproduced_value(metric: str, spring: float, metrics: pd.DataFrame, medians) -> float:
    """The workflow's counterpart of one reported number (``medians``: per spring, included)."""
    per_trial = metrics.groupby("trial")
    if metric == "strides_analysed":
        return float(per_trial["peak_moment_Nm"].count().median())
    if metric == "strides_kept":
        return float(per_trial["included"].sum().median())
    if metric == "phantom_stance_flexion_median_difference_deg":
        column = medians["phantom_stance_flexion_deg"]
        return float(column.iloc[0] - column.iloc[-1])
    if metric == "work_spring_net_abs_max_J":
        return float(medians["work_spring_net_J"].abs().max())
    if metric not in medians.columns or spring not in medians.index:
        return np.nan
    return float(medians.loc[spring, metric])


def compare(reported: pd.DataFrame, metrics: pd.DataFrame) -> pd.DataFrame:
    """One row per reported number: reported, reproduced, absolute and relative error."""
    table = reported.rename(columns={"value": "reported", "spring_stiffness_N_per_m": SPRING})
    medians = included(metrics).groupby(SPRING).median(numeric_only=True)
    table["reproduced"] = [
        reproduced_value(m, s, metrics, medians)
        for m, s in zip(table["metric"], table[SPRING], strict=True)
    ]
    table["abs_error"] = (table["reproduced"] - table["reported"]).abs()
    table["rel_error"] = table["abs_error"] / table["reported"].abs()
    return table[COLUMNS]
