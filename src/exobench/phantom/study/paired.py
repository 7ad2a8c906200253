"""The design seed 000 ran, analysed as run: the same programmed trajectories at every spring
(§2: kept constant among the conditions), so a stride is matched across springs by its
trajectory (its ``stride`` number), and one trial per spring, so the spring is confounded with
the trial (order, re-mounting, the interface's state).

- Friedman's test over the trajectories complete at every spring (scipy), Kendall's
  W = χ²/(n(k − 1)) as its effect size (range 0 to 1);
- Wilcoxon signed-rank tests of every spring pair on the matched strides (scipy), p adjusted
  over the pairs (statsmodels' ``multipletests``, the study's method, named); beside each the
  median difference b − a (b the stiffer spring) and the share of trajectories where b is higher
  (ties counted half) with its Wilson interval at the adjusted level 1 − α/m (a sign-test
  quantity: it can disagree with the signed-rank test near the boundary);
- a linear mixed model y ~ spring + (1 | trajectory) (statsmodels ``MixedLM``, REML, started
  from the two-way layout's moment estimates, REML's own answer when every trajectory holds
  every spring once), the spring's Wald χ² on k − 1 degrees of freedom, the trajectory and
  residual variances; a trajectory share below ``bound_share`` is at its bound 0, and a p below
  the smallest float (:data:`P_FLOOR`) is written at the floor and flagged;
- with repeated trials per spring, trial as a random effect: the trajectory-centred values
  y − (its trajectory's mean over every trial) ~ spring + (1 | trial) gives the between-trial
  variance (MixedLM), and the spring is tested against it by the one-way F of the k·r trial
  means, df (k − 1, k(r − 1)): exact for the balanced nested design, where a Wald χ² on k − 1 df
  over-rejects; with one trial per spring the component cannot be told from the spring (stated,
  not tested);
- paired two one-sided tests (statsmodels ``ttost_paired``) of a pair's equivalence within a
  margin ±Δ.
"""

from __future__ import annotations

import warnings
from collections.abc import Mapping

import numpy as np
import pandas as pd

from exobench.phantom.study.kept import SPRING, included
from exobench.phantom.study.statistics import P_ADJUST

# the smallest positive float: a p below it underflows to 0 and is written as "< P_FLOOR"
P_FLOOR = float(np.finfo(float).tiny)
PAIR_COLUMNS = ["metric", "spring_a_N_per_m", "spring_b_N_per_m", "n_trajectories",
                "wilcoxon_W", "p_unadjusted", "p_adjusted", "p_adjust_method",
                "median_difference", "superiority", "superiority_ci_low", "superiority_ci_high",
                "interval_level"]  # fmt: skip


def matched(metrics: pd.DataFrame, column: str) -> pd.DataFrame:
    """Trajectory × spring table of one metric (repeats averaged), complete trajectories only."""
    kept = included(metrics)[["stride", SPRING, column]].dropna()
    wide = kept.pivot_table(index="stride", columns=SPRING, values=column, aggfunc="mean")
    return wide.dropna().sort_index(axis=1)


def friedman(wide: pd.DataFrame) -> dict:
    """Friedman's χ², df, p, n trajectories and Kendall's W = χ²/(n(k − 1)) (0 to 1)."""
    from scipy import stats

    values = np.asarray(wide, float)
    n, k = values.shape
    if n < 2 or k < 3:
        return {"friedman_chi2": np.nan, "friedman_df": k - 1, "friedman_p": np.nan,
                "n_trajectories": n, "kendall_W": np.nan}  # fmt: skip
    chi2, p = stats.friedmanchisquare(*values.T)
    return {"friedman_chi2": float(chi2), "friedman_df": k - 1, "friedman_p": float(p),
            "n_trajectories": n, "kendall_W": float(chi2 / (n * (k - 1)))}  # fmt: skip


def wilcoxon_pairs(wide: pd.DataFrame, alpha: float, p_adjust: str = P_ADJUST) -> pd.DataFrame:
    """Wilcoxon signed-rank test of b − a per pair, p adjusted, share b > a in a 1 − α/m CI."""
    from scipy import stats
    from statsmodels.stats.multitest import multipletests
    from statsmodels.stats.proportion import proportion_confint

    labels = list(wide.columns)
    pairs = [(a, b) for i, a in enumerate(labels) for b in labels[i + 1 :]]
    n = len(wide)
    rows = []
    for a, b in pairs:
        diff = wide[b].to_numpy(float) - wide[a].to_numpy(float)
        if np.any(diff != 0):
            result = stats.wilcoxon(diff)
            statistic, p = float(result.statistic), float(result.pvalue)
        else:
            statistic, p = np.nan, 1.0
        rows.append({"spring_a_N_per_m": a, "spring_b_N_per_m": b, "n_trajectories": n,
                     "wilcoxon_W": statistic, "p_unadjusted": p,
                     "median_difference": float(np.median(diff)) if n else np.nan,
                     "superiority": float(np.mean(diff > 0) + 0.5 * np.mean(diff == 0))
                     if n else np.nan})  # fmt: skip
    table = pd.DataFrame(rows)
    if table.empty:
        return pd.DataFrame(columns=PAIR_COLUMNS)
    table["p_adjusted"] = multipletests(table["p_unadjusted"], method=p_adjust)[1]
    table["p_adjust_method"] = p_adjust
    level = 1.0 - alpha / len(pairs)
    low, high = proportion_confint(table["superiority"] * n, n, alpha=1 - level, method="wilson")
    table["superiority_ci_low"], table["superiority_ci_high"] = low, high
    table["interval_level"] = level
    return table


def _spring_wald(result, names: list[str]) -> tuple[float, float]:
    """Wald χ² = β̂ᵀ·V⁻¹·β̂ of every spring coefficient at once (a MixedLM fit), and its p."""
    params = list(result.params.index)
    contrast = np.zeros((len(names), len(params)))
    for row, name in enumerate(names):
        contrast[row, params.index(name)] = 1.0
    test = result.wald_test(contrast, scalar=True)
    return float(np.squeeze(test.statistic)), float(np.squeeze(test.pvalue))


def _start(data: pd.DataFrame, groups: str):
    """REML start: spring means and σ²_g/σ²_e by moments, σ²_g = var(group means) − σ²_e/n_g."""
    from statsmodels.regression.mixed_linear_model import MixedLMParams

    means = data.groupby("spring")["y"].mean().sort_index()
    centred = data["y"] - data["spring"].map(means)
    by = centred.groupby(data[groups])
    effect = by.transform("mean")
    dof = len(data) - by.ngroups - len(means) + 1
    residual = float(((centred - effect) ** 2).sum()) / max(dof, 1)
    size = float(by.size().mean())
    between = max(float(by.mean().var(ddof=1)) - residual / size, 0.0) if by.ngroups > 1 else 0.0
    fe = np.r_[means.iloc[0], means.iloc[1:].to_numpy() - means.iloc[0]]
    ratio = between / residual if residual > 0 else 1.0
    return MixedLMParams.from_components(fe, cov_re=np.array([[max(ratio, 1e-3)]]))


def _fit(data: pd.DataFrame, groups: str):
    """REML fit of y ~ C(spring) + (1 | groups) from :func:`_start` (convergence reported)."""
    import statsmodels.formula.api as smf

    model = smf.mixedlm("y ~ C(spring)", data, groups=data[groups])
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return model.fit(reml=True, method="bfgs", start_params=_start(data, groups))


def mixed_model(wide: pd.DataFrame, bound_share: float) -> dict:
    """y ~ spring + (1 | trajectory): Wald χ², p, σ²_traj, σ²_e, share σ²_traj/(σ²_traj + σ²_e)."""
    long = wide.stack().rename("y").reset_index()
    long.columns = ["trajectory", "spring", "y"]
    k = long["spring"].nunique()
    empty = {"mixed_chi2": np.nan, "mixed_df": k - 1, "mixed_p": np.nan,
             "trajectory_variance": np.nan, "residual_variance": np.nan,
             "trajectory_share": np.nan, "trajectory_share_at_bound": False,
             "mixed_p_at_floor": False, "mixed_converged": False}  # fmt: skip
    if len(wide) < 3 or k < 2 or long["y"].std() == 0:
        return empty
    scale = float(long["y"].std())
    long["y"] = long["y"] / scale  # unit variance: the optimiser's tolerances are absolute
    result = _fit(long, "trajectory")
    names = [p for p in result.params.index if p.startswith("C(spring)")]
    chi2, p = _spring_wald(result, names)
    group, residual = float(result.cov_re.iloc[0, 0]) * scale**2, float(result.scale) * scale**2
    share = group / (group + residual) if group + residual > 0 else np.nan
    return {"mixed_chi2": chi2, "mixed_df": len(names), "mixed_p": max(p, P_FLOOR),
            "trajectory_variance": group, "residual_variance": residual,
            "trajectory_share": share, "trajectory_share_at_bound": bool(share < bound_share),
            "mixed_p_at_floor": bool(p < P_FLOOR),
            "mixed_converged": bool(result.converged)}  # fmt: skip


def spring_against_trials(kept: pd.DataFrame, column: str) -> dict:
    """One-way F of the k·r trial means of trajectory-centred y: F(k − 1, k(r − 1)) and p."""
    from scipy import stats

    centred = kept[column] - kept.groupby("stride")[column].transform("mean")
    means = centred.groupby([kept[SPRING], kept["trial"]]).mean()
    groups = [g.to_numpy(float) for _, g in means.groupby(level=0)]
    f, p = stats.f_oneway(*groups)
    return {"trial_F": float(f), "trial_df": len(groups) - 1,
            "trial_df_denominator": len(means) - len(groups), "trial_p": float(p)}  # fmt: skip


def trial_model(metrics: pd.DataFrame, column: str) -> dict:
    """Trial as a random effect: σ²_trial (MixedLM), the spring's F against it, or the confound."""
    kept = included(metrics)[["trial", "stride", SPRING, column]].dropna()
    per_spring = kept.groupby(SPRING)["trial"].nunique()
    out = {"trials_per_spring": int(per_spring.min()) if len(per_spring) else 0,
           "trial_variance": np.nan, "trial_F": np.nan, "trial_df": np.nan,
           "trial_df_denominator": np.nan, "trial_p": np.nan,
           "trial_converged": False}  # fmt: skip
    if per_spring.empty or per_spring.min() < 2:
        out["trial_note"] = (
            "one trial per spring: the spring is confounded with the trial (order, "
            "re-mounting), no between-trial variance can be estimated"
        )
        return out
    centred = kept[column] - kept.groupby("stride")[column].transform("mean")
    data = pd.DataFrame({"y": centred, "spring": kept[SPRING], "trial": kept["trial"]})
    scale = float(data["y"].std()) or 1.0
    data["y"] = data["y"] / scale
    result = _fit(data, "trial")
    out.update(spring_against_trials(kept, column))
    out.update({"trial_variance": float(result.cov_re.iloc[0, 0]) * scale**2,
                "trial_converged": bool(result.converged),
                "trial_note": "spring tested against the between-trial variance: F on the "
                "trial means"})  # fmt: skip
    return out


def tost(wide: pd.DataFrame, a: float, b: float, margin: float) -> dict:
    """Paired TOST of b − a within ±Δ: p = max of the two one-sided t-tests, mean b − a."""
    from statsmodels.stats.weightstats import ttost_paired

    x, y = wide[b].to_numpy(float), wide[a].to_numpy(float)
    if x.size < 3 or not np.isfinite(margin):
        return {"tost_p": np.nan, "mean_difference": np.nan}
    p, _, _ = ttost_paired(x, y, -margin, margin)
    return {"tost_p": float(p), "mean_difference": float(np.mean(x - y))}


def test_all(
    metrics: pd.DataFrame, columns, alpha: float, bound_share: float
) -> tuple[pd.DataFrame, pd.DataFrame]:
    """Per metric Friedman, mixed and trial models (one row), and its Wilcoxon pairs (long)."""
    rows, parts = [], []
    for column in columns:
        wide = matched(metrics, column)
        rows.append({"metric": column, **friedman(wide), **mixed_model(wide, bound_share),
                     **trial_model(metrics, column)})  # fmt: skip
        parts.append(wilcoxon_pairs(wide, alpha).assign(metric=column))
    return pd.DataFrame(rows), pd.concat(parts, ignore_index=True)[PAIR_COLUMNS]


def margins(block: Mapping) -> dict[str, tuple[float, str]]:
    """Equivalence margin Δ and its source per metric (``phantom.statistics.equivalence``)."""
    return {m: (float(entry["margin"]), str(entry["source"]))
            for m, entry in block["margins"].items()}  # fmt: skip
