"""W.S.B. et al.'s significance statements (§3, ``seed000_significance.csv``) against the
reproduced Dunn tests: one row per spring pair a statement calls different or not, and one per
statement that names no pair (its Kruskal–Wallis test beside it, not compared).

A pair is reproduced as different when its Bonferroni-adjusted Dunn p is below α (the study's
own test). Where reproduction and study disagree, the cause is, in this order:

- ``the chain``: on the twin's true values of the same strides the decision is the study's, on
  the chain's measurement it is not (only with the twin: its truth files);
- ``sample size``: the decision flips within the reproduction's own 95 % interval of Cliff's δ:
  the interval holds effects on both sides of the smallest |δ| the study's test detects at its
  sample size, δ* = z(1 − α/(2m))·√((2n + 1)/(3n²)) (n strides per spring, m pairs; the
  Mann–Whitney z of δ under no effect);
- ``an effect the twin lacks``: otherwise, with the twin: its strides, measured without error,
  separate (or fail to separate) the two springs beyond what sampling explains; the twin lacks
  whatever makes the study's springs differ (or alike);
- ``the recordings``: the same with a lab's recordings, which hold no truth to tell the rig
  from the chain.
"""

from __future__ import annotations

from collections.abc import Mapping

import numpy as np
import pandas as pd

from exobench.phantom.reference import pairs

COLUMNS = [
    "statement",
    "metric",
    "section",
    "spring_a_N_per_m",
    "spring_b_N_per_m",
    "study",
    "reproduced",
    "agree",
    "p_adjusted",
    "z",
    "cliffs_delta",
    "cliffs_delta_ci_low",
    "cliffs_delta_ci_high",
    "without_outliers",
    "cause",
    "detail",
    "claim",
    "stated_test",
]
DIFFERENT, ALIKE = "different", "not different"


def smallest_detected(n: float, alpha: float, pairs_tested: int) -> float:
    """δ* = z(1 − α/(2m))·√((2n + 1)/(3n²)): the smallest |Cliff's δ| a Bonferroni-adjusted
    test of two springs of n strides each detects."""
    from statistics import NormalDist

    z = NormalDist().inv_cdf(1 - alpha / (2 * pairs_tested))
    return float(z * np.sqrt((2 * n + 1) / (3 * n**2)))


def decision(p: float, alpha: float) -> str:
    """'different' when the adjusted p is below α, else 'not different'."""
    return DIFFERENT if p < alpha else ALIKE


def within_reach(study: str, low: float, high: float, threshold: float) -> bool:
    """Whether δ's interval holds an effect that gives the study's decision at its sample size."""
    ends = np.abs([low, high])
    if study == DIFFERENT:
        return bool(ends.max() >= threshold)
    return bool(low <= 0.0 <= high or ends.min() < threshold)


def compare(
    statements: pd.DataFrame,
    dunn: Mapping[str, pd.DataFrame],
    kruskal: pd.DataFrame,
    alpha: float,
    study_n: float,
    truth: Mapping[str, pd.DataFrame] | None = None,
) -> pd.DataFrame:
    """One row per pair each statement names (and one per statement naming none), the study's
    decision beside the reproduced one, whether they agree and, where not, the cause;
    ``truth``: per metric the adjusted-p matrix of the twin's true values of the same strides."""
    rows = []
    for entry in statements.to_dict("records"):
        metric = entry["metric"]
        tests = dunn[metric]
        head = {k: entry[k] for k in ("statement", "metric", "section", "claim", "stated_test")}
        named = [(p, DIFFERENT) for p in pairs(entry["different"])]
        named += [(p, ALIKE) for p in pairs(entry["not_different"])]
        if not named:
            rows.append({**head, **_omnibus(kruskal, metric)})
            continue
        threshold = smallest_detected(study_n, alpha, len(tests[tests["analysis"] == "as_study"]))
        for (a, b), study in named:
            rows.append(
                {
                    **head,
                    **_pair(
                        tests,
                        a,
                        b,
                        study,
                        alpha,
                        threshold,
                        None if truth is None else truth[metric],
                    ),
                }
            )
    return pd.DataFrame(rows, columns=COLUMNS)


def _omnibus(kruskal: pd.DataFrame, metric: str) -> dict:
    """A statement naming no pair: the study's words beside the Kruskal–Wallis test, not
    compared."""
    row = kruskal[(kruskal["metric"] == metric) & (kruskal["analysis"] == "as_study")].iloc[0]
    return {
        "study": "no test stated",
        "reproduced": f"Kruskal–Wallis p = {row['p']:.2g}, ε² = {row['epsilon2']:.2g} "
        f"[{row['epsilon2_ci_low']:.2g}, {row['epsilon2_ci_high']:.2g}]",
        "agree": pd.NA,
        "cause": "",
        "detail": "not compared: the study states no test",
    }


def _lookup(tests: pd.DataFrame, a: float, b: float, analysis: str):
    rows = tests[
        (tests["analysis"] == analysis)
        & (tests["spring_a_N_per_m"] == a)
        & (tests["spring_b_N_per_m"] == b)
    ]
    return None if rows.empty else rows.iloc[0]


def _pair(tests, a, b, study, alpha, threshold, truth) -> dict:
    """One pair the study names: both decisions, the effect, the sensitivity decision, and the
    cause of a disagreement."""
    row = _lookup(tests, a, b, "as_study")
    plain = _lookup(tests, a, b, "without_outliers")
    reproduced = decision(row["p_adjusted"], alpha)
    out = {
        "spring_a_N_per_m": a,
        "spring_b_N_per_m": b,
        "study": study,
        "reproduced": reproduced,
        "agree": reproduced == study,
        "p_adjusted": row["p_adjusted"],
        "z": row["z"],
        "cliffs_delta": row["cliffs_delta"],
        "cliffs_delta_ci_low": row["cliffs_delta_ci_low"],
        "cliffs_delta_ci_high": row["cliffs_delta_ci_high"],
        "without_outliers": reproduced if plain is None else decision(plain["p_adjusted"], alpha),
        "cause": "",
        "detail": "",
    }
    if reproduced != study:
        out["cause"], out["detail"] = cause(out, alpha, threshold, truth)
    return out


def cause(row: Mapping, alpha: float, threshold: float, truth: pd.DataFrame | None):
    """The cause of a disagreement and the evidence, in words (see the module's docstring)."""
    effect = (
        f"Cliff's δ {row['cliffs_delta']:.2f} [{row['cliffs_delta_ci_low']:.2f}, "
        f"{row['cliffs_delta_ci_high']:.2f}], adjusted p = {row['p_adjusted']:.2g}"
    )
    if truth is not None:
        true_p = float(truth.loc[row["spring_a_N_per_m"], row["spring_b_N_per_m"]])
        if decision(true_p, alpha) == row["study"]:
            return "the chain", (
                f"{effect}; on the twin's true values of the same strides "
                f"adjusted p = {true_p:.2g}, the study's decision: the chain's "
                "measurement changes it"
            )
    if within_reach(
        row["study"], row["cliffs_delta_ci_low"], row["cliffs_delta_ci_high"], threshold
    ):
        return "sample size", (
            f"{effect}: the interval holds effects on both sides of the "
            f"smallest |δ| the study's test detects ({threshold:.2f}), so its "
            "decision lies within the reproduction's own uncertainty"
        )
    if truth is None:
        return "the recordings", (
            f"{effect}: beyond sampling; the recordings' springs differ "
            "otherwise than the study's (no truth tells the rig from the "
            "chain)"
        )
    return "an effect the twin lacks", (
        f"{effect}, on the twin's true values alike: beyond "
        "sampling, the twin's springs differ otherwise than the "
        "study's"
    )


def counts(table: pd.DataFrame) -> dict[str, int]:
    """Statements and pair claims compared, and how many agree (a statement agrees when every
    pair it names does; statements naming no pair are not compared)."""
    compared = table[table["agree"].notna()]
    per_statement = compared.groupby("statement")["agree"].all()
    return {
        "pairs": len(compared),
        "pairs_agree": int(compared["agree"].astype(bool).sum()),
        "statements": int(per_statement.size),
        "statements_agree": int(per_statement.sum()),
        "not_compared": int(table["agree"].isna().sum()),
    }
