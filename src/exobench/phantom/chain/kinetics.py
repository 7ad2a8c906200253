"""Power stage: per-sample power partition of the analysed strides (seed 000 eqs. 2.3–2.4)."""

from __future__ import annotations

import numpy as np
import pandas as pd

from exobench import tables
from exobench.phantom.chain import dynamics, metrics
from exobench.phantom.rig import ANALOG_RATE_HZ, LOAD_CELLS

POWER_COLUMNS = {f"power_{c}_W": c for c in metrics.COMPONENTS}
# The stage's own columns, its Parquet file (the others are the earlier stages', :func:`read`).
OWN_COLUMNS = ["stride", "t_s", "gait_cycle_pct", *POWER_COLUMNS]
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
    return widen(own_table(angles, moments, filtered, strides), angles, moments, filtered)


def own_table(angles, moments, filtered, strides) -> pd.DataFrame:
    """The power stage's own columns (its Parquet file): stride, time, gait-cycle share and the
    power partition P = M·ω of each component, per sample of the analysed strides."""
    dt = 1.0 / ANALOG_RATE_HZ
    powers = metrics.power_partition(
        moments["knee_moment_Nm"].to_numpy(),
        angles["phantom_knee_angle_rad"].to_numpy(),
        angles["exo_knee_angle_rad"].to_numpy(),
        filtered["LC_SPRING_N"].to_numpy(),
        angles["spring_length_m"].to_numpy(),
        dt,
    )
    numbers, index = stride_index(strides)
    samples = index.shape[1]
    flat = index.ravel()
    table = {
        "stride": np.repeat(numbers, samples),
        "t_s": angles["t_s"].to_numpy()[flat],
        "gait_cycle_pct": np.tile(np.arange(samples) / samples * 100.0, numbers.size),
    }
    table.update({name: powers[c][flat] for name, c in POWER_COLUMNS.items()})
    return pd.DataFrame(table)


def widen(own: pd.DataFrame, angles, moments, filtered) -> pd.DataFrame:
    """The contract table from the stage's own columns and the earlier stages' tables, matched
    by sample time: the angles, moments and load cells of every analysed sample."""
    flat = np.searchsorted(angles["t_s"].to_numpy(), own["t_s"].to_numpy())
    table = {
        "stride": own["stride"].to_numpy(),
        "t_s": own["t_s"].to_numpy(),
        "gait_cycle_pct": own["gait_cycle_pct"].to_numpy(),
        "knee_moment_Nm": moments["knee_moment_Nm"].to_numpy()[flat],
        "phantom_knee_angle_rad": angles["phantom_knee_angle_rad"].to_numpy()[flat],
        "exo_knee_angle_rad": angles["exo_knee_angle_rad"].to_numpy()[flat],
        "spring_force_N": filtered["LC_SPRING_N"].to_numpy()[flat],
        "spring_length_m": angles["spring_length_m"].to_numpy()[flat],
        "ankle_force_y_N": moments["ankle_force_y_N"].to_numpy()[flat],
        "moment_per_ankle_force_m": moments["moment_per_ankle_force_m"].to_numpy()[flat],
        **{c: moments[c].to_numpy()[flat] for c in SENSITIVITY_COLUMNS},
        **{f"{cell}_N": filtered[f"{cell}_N"].to_numpy()[flat] for cell in LOAD_CELLS},
    }
    table.update({name: own[name].to_numpy() for name in POWER_COLUMNS})
    return pd.DataFrame(table)


def trial_files(inputs) -> list[dict]:
    """Per trial, the four files :func:`read` joins, from a rule's inputs ``kinetics``,
    ``angles``, ``moments`` and ``filtered`` (one file per trial each, in trial order)."""
    kinds = ("kinetics", "angles", "moments", "filtered")
    columns = [list(getattr(inputs, kind)) for kind in kinds]
    return [dict(zip(kinds, files, strict=True)) for files in zip(*columns, strict=True)]


def read_parts(paths) -> dict[str, pd.DataFrame]:
    """One trial's four files as tables (``paths``: kinetics, angles, moments, filtered)."""
    return {kind: tables.read_table(path).data for kind, path in paths.items()}


def joined(parts, columns: list[str] | None = None) -> pd.DataFrame:
    """The contract table of :func:`read_parts`' tables, all columns or those named."""
    table = widen(parts["kinetics"], parts["angles"], parts["moments"], parts["filtered"])
    return table if columns is None else table[list(columns)]


def read(paths, columns: list[str] | None = None) -> pd.DataFrame:
    """One trial's contract table from its files, all columns or those named."""
    return joined(read_parts(paths), columns)
