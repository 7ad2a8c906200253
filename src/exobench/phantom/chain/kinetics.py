"""Power stage: per-sample power partition of the analysed strides (seed 000 eqs. 2.3–2.4)."""

from __future__ import annotations

import numpy as np
import pandas as pd

from exobench.phantom.chain import dynamics, metrics
from exobench.phantom.rig import ANALOG_RATE_HZ, LOAD_CELLS

POWER_COLUMNS = {f"power_{c}_W": c for c in metrics.COMPONENTS}
# The inverse dynamics' columns the discrepancy engine's terms read (inverse_dynamics).
SENSITIVITY_COLUMNS = (
    "ankle_force_x_N",
    "moment_per_hip_moment_Nm_per_Nm",
    "thigh_rate_rad_per_s",
    "thigh_angle_rad",
    *(f"moment_per_{key}_scale_Nm" for key in dynamics.SEGMENT_VALUES),
    *(f"moment_per_{key}_scale2_Nm" for key in ("thigh_com", "shank_com")),
    "moment_per_knee_shift_Nm_per_m",
)


def stride_index(strides: pd.DataFrame) -> tuple[np.ndarray, np.ndarray]:
    """Analysed stride numbers and the (strides, samples) sample indices of each."""
    analysed = strides[strides["analysed"]]
    starts = np.round(analysed["start_s"].to_numpy() * ANALOG_RATE_HZ).astype(int)
    ends = np.round(analysed["end_s"].to_numpy() * ANALOG_RATE_HZ).astype(int)
    samples = int(np.min(ends - starts)) if len(starts) else 0
    return analysed["stride"].to_numpy(), starts[:, None] + np.arange(samples)[None, :]


def kinetics_table(angles, moments, filtered, strides) -> pd.DataFrame:
    """Kinetics contract table: one row per 1000 Hz sample of the analysed strides."""
    dt = 1.0 / ANALOG_RATE_HZ
    moment = moments["knee_moment_Nm"].to_numpy()
    phantom = angles["phantom_knee_angle_rad"].to_numpy()
    exo = angles["exo_knee_angle_rad"].to_numpy()
    force = filtered["LC_SPRING_N"].to_numpy()
    length = angles["spring_length_m"].to_numpy()
    powers = metrics.power_partition(moment, phantom, exo, force, length, dt)
    numbers, index = stride_index(strides)
    samples = index.shape[1]
    flat = index.ravel()
    table = {
        "stride": np.repeat(numbers, samples),
        "t_s": angles["t_s"].to_numpy()[flat],
        "gait_cycle_pct": np.tile(np.arange(samples) / samples * 100.0, numbers.size),
        "knee_moment_Nm": moment[flat],
        "phantom_knee_angle_rad": phantom[flat],
        "exo_knee_angle_rad": exo[flat],
        "spring_force_N": force[flat],
        "spring_length_m": length[flat],
        "ankle_force_y_N": moments["ankle_force_y_N"].to_numpy()[flat],
        "moment_per_ankle_force_m": moments["moment_per_ankle_force_m"].to_numpy()[flat],
        **{c: moments[c].to_numpy()[flat] for c in SENSITIVITY_COLUMNS},
        **{f"{cell}_N": filtered[f"{cell}_N"].to_numpy()[flat] for cell in LOAD_CELLS},
    }
    table.update({name: powers[c][flat] for name, c in POWER_COLUMNS.items()})
    return pd.DataFrame(table)
