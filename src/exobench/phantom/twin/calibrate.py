"""Calibration of the twin's physical effects to the medians seed 000 reports.

The parameters of the enabled effects set to ``calibrated`` (by default the interface stiffness
and damping, the frame stiffness, the frame friction and the drive stiffness) are fitted by
nonlinear least squares (in log space) so that the medians of the twin's true per-stride metrics
match the reported medians of the springs the paper reports (3.4 and 21.7 kN/m), each simulated
for the calibration block's strides and ramp strides (the paper's protocol, whatever the
recordings' length); the protocol block gives the stride's timing, clutch and work windows.
Residuals are relative: metric error over max(|reported|, floor), with a larger floor for
work values so that near-zero works do not dominate.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass

import numpy as np
import pandas as pd
from scipy.optimize import least_squares

from exobench.phantom.chain import metrics
from exobench.phantom.rig import ANALOG_RATE_HZ, Rig
from exobench.phantom.twin import twin, twin_mechanics

# Relative change of the cost and of the log parameters that ends the search (0.1 % in a parameter
# moves no reported number by more than a few 0.01 %).
TOLERANCE = 1e-4
FITTED_METRICS = (*metrics.STANCE_METRICS, *metrics.WORK_COLUMNS)
# Reported differences between the softest and the stiffest spring: the drop of the phantom's
# stance flexion carries the drive compliance (its level is the programme's, not an effect's).
DIFFERENCES = {"phantom_stance_flexion_median_difference_deg": "phantom_stance_flexion_deg"}


def fitted_parameters(effects: Mapping, settings: Mapping) -> tuple[str, ...]:
    """Parameters of the enabled effects set to 'calibrated', in the calibration block's order."""
    calibrated = {
        parameter
        for effect, parameter in twin.MECHANICAL_EFFECTS.items()
        if effects[effect]["enabled"] and effects[effect][parameter] == "calibrated"
    }
    return tuple(parameter for parameter in settings["initial"] if parameter in calibrated)


def targets(reported: pd.DataFrame) -> pd.DataFrame:
    """Reported per-spring medians and spring differences of the metrics the effects shape."""
    rows = reported[reported["metric"].isin(FITTED_METRICS)]
    rows = rows.dropna(subset=["spring_stiffness_N_per_m"])
    rows = rows.sort_values(["spring_stiffness_N_per_m", "metric"])
    differences = reported[reported["metric"].isin(DIFFERENCES)]
    return pd.concat([rows, differences]).reset_index(drop=True)


def model_value(metric: str, spring: float, medians) -> float:
    """The twin's counterpart of one target: a spring's median, or softest minus stiffest."""
    if metric in DIFFERENCES:
        springs = sorted(medians)
        column = DIFFERENCES[metric]
        return medians[springs[0]][column] - medians[springs[-1]][column]
    return medians[spring][metric]


@dataclass(frozen=True)
class Strides:
    """The strides the fit simulates: the programmed block once per spring (rows), and more.

    Also the knee offsets x_K of the rows' postures, each row's spring and the springs in order.
    """

    flexion_rad: np.ndarray
    knee_offset_m: np.ndarray
    row_spring_N_per_m: np.ndarray
    springs_N_per_m: np.ndarray


def simulated_strides(flexion_rad: np.ndarray, springs: np.ndarray, rig: Rig) -> Strides:
    """The block ``flexion_rad`` repeated for every spring, with its knee offsets."""
    rows = np.tile(flexion_rad, (len(springs), 1))
    return Strides(
        rows,
        twin_mechanics.knee_offset_m(rows, rig),
        np.repeat(springs, flexion_rad.shape[0]),
        springs,
    )


def twin_strides(calibrated: Mapping[str, float], block: Strides, rig: Rig,
                 config: Mapping) -> pd.DataFrame:  # fmt: skip
    """The twin's true per-stride metrics of every simulated stride: spring, stride, whether
    its spring force reaches the protocol's minimum (``included``) and every metric."""
    springs = block.springs_N_per_m
    strides = block.flexion_rad.shape[0] // len(springs)
    missed = np.zeros(block.flexion_rad.shape[0], bool)
    values = twin.effect_values(config["twin"]["effects"], calibrated)
    _, state = twin.stride_states(
        block.flexion_rad,
        block.knee_offset_m,
        block.row_spring_N_per_m,
        missed,
        rig,
        config,
        values,
    )
    signals = {name: state[name] for name in metrics.SIGNALS}
    dt = 1.0 / ANALOG_RATE_HZ
    powers = metrics.power_partition(
        *(signals[c] for c in metrics.SIGNALS), state["spring_extension_m"], dt
    )
    per = metrics.stride_metrics(signals, powers, dt, config["protocol"])
    kept = per["peak_spring_force_N"] >= float(config["protocol"]["min_spring_force_N"])
    return pd.DataFrame({
        "spring_stiffness_N_per_m": block.row_spring_N_per_m.astype(float),
        "stride": np.tile(np.arange(strides), len(springs)),
        "included": kept,
        **per,
    })  # fmt: skip


def twin_medians(calibrated: Mapping[str, float], block: Strides, rig: Rig, config: Mapping):
    """Median true per-stride metrics of the twin for each spring, kept strides only."""
    return medians_of(twin_strides(calibrated, block, rig, config))


def medians_of(table: pd.DataFrame) -> dict[float, dict[str, float]]:
    """Spring -> metric -> median over the included strides of a :func:`twin_strides` table."""
    kept = table[table["included"]].drop(columns=["stride", "included"])
    return {float(spring): rows.drop(columns="spring_stiffness_N_per_m").median().to_dict()
            for spring, rows in kept.groupby("spring_stiffness_N_per_m")}  # fmt: skip


def residuals(values, goal: pd.DataFrame, medians) -> np.ndarray:
    """Relative residuals of the twin's medians against the reported ones."""
    model = np.array(
        [
            model_value(m, s, medians)
            for s, m in zip(goal["spring_stiffness_N_per_m"], goal["metric"], strict=True)
        ]
    )
    return (model - goal["value"].to_numpy()) / scales(goal)


def scales(goal: pd.DataFrame) -> np.ndarray:
    """Residual scale per target: |reported|, at least 0.2 J for work and 1 unit otherwise."""
    is_work = goal["metric"].str.startswith("work_").to_numpy()
    return np.maximum(np.abs(goal["value"].to_numpy()), np.where(is_work, 0.2, 1.0))


def fit(mean_cycle_deg: np.ndarray, reported: pd.DataFrame, rig: Rig, config: Mapping, settings):
    """Fitted effect parameters, fit summary, per-target residual table and the fitted twin's
    simulated strides (its per-stride metrics, the spread behind each of its medians)."""
    goal = targets(reported)
    springs = np.unique(goal["spring_stiffness_N_per_m"].dropna().to_numpy(float))
    ramps = int(settings["ramp_strides"])
    parameters = fitted_parameters(config["twin"]["effects"], settings)
    protocol = {**config["protocol"], "strides": int(settings["strides"]), "ramp_strides": ramps}
    flexion = twin.programmed_flexion(mean_cycle_deg, {**config, "protocol": protocol})
    flexion = flexion[ramps : flexion.shape[0] - ramps]
    block = simulated_strides(flexion, springs, rig)
    start = np.log([float(settings["initial"][p]) for p in parameters])
    low = np.log([float(settings["lower"][p]) for p in parameters])
    high = np.log([float(settings["upper"][p]) for p in parameters])

    def objective(log_values):
        values = dict(zip(parameters, np.exp(log_values), strict=True))
        return residuals(values, goal, twin_medians(values, block, rig, config))

    result = least_squares(
        objective,
        start,
        bounds=(low, high),
        diff_step=1e-2,
        x_scale=1.0,
        xtol=TOLERANCE,
        ftol=TOLERANCE,
    )
    fitted = dict(zip(parameters, np.exp(result.x).tolist(), strict=True))
    simulated = twin_strides(fitted, block, rig, config)
    medians = medians_of(simulated)
    model = [
        model_value(m, s, medians)
        for s, m in zip(goal["spring_stiffness_N_per_m"], goal["metric"], strict=True)
    ]
    table = goal[["metric", "spring_stiffness_N_per_m", "value", "unit", "source"]].rename(
        columns={"value": "reported"}
    )
    table["twin"] = model
    table["residual_scaled"] = result.fun
    summary = {
        "parameters": fitted,
        "initial": dict(settings["initial"]),
        "lower": dict(settings["lower"]),
        "upper": dict(settings["upper"]),
        "method": "scipy.optimize.least_squares (trf) on log parameters, relative residuals",
        "targets": len(goal),
        "strides_per_spring": int(flexion.shape[0]),
        "springs_N_per_m": springs.tolist(),
        "cost": float(result.cost),
        "rms_scaled_residual": float(np.sqrt(np.mean(result.fun**2))),
        "success": bool(result.success),
        "message": str(result.message),
        "evaluations": int(result.nfev),
    }
    return fitted, summary, table, simulated
