"""The method checking itself: every reported number the twin predicts, the twin's prediction
against the chain's measurement of the twin's own recordings.

The twin predicts a number by its calibration's simulated strides (``calibration/strides.parquet``);
the chain measures it on the recordings the twin wrote. Each is a median with its bootstrap
standard error (the calibration simulation's own spread, the recordings' stride-to-stride
spread); they differ when |z| = |chain − twin|/√(SE_chain² + SE_twin²) exceeds z(1 − α/(2m)),
m the numbers compared (Bonferroni). A difference is a finding of the method, and the twin's
true values of the same strides (``truth/``, per-stride metrics by the same definitions) say
which side is wrong: the chain, when its measurement departs from the truth of the strides it
measured (paired bootstrap: the same strides drawn for both); the twin, when its prediction
departs from that truth (its recordings are not what its calibration simulated); both; or
neither, which leaves the difference unexplained. Paired on the same strides, the chain's
departure from the truth is seen more sharply than the difference from the prediction: each
number also says whether the chain departs so (``chain_departs``), beyond or not.
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np
import pandas as pd

from exobench.phantom.study.comparison import BOUNDS, COUNTS, Medians
from exobench.phantom.study.kept import SPRING, at_spring

COLUMNS = [
    "metric",
    SPRING,
    "unit",
    "twin",
    "twin_se",
    "chain",
    "chain_se",
    "z",
    "limit",
    "beyond",
    "truth",
    "chain_minus_truth",
    "chain_minus_truth_se",
    "chain_departs",
    "twin_minus_truth",
    "twin_minus_truth_se",
    "side",
    "finding",
]


def predicted(reported: pd.DataFrame, twin: Medians, chain: Medians) -> list[tuple]:
    """(metric, spring, unit) of every reported number the twin predicts as the chain measures
    it: per-spring medians of the springs it simulates and differences of its extreme springs
    (not counts, nor bounds over springs it does not simulate)."""
    out = []
    for metric, spring, unit in reported[["metric", SPRING, "unit"]].itertuples(index=False):
        if metric in COUNTS or metric in BOUNDS:
            continue
        value = twin.value(metric, spring)
        if np.isfinite(value) and np.isfinite(chain.value(metric, spring)):
            out.append((metric, spring, unit))
    return out


def _spread(draws_a, draws_b=None) -> float:
    """SD of a bootstrap distribution (of a − b when two are given, paired draw by draw)."""
    draws = np.asarray(draws_a, float) - (0.0 if draws_b is None else np.asarray(draws_b, float))
    return float(np.std(draws, ddof=1))


def check(
    numbers: Sequence[tuple], twin: Medians, chain: Medians, truth: Medians, alpha: float
) -> pd.DataFrame:
    """One row per number: twin, chain, their z and limit, whether they differ (``beyond``), the
    truth of the chain's strides and each side's departure from it, the side that is wrong and
    the finding in words (empty where they agree)."""
    from statistics import NormalDist

    limit = float(NormalDist().inv_cdf(1 - alpha / (2 * max(len(numbers), 1))))
    rows = []
    for metric, spring, unit in numbers:
        t, c, r = (float(m.value(metric, spring)) for m in (twin, chain, truth))
        draws = {
            name: m.value(metric, spring, drawn=True)
            for name, m in (("twin", twin), ("chain", chain), ("truth", truth))
        }
        twin_se, chain_se = _spread(draws["twin"]), _spread(draws["chain"])
        z = (c - t) / np.hypot(twin_se, chain_se)
        row = {
            "metric": metric,
            SPRING: spring,
            "unit": unit,
            "twin": t,
            "twin_se": twin_se,
            "chain": c,
            "chain_se": chain_se,
            "z": z,
            "limit": limit,
            "beyond": bool(abs(z) > limit),
            "truth": r,
            "chain_minus_truth": c - r,
            "chain_minus_truth_se": _spread(draws["chain"], draws["truth"]),
            "twin_minus_truth": t - r,
            "twin_minus_truth_se": np.hypot(twin_se, _spread(draws["truth"])),
        }
        row["chain_departs"] = departs(row, "chain")
        row["side"], row["finding"] = diagnose(row) if row["beyond"] else ("", "")
        rows.append(row)
    return pd.DataFrame(rows, columns=COLUMNS)


def departs(row, side: str) -> bool:
    """Whether one side's median departs from the truth of the same strides beyond its
    uncertainty (paired for the chain), at the same limit."""
    return bool(abs(row[f"{side}_minus_truth"]) > row["limit"] * row[f"{side}_minus_truth_se"])


def diagnose(row) -> tuple[str, str]:
    """Which side departs from the truth beyond its uncertainty (at the same limit), in words."""
    chain_off, twin_off = departs(row, "chain"), departs(row, "twin")
    side = {(True, False): "chain", (False, True): "twin", (True, True): "both"}.get(
        (bool(chain_off), bool(twin_off)), "unexplained"
    )
    unit = row["unit"]
    shift = 100.0 * (row["chain"] - row["twin"]) / abs(row["twin"]) if row["twin"] else np.nan
    head = (
        f"{row['metric']}{at_spring(row[SPRING])}: the twin predicts {row['twin']:.3g} {unit}, "
        f"the chain measures {row['chain']:.3g} {unit} on the twin's recordings ({shift:+.2g} %, "
        f"z = {row['z']:.1f})"
    )
    truth = (
        f"the twin's true value over the same strides is {row['truth']:.3g} {unit}; the "
        f"chain departs from it by {row['chain_minus_truth']:+.3g} ± "
        f"{row['chain_minus_truth_se']:.2g} {unit}, the prediction by "
        f"{row['twin_minus_truth']:+.3g} ± {row['twin_minus_truth_se']:.2g} {unit}"
    )
    verdict = {
        "chain": "the chain is wrong: it does not measure what the recordings hold",
        "twin": "the twin is wrong: its recordings are not what its calibration simulated",
        "both": "both are wrong: the chain misreads the recordings and the recordings are not "
        "what the calibration simulated",
        "unexplained": "left unexplained: neither departs from the truth on its own",
    }[side]
    return side, f"{head}; {truth}: {verdict}"
