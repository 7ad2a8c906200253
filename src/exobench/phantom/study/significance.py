"""W.S.B. et al.'s significance statements (§3, ``seed000_significance.csv``) against the
reproduced tests: one row per spring pair a statement calls different or not, and one per
statement that names no pair (its omnibus tests beside it, not compared).

Each pair is decided by every analysis: the study's own (Dunn, Bonferroni-adjusted p below α,
the springs as independent samples), the paired one of the design run (Wilcoxon signed-rank on
the strides matched by trajectory, Bonferroni; ``phantom.study.paired``) with the metric's
Friedman test and mixed model beside it, and, for every pair the study calls not different,
the paired two one-sided tests within the metric's margin (equivalent when their p is below α).
The study's conclusion depends on ignoring the pairing when the unpaired test gives the study's
decision and the paired one does not; a statement depends on it when every pair it names
agrees with the unpaired test and at least one is decided otherwise paired. A pair the paired
test calls different and the TOST equivalent is "different but equivalent within ±Δ".

``compare`` takes ``paired`` (per metric its Wilcoxon pairs), ``omnibus`` (per metric Friedman
and mixed model), ``tost`` (per (metric, a, b) of a not-different pair its margin, source and
p), ``settings`` (alpha, study_n, power) and ``truth`` (per metric the adjusted-p matrix of the
twin's true values of the same strides).

Where the study's decision is not what the design-respecting analysis gives, the cause is the
first reading that holds, in this order:

- ``design (pairing)``: the unpaired test gives the study's decision and the paired one does
  not (``depends_on_ignoring_pairing``); where the paired test gives the study's decision and
  only the reproduced unpaired test misses it, the study's decision is the design's: no cause,
  the miss is written in ``detail``;
- ``the chain``: on the twin's true values of the same strides the decision is the study's, on
  the chain's measurement it is not (only with the twin: its truth files);
- ``power``: the study calls the pair not different, and a power calculation gives its own test
  (its n per spring, Bonferroni over the pairs) less than the configured power at the
  reproduced effect (Cliff's δ as a normal shift d = √2·Φ⁻¹((δ + 1)/2), statsmodels'
  ``NormalIndPower``);
- ``unexplained``: no reading above holds; no effect is named, so none is blamed.
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
    "cliffs_delta_ci_level",
    "without_outliers",
    "paired",
    "paired_p_adjusted",
    "paired_median_difference",
    "friedman_p",
    "mixed_model",
    "mixed_p",
    "tost_margin",
    "tost_margin_source",
    "tost_p",
    "equivalent",
    "depends_on_ignoring_pairing",
    "study_power",
    "cause",
    "detail",
    "claim",
    "stated_test",
]
DIFFERENT, ALIKE = "different", "not different"
CAUSES = ("design (pairing)", "the chain", "power", "unexplained")


def decision(p: float, alpha: float) -> str:
    """'different' when the adjusted p is below α, else 'not different'."""
    return DIFFERENT if p < alpha else ALIKE


def study_power(delta: float, n: float, alpha: float, pairs_tested: int) -> float:
    """Power of a two-sided α/m z-test at d = √2·Φ⁻¹((δ + 1)/2), n per spring (NormalIndPower)."""
    from scipy.stats import norm
    from statsmodels.stats.power import NormalIndPower

    theta = float(np.clip((delta + 1.0) / 2.0, 1e-12, 1 - 1e-12))
    d = abs(np.sqrt(2.0) * norm.ppf(theta))
    if d == 0:
        return alpha / pairs_tested
    return float(NormalIndPower().power(d, nobs1=n, alpha=alpha / pairs_tested, ratio=1.0))


def compare(
    statements: pd.DataFrame,
    dunn: Mapping[str, pd.DataFrame],
    kruskal: pd.DataFrame,
    paired: Mapping[str, pd.DataFrame],
    omnibus: pd.DataFrame,
    tost: Mapping[tuple, Mapping],
    settings: Mapping,
    truth: Mapping[str, pd.DataFrame] | None = None,
) -> pd.DataFrame:
    """One row per named pair (or per statement naming none): each analysis's decision, cause."""
    rows = []
    whole = omnibus.set_index("metric")
    for entry in statements.to_dict("records"):
        metric = entry["metric"]
        head = {k: entry[k] for k in ("statement", "metric", "section", "claim", "stated_test")}
        named = [(p, DIFFERENT) for p in pairs(entry["different"])]
        named += [(p, ALIKE) for p in pairs(entry["not_different"])]
        overall = _overall(whole.loc[metric], settings["alpha"])
        if not named:
            rows.append({**head, **overall, **_omnibus(kruskal, metric)})
            continue
        tests = dunn[metric]
        m = len(tests[tests["analysis"] == "as_study"])
        for (a, b), study in named:
            row = _pair(tests, paired[metric], a, b, study, settings["alpha"])
            row.update(overall)
            row.update(tost.get((metric, a, b), {}))
            if study == ALIKE:
                row["study_power"] = study_power(
                    row["cliffs_delta"], settings["study_n"], settings["alpha"], m
                )
                row["equivalent"] = equivalence(row, settings["alpha"])
            row["cause"], row["detail"] = cause(
                row, settings, None if truth is None else truth[metric]
            )
            rows.append({**head, **row})
    return pd.DataFrame(rows, columns=COLUMNS)


def equivalence(row: Mapping, alpha: float) -> str:
    """TOST's word: equivalent when p_TOST < α, "different but equivalent" if paired p < α too."""
    if not row["tost_p"] < alpha:
        return "not shown equivalent"
    if row["paired"] == DIFFERENT:
        return f"different but equivalent within ±{row['tost_margin']:g}"
    return "equivalent"


def _overall(row: pd.Series, alpha: float) -> dict:
    """The metric's Friedman p and the mixed model's decision (p_mixed < α) across the springs."""
    mixed = row["mixed_p"]
    return {"friedman_p": row["friedman_p"], "mixed_p": mixed,
            "mixed_model": "" if not np.isfinite(mixed) else
            ("springs differ" if mixed < alpha else "no spring effect shown")}  # fmt: skip


def _omnibus(kruskal: pd.DataFrame, metric: str) -> dict:
    """A statement naming no pair: its Kruskal–Wallis H test and ε² beside it, not compared."""
    row = kruskal[(kruskal["metric"] == metric) & (kruskal["analysis"] == "as_study")].iloc[0]
    return {
        "study": "no test stated",
        "reproduced": f"Kruskal–Wallis p = {row['p']:.2g}, ε² = {row['epsilon2']:.2g} "
        f"[{row['epsilon2_ci_low']:.2g}, {row['epsilon2_ci_high']:.2g}] of at most "
        f"{row['epsilon2_max']:.3g}",
        "agree": pd.NA,
        "cause": "",
        "detail": "not compared: the study states no test",
    }


def _lookup(tests: pd.DataFrame, a: float, b: float, analysis: str | None = None):
    """The row of pair (a, b) (of one analysis), or None."""
    chosen = (tests["spring_a_N_per_m"] == a) & (tests["spring_b_N_per_m"] == b)
    if analysis is not None:
        chosen &= tests["analysis"] == analysis
    rows = tests[chosen]
    return None if rows.empty else rows.iloc[0]


def _pair(tests, paired, a, b, study, alpha) -> dict:
    """One named pair: unpaired (Dunn) and paired (Wilcoxon) decisions, p_adj < α, and effects."""
    row = _lookup(tests, a, b, "as_study")
    plain = _lookup(tests, a, b, "without_outliers")
    match = _lookup(paired, a, b)
    reproduced = decision(row["p_adjusted"], alpha)
    return {
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
        "cliffs_delta_ci_level": row["cliffs_delta_ci_level"],
        "without_outliers": reproduced if plain is None else decision(plain["p_adjusted"], alpha),
        "paired": decision(match["p_adjusted"], alpha),
        "paired_p_adjusted": match["p_adjusted"],
        "paired_median_difference": match["median_difference"],
        "tost_margin": np.nan,
        "tost_margin_source": "",
        "tost_p": np.nan,
        "equivalent": "",
        "depends_on_ignoring_pairing": reproduced == study != decision(match["p_adjusted"], alpha),
        "study_power": np.nan,
        "cause": "",
        "detail": "",
    }


def cause(row: Mapping, settings: Mapping, truth: pd.DataFrame | None) -> tuple[str, str]:
    """The first cause that holds where the study's decision is not the design's, with evidence."""
    study, unpaired, paired = row["study"], row["reproduced"], row["paired"]
    if unpaired == study == paired:
        return "", ""
    effect = (
        f"unpaired Dunn adjusted p = {row['p_adjusted']:.2g}, Cliff's δ {row['cliffs_delta']:.2f} "
        f"[{row['cliffs_delta_ci_low']:.2f}, {row['cliffs_delta_ci_high']:.2f}] "
        f"({row['cliffs_delta_ci_level']:.4g} level); paired Wilcoxon adjusted p = "
        f"{row['paired_p_adjusted']:.2g}, median difference {row['paired_median_difference']:.3g}"
    )
    if paired == study:
        return "", (
            f"{effect}: the paired test, the design's, gives the study's decision; only the "
            "reproduced unpaired test misses it"
        )
    if unpaired == study:
        return "design (pairing)", (
            f"{effect}: only the unpaired test gives the study's decision; the same trajectories "
            "at every spring make the strides paired"
        )
    alpha = settings["alpha"]
    if truth is not None:
        true_p = float(truth.loc[row["spring_a_N_per_m"], row["spring_b_N_per_m"]])
        if decision(true_p, alpha) == study:
            return "the chain", (
                f"{effect}; on the twin's true values of the same strides adjusted p = "
                f"{true_p:.2g}, the study's decision: the chain's measurement changes it"
            )
    power = row["study_power"]
    if study == ALIKE and np.isfinite(power) and power < settings["power"]:
        return "power", (
            f"{effect}; at the reproduced δ the study's test (n = {settings['study_n']:g} per "
            f"spring, Bonferroni) had power {power:.2f}, below {settings['power']:g}"
        )
    return "unexplained", (
        f"{effect}: neither the pairing, the chain"
        + (f" nor power ({power:.2f})" if np.isfinite(power) else "")
        + " accounts for it; no effect of the twin is named"
    )


def counts(table: pd.DataFrame) -> dict[str, int]:
    """Statements (all pairs agree) and pairs agreeing unpaired, paired, by ignoring pairing."""
    compared = table[table["agree"].notna()]
    per_statement = compared["agree"].astype(bool).groupby(compared["statement"]).all()
    flipped = compared["depends_on_ignoring_pairing"].astype(bool).groupby(compared["statement"])
    paired = (compared["paired"] == compared["study"]).groupby(compared["statement"]).all()
    alike = compared[compared["study"] == ALIKE]
    return {
        "pairs": len(compared),
        "pairs_agree": int(compared["agree"].astype(bool).sum()),
        "pairs_paired_agree": int((compared["paired"] == compared["study"]).sum()),
        "statements": int(per_statement.size),
        "statements_agree": int(per_statement.sum()),
        "statements_paired_agree": int(paired.sum()),
        "statements_pairing": int((per_statement & flipped.any()).sum()),
        "pairs_pairing": int(compared["depends_on_ignoring_pairing"].astype(bool).sum()),
        "alike_pairs": len(alike),
        "equivalent": int(alike["equivalent"].str.contains("equivalent within|^equivalent$").sum()),
        "different_but_equivalent": int(alike["equivalent"].str.startswith("different").sum()),
        "not_compared": int(table["agree"].isna().sum()),
    }
