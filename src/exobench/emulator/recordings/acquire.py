"""Reading emulator recordings that follow docs/rig.md §3, with clear errors for anything else."""

from __future__ import annotations

from collections.abc import Mapping
from pathlib import Path

import numpy as np
import pandas as pd

from exobench import plausibility
from exobench.csvfiles import check_listed_files, read_csv_table
from exobench.emulator.rig import (
    BRACE_COLUMNS,
    BRACE_RATE_HZ,
    CHANNEL_RANGES,
    MANIFEST_COLUMNS,
    MOCAP_COLUMNS,
    MOCAP_RATE_HZ,
    OPTIONAL_BRACE_COLUMNS,
)
from exobench.errors import InputError

RATE_TOLERANCE = 0.01  # relative


def read_manifest(path: str | Path) -> pd.DataFrame:
    """The manifest's rows, checked for columns, unique trials, numeric conditions and files."""
    path = Path(path)
    if not path.is_file():
        raise InputError(path, "manifest", "a file listing the trials (docs/rig.md §3)")
    frame = read_csv_table(path, {"trial": str, "file": str, "mocap_file": str, "side": str})
    for column in MANIFEST_COLUMNS:
        if column not in frame.columns:
            raise InputError(
                path, column, f"columns {', '.join(MANIFEST_COLUMNS)}", list(frame.columns)
            )
    for column in ("speed_m_per_s", "stiffness_Nm_per_rad"):
        values = pd.to_numeric(frame[column], errors="coerce")
        if values.isna().any() or (values < 0).any():
            raise InputError(path, column, "non-negative numbers", frame[column].tolist())
        frame[column] = values.astype(float)
    if frame["trial"].duplicated().any():
        raise InputError(path, "trial", "unique trial names", frame["trial"].tolist())
    check_listed_files(path, frame, ("file", "mocap_file"))
    return frame


def _read_csv(
    path: Path,
    columns: tuple[str, ...],
    rate_Hz: float,
    duration_s: float,
    optional: tuple[str, ...] = (),
    names: Mapping[str, str] | None = None,
) -> pd.DataFrame:
    """A recording's columns (and the optional ones it has), checked: finite, plausible, rate,
    at least ``duration_s`` long. ``names`` maps a contract column to the lab's (config
    ``emulator.columns``); the table comes back under the contract's names."""
    if not path.is_file():
        raise InputError(path, "file", "a recording listed in the manifest")
    frame = read_csv_table(path)
    lab = {column: str((names or {}).get(column, column)) for column in columns + optional}
    columns = columns + tuple(c for c in optional if lab[c] in frame.columns)
    for column in columns:
        if lab[column] not in frame.columns:
            mapped = "" if lab[column] == column else f" ('{lab[column]}' by emulator.columns)"
            raise InputError(
                path, lab[column], f"columns {', '.join(columns)}{mapped}", list(frame.columns)
            )
    frame = frame.rename(columns={lab[c]: c for c in columns})
    for column in columns:
        values = pd.to_numeric(frame[column], errors="coerce").to_numpy(float)
        if not np.isfinite(values).all():
            raise InputError(path, column, "finite numbers in every row")
        if column in CHANNEL_RANGES:
            plausibility.check_range(path, column, values, CHANNEL_RANGES[column])
        frame[column] = values
    dt = np.diff(frame["time_s"].to_numpy())
    if len(dt) < 2 or (dt <= 0).any():
        raise InputError(path, "time_s", "strictly increasing times")
    rate = 1.0 / float(np.median(dt))
    if abs(rate / rate_Hz - 1.0) > RATE_TOLERANCE:
        raise InputError(path, "time_s", f"samples at {rate_Hz:g} Hz", f"{rate:.3f} Hz")
    recorded = len(frame) / rate_Hz
    if recorded < duration_s * (1.0 - RATE_TOLERANCE):
        raise InputError(
            path, "time_s", f"{duration_s:g} s recorded (the protocol)", f"{recorded:g} s"
        )
    return frame[list(columns)]


def read_brace(path: str | Path, duration_s: float, names: Mapping | None = None) -> pd.DataFrame:
    """Brace recording at 1000 Hz, ``duration_s`` long: time, encoder angle, torques, motor
    angle (and the clutch flag where the file has one); ``names``: the lab's column names."""
    return _read_csv(
        Path(path), BRACE_COLUMNS, BRACE_RATE_HZ, duration_s, OPTIONAL_BRACE_COLUMNS, names
    )


def read_mocap(path: str | Path, duration_s: float, names: Mapping | None = None) -> pd.DataFrame:
    """Motion capture at 100 Hz, ``duration_s`` long: knee flexion of the same knee, same clock;
    ``names``: the lab's column names."""
    return _read_csv(Path(path), MOCAP_COLUMNS, MOCAP_RATE_HZ, duration_s, names=names)


def check_steps(path: str | Path, steps: pd.DataFrame) -> None:
    """A recording must hold at least one step between heel strikes (Table 5.1 events)."""
    if steps.empty:
        raise InputError(
            path, "brace_angle_deg", "at least one step between two heel strikes", "no step"
        )
