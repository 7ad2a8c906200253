"""Mean ± SD curves over the gait cycle per spring, from the kinetics of included strides."""

from __future__ import annotations

import numpy as np
import pandas as pd

from exobench.phantom.study.statistics import SPRING

CURVE_SIGNALS = {
    "phantom_knee_angle_deg": ("phantom_knee_angle_rad", np.rad2deg),
    "exo_knee_angle_deg": ("exo_knee_angle_rad", np.rad2deg),
    "knee_moment_Nm": ("knee_moment_Nm", None),
    "power_knee_W": ("power_knee_W", None),
    "power_exoskeleton_W": ("power_exoskeleton_W", None),
    "power_interface_W": ("power_interface_W", None),
    "power_spring_W": ("power_spring_W", None),
    "power_frame_W": ("power_frame_W", None),
}


def mean_curves(kinetics: pd.DataFrame, kept_strides, spring: float, points: int) -> pd.DataFrame:
    """Mean and SD of each curve signal over the kept strides, on ``points`` cycle samples, and
    the number of strides (``n_strides``)."""
    rows = kinetics[kinetics["stride"].isin(kept_strides)]
    strides = rows["stride"].nunique()
    samples = len(rows) // max(strides, 1)
    step = max(samples // points, 1)
    table = {
        SPRING: float(spring),
        "gait_cycle_pct": np.arange(0, samples, step) / samples * 100,
        "n_strides": strides,
    }
    for name, (column, convert) in CURVE_SIGNALS.items():
        values = rows[column].to_numpy().reshape(strides, samples)[:, ::step]
        values = convert(values) if convert else values
        table[f"mean_{name}"] = values.mean(0)
        table[f"sd_{name}"] = values.std(0, ddof=1) if strides > 1 else np.zeros(values.shape[1])
    return pd.DataFrame(table)
