"""Outlying strides, named and kept: a stride whose metric lies far beyond its spring's spread.

Per spring and metric, over the included strides: robust z = (x − median)/s with s = 1.4826·MAD
(the SD of normal data; where half the strides share one value, s = 1.2533 × the mean absolute
deviation from the median instead, Iglewicz & Hoaglin's fallback). A stride is an outlier in a
metric when |z| exceeds the config's ``phantom.statistics.outlier_robust_z``. Outliers stay in
the statistics, as W.S.B. et al. kept every included stride; the statistics are also given without
them (the sensitivity rows of ``stats/``).
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np
import pandas as pd

from exobench.phantom.study.kept import SPRING, included
from exobench.tables import unit_for

FLEXION = "phantom_stance_flexion_deg"  # what the programme varies stride to stride
COLUMNS = [
    "trial",
    "stride",
    SPRING,
    "metric",
    "value",
    "unit",
    "spring_median",
    "robust_sd",
    "robust_z",
    "reason",
]


def robust_scale(values: pd.Series) -> float:
    """s = 1.4826·median|x − median|, or 1.2533·mean|x − median| where the MAD is zero."""
    deviation = (values - values.median()).abs()
    mad = 1.4826 * deviation.median()
    return float(mad) if mad > 0 else float(1.2533 * deviation.mean())


def robust_z(metrics: pd.DataFrame, metric: str) -> tuple[pd.Series, pd.Series, pd.Series]:
    """Robust z of every included stride's value of ``metric`` within its spring, with the
    spring's median and robust SD beside it (indexed as ``metrics``)."""
    kept = included(metrics)
    groups = kept.groupby(SPRING)[metric]
    median = groups.transform("median")
    scale = groups.transform(robust_scale)
    with np.errstate(divide="ignore", invalid="ignore"):
        z = (kept[metric] - median) / scale.where(scale > 0)
    return z, median, scale


def find(metrics: pd.DataFrame, columns: Sequence[str], threshold: float) -> pd.DataFrame:
    """Every (stride, metric) whose |robust z| exceeds ``threshold``, with the reason in words."""
    flexion = robust_z(metrics, FLEXION)[1] if FLEXION in metrics else None
    rows = []
    for metric in columns:
        z, median, scale = robust_z(metrics, metric)
        for index in z.index[z.abs() > threshold]:
            row = metrics.loc[index]
            unit = unit_for(metric)
            context = None
            if flexion is not None and metric != FLEXION:
                context = (row[FLEXION], flexion.loc[index])
            rows.append(
                {
                    "trial": row["trial"],
                    "stride": int(row["stride"]),
                    SPRING: row[SPRING],
                    "metric": metric,
                    "value": float(row[metric]),
                    "unit": unit,
                    "spring_median": float(median.loc[index]),
                    "robust_sd": float(scale.loc[index]),
                    "robust_z": float(z.loc[index]),
                    "reason": reason(
                        metric,
                        float(row[metric]),
                        unit,
                        float(median.loc[index]),
                        float(scale.loc[index]),
                        float(z.loc[index]),
                        context,
                    ),
                }
            )
    return pd.DataFrame(rows, columns=COLUMNS)


def reason(
    metric: str,
    value: float,
    unit: str,
    median: float,
    scale: float,
    z: float,
    flexion: tuple[float, float] | None,
) -> str:
    """'exo_stiffness_Nm_per_rad 886 N·m/rad: 127 robust SD above the spring's median 174
    (robust SD 5.6); the stride's phantom stance flexion 1.12° (spring median 8.30°)'."""
    side = "above" if z > 0 else "below"
    units = "" if unit == "1" else f" {unit}"
    text = (
        f"{metric} {value:.3g}{units}: {abs(z):.3g} robust SD {side} the spring's median "
        f"{median:.3g} (robust SD {scale:.3g})"
    )
    if flexion is not None:
        text += (
            f"; the stride's phantom stance flexion {flexion[0]:.3g}° (spring median "
            f"{flexion[1]:.3g}°)"
        )
    return text


def annotate(metrics: pd.DataFrame, found: pd.DataFrame) -> pd.DataFrame:
    """The metrics table with each stride's outlying metrics (';'-joined, empty if none) and
    their reasons ('; '-joined … one reason per metric, '|'-separated)."""
    keys = pd.MultiIndex.from_frame(metrics[["trial", "stride"]])
    grouped = found.groupby(["trial", "stride"], sort=False)
    names = grouped["metric"].agg(";".join)
    reasons = grouped["reason"].agg(" | ".join)
    out = metrics.copy()
    out["outlier_metrics"] = names.reindex(keys).fillna("").to_numpy()
    out["outlier_reason"] = reasons.reindex(keys).fillna("").to_numpy()
    return out
