"""Model discrepancy against the medians seed 000 reports (no recordings, only numbers).

From medians only the series compliances are identifiable. With k_θ from eq. (2.2):
exoskeleton stiffness = (1/k_θ + 1/k_frame)⁻¹, phantom stiffness = (1/k_exo + 1/k_interface)⁻¹,
peak moment = phantom stiffness × phantom stance flexion, exoskeleton stance flexion =
peak moment / exoskeleton stiffness. The rigid theory has both compliances at zero.
Candidates are scored by leave-one-spring-out prediction (fit on one spring, predict the
other) and chosen by AIC; 95 % intervals come from the least-squares covariance.
"""

from __future__ import annotations

import itertools

import numpy as np
import pandas as pd
from scipy.optimize import least_squares

from exobench.phantom.discrepancy import DESCRIPTIONS, EFFECTS
from exobench.phantom.metrics import STANCE_METRICS
from exobench.phantom.rig import Rig

COMPLIANCES = ("interface_compliance", "frame_compliance")
PREDICTED = STANCE_METRICS


def medians(reported: pd.DataFrame) -> pd.DataFrame:
    """Reported medians per spring (rows) for the phantom flexion and the predicted metrics."""
    rows = reported.dropna(subset=["spring_stiffness_N_per_m"])
    table = rows.pivot(index="spring_stiffness_N_per_m", columns="metric", values="value")
    return table[["phantom_stance_flexion_deg", *PREDICTED]].dropna()


def predict(table: pd.DataFrame, values: dict, rig: Rig) -> pd.DataFrame:
    """Series-stiffness predictions of the four metrics for each reported spring."""
    k_theta = rig.joint_stiffness(table.index.to_numpy(float))
    frame = 1.0 / values.get("k_frame_Nm_per_rad", np.inf)
    interface = 1.0 / values.get("k_interface_Nm_per_rad", np.inf)
    exo = 1.0 / (1.0 / k_theta + frame)
    phantom = 1.0 / (1.0 / exo + interface)
    moment = phantom * np.deg2rad(table["phantom_stance_flexion_deg"].to_numpy())
    return pd.DataFrame(
        {
            "peak_moment_Nm": moment,
            "phantom_stiffness_Nm_per_rad": phantom,
            "exo_stiffness_Nm_per_rad": exo,
            "exo_stance_flexion_deg": np.rad2deg(moment / exo),
        },
        index=table.index,
    )


def log_residuals(table, values, rig) -> np.ndarray:
    """log(predicted / reported) of every metric and spring."""
    return (
        np.log(predict(table, values, rig)[list(PREDICTED)] / table[list(PREDICTED)])
        .to_numpy()
        .ravel()
    )


def rms(values) -> float:
    """Root mean square."""
    return float(np.sqrt(np.mean(np.square(values))))


def fit(table, effects, rig):
    """Least-squares compliances (log space) and the log-parameter covariance."""
    if not effects:
        return {}, np.zeros((0, 0))
    names = [EFFECTS[e][0] for e in effects]
    low = np.log([EFFECTS[e][1] for e in effects])
    high = np.log([EFFECTS[e][2] for e in effects])

    def objective(x):
        return log_residuals(table, dict(zip(names, np.exp(x), strict=True)), rig)

    result = least_squares(objective, np.log(np.full(len(names), 500.0)), bounds=(low, high))
    dof = max(result.fun.size - len(names), 1)
    variance = float(np.sum(result.fun**2)) / dof
    jtj = result.jac.T @ result.jac
    covariance = np.linalg.pinv(jtj) * variance
    return dict(zip(names, np.exp(result.x).tolist(), strict=True)), covariance


def analyse(reported: pd.DataFrame, rig: Rig, source: str) -> dict:
    """Discrepancy report for the reported medians (same contract as the recordings' one)."""
    table = medians(reported)
    springs = table.index.to_numpy()
    candidates = []
    for size in range(len(COMPLIANCES) + 1):
        for effects in itertools.combinations(COMPLIANCES, size):
            values, covariance = fit(table, effects, rig)
            residual = log_residuals(table, values, rig)
            held_out, moment_errors = [], []
            for spring in springs:
                trained, _ = fit(table.drop(index=spring), effects, rig)
                test = table.loc[[spring]]
                held_out.append(log_residuals(test, trained, rig))
                moment_errors.append(
                    predict(test, trained, rig)["peak_moment_Nm"].iloc[0]
                    - test["peak_moment_Nm"].iloc[0]
                )
            n = residual.size
            candidates.append(
                {
                    "effects": list(effects),
                    "parameters": values,
                    "log_se": np.sqrt(np.diag(covariance)).tolist(),
                    "cv_rmse_Nm": rms(moment_errors),
                    "cv_rms_relative_error": float(
                        np.sqrt(np.mean(np.square(np.expm1(np.concatenate(held_out)))))
                    ),
                    "aic": float(n * np.log(np.mean(residual**2)) + 2 * len(values)),
                    "predictions": predict(table, values, rig).reset_index().to_dict("records"),
                }
            )
    baseline = candidates[0]
    chosen = min(candidates, key=lambda c: c["aic"])
    found = []
    for effect, se in zip(chosen["effects"], chosen["log_se"], strict=True):
        name = EFFECTS[effect][0]
        value = chosen["parameters"][name]
        interval = [value * np.exp(-1.96 * se), value * np.exp(1.96 * se)]
        found.append({"effect": effect, "parameters": {name: value}, "ci95": {name: interval}})
    found.sort(key=lambda f: next(iter(f["parameters"].values())))
    gain = {
        "baseline_cv_rmse_Nm": baseline["cv_rmse_Nm"],
        "extended_cv_rmse_Nm": chosen["cv_rmse_Nm"],
        "reduction_pct": 100.0 * (1.0 - chosen["cv_rmse_Nm"] / baseline["cv_rmse_Nm"]),
        "baseline_cv_rms_relative_error": baseline["cv_rms_relative_error"],
        "extended_cv_rms_relative_error": chosen["cv_rms_relative_error"],
    }
    if found:
        named = " and ".join(DESCRIPTIONS[f["effect"]] for f in found)
        cause = (
            f"The rigid theory over-predicts the reported moments and stiffnesses because of "
            f"{named}; the softest compliance, listed first, dominates. Held-out peak-moment "
            f"error falls by {gain['reduction_pct']:.0f} %."
        )
    else:
        cause = "none: the rigid theory explains the data"
    return {
        "source": source,
        "baseline": {"model": "rigid", "cv_rmse_Nm": baseline["cv_rmse_Nm"]},
        "candidates": candidates,
        "selected": chosen["effects"],
        "selection": "lowest AIC over log residuals; cross-validation leaves one spring out",
        "effects_found": found,
        "cause": cause,
        "gain": gain,
    }
