"""Reading emulator recordings that follow docs/rig.md §3, with clear errors for anything else."""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from pathlib import Path

import numpy as np
import pandas as pd

from exobench import plausibility
from exobench.csvfiles import check_listed_files, read_csv_table
from exobench.emulator.recordings import matfiles
from exobench.emulator.rig import (
    BRACE_COLUMNS,
    CHANNEL_RANGES,
    MANIFEST_COLUMNS,
    MOCAP_COLUMNS,
    OPTIONAL_BRACE_COLUMNS,
    sample_rate_Hz,
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


def _read_table(
    path: Path,
    columns: tuple[str, ...],
    optional: tuple[str, ...],
    names: Mapping[str, str] | None,
    channels: Sequence[str],
) -> pd.DataFrame:
    """A recording's columns (and the optional ones it has) under the contract's names, from a
    CSV file or a MATLAB ``.mat`` file (:mod:`exobench.emulator.recordings.matfiles`)."""
    if not path.is_file():
        raise InputError(path, "file", "a recording listed in the manifest")
    if path.suffix.lower() == ".mat":
        return matfiles.read(path, columns, optional, names, channels)
    frame = read_csv_table(path)
    lab = {column: str((names or {}).get(column, column)) for column in columns + optional}
    columns = columns + tuple(c for c in optional if lab[c] in frame.columns)
    for column in columns:
        if lab[column] not in frame.columns:
            mapped = "" if lab[column] == column else f" ('{lab[column]}' by emulator.columns)"
            raise InputError(
                path, lab[column], f"columns {', '.join(columns)}{mapped}", list(frame.columns)
            )
    frame = frame.rename(columns={lab[c]: c for c in columns})[list(columns)]
    for column in columns:
        values = pd.to_numeric(frame[column], errors="coerce")
        if (values.isna() & frame[column].notna()).any():
            raise InputError(path, column, "numbers (an empty cell is a gap)", "text")
        frame[column] = values.to_numpy(float)
    return frame


def _check(
    path: Path,
    frame: pd.DataFrame,
    rate_range: tuple[str, Sequence[float]],
    duration_s: float,
    gaps: tuple[str, ...],
    max_gap_fraction: float,
) -> pd.DataFrame:
    """The table, checked: finite (the ``gaps`` columns may hold gaps, NaN, in at most
    ``max_gap_fraction`` of the rows), plausible, sampled evenly at a rate inside ``rate_range``
    (its config key and [low, high] Hz), ``duration_s`` long at that rate."""
    for column in frame.columns:
        values = frame[column].to_numpy(float)
        missing = np.isnan(values) if column in gaps else np.zeros(len(values), bool)
        if not (np.isfinite(values) | missing).all():
            allowed = f" or gaps in at most {max_gap_fraction:g} of them" if column in gaps else ""
            raise InputError(path, column, f"finite numbers in every row{allowed}")
        if missing.mean() > max_gap_fraction:
            raise InputError(
                path,
                column,
                f"gaps in at most {max_gap_fraction:g} of the rows (emulator.analysis."
                "max_gap_fraction)",
                f"{missing.mean():.3g}",
            )
        if column in CHANNEL_RANGES:
            plausibility.check_range(path, column, values, CHANNEL_RANGES[column])
    dt = np.diff(frame["time_s"].to_numpy())
    if len(dt) < 2 or (dt <= 0).any():
        raise InputError(path, "time_s", "strictly increasing times")
    rate = sample_rate_Hz(frame["time_s"])
    key, (low, high) = rate_range
    if not low <= rate <= high:
        raise InputError(
            path,
            "time_s",
            f"samples at {low:g} to {high:g} Hz (emulator.analysis.{key})",
            f"{rate:.3f} Hz",
        )
    # evenly sampled: the mean rate over the whole span agrees with the median step's
    mean_rate = len(dt) / float(frame["time_s"].iloc[-1] - frame["time_s"].iloc[0])
    if abs(mean_rate / rate - 1.0) > RATE_TOLERANCE:
        raise InputError(
            path,
            "time_s",
            f"evenly spaced samples (mean rate within {RATE_TOLERANCE:g} of the median "
            f"step's {rate:g} Hz; samples a recorder dropped are rows with empty cells, gaps)",
            f"{mean_rate:.3f} Hz",
        )
    recorded = len(frame) / rate
    if recorded < duration_s * (1.0 - RATE_TOLERANCE):
        raise InputError(
            path, "time_s", f"{duration_s:g} s recorded (the protocol)", f"{recorded:g} s"
        )
    return frame


def read_brace(
    path: str | Path,
    duration_s: float,
    names: Mapping | None = None,
    *,
    max_gap_fraction: float,
    rate_range_Hz: Sequence[float],
    channels: Sequence[str] = (),
) -> pd.DataFrame:
    """Brace recording at its own rate (inside ``rate_range_Hz``, Heer's 1000 Hz),
    ``duration_s`` long: time, encoder angle, torques, motor angle (and the clutch flag where
    the file has one); ``names``: the lab's column names;
    gaps (NaN) in the angle, torque and motor channels kept for the analysis to exclude their
    steps; ``channels``: the rows of a ``.mat`` file's one array after time."""
    path = Path(path)
    frame = _read_table(path, BRACE_COLUMNS, OPTIONAL_BRACE_COLUMNS, names, channels)
    rate_range = ("brace_rate_range_Hz", rate_range_Hz)
    return _check(path, frame, rate_range, duration_s, BRACE_COLUMNS[1:], max_gap_fraction)


def read_mocap(
    path: str | Path,
    duration_s: float,
    names: Mapping | None = None,
    *,
    max_gap_fraction: float,
    rate_range_Hz: Sequence[float],
    channels: Sequence[str] = (),
) -> pd.DataFrame:
    """Motion capture at its own rate (inside ``rate_range_Hz``, Heer's 100 Hz), ``duration_s``
    long: knee flexion of the same knee, same clock,
    its gaps (NaN: frames the cameras lost) kept as a mask; ``names``: the lab's column names;
    ``channels``: the rows of a ``.mat`` file's one array after time."""
    path = Path(path)
    frame = _read_table(path, MOCAP_COLUMNS, (), names, channels)
    rate_range = ("mocap_rate_range_Hz", rate_range_Hz)
    return _check(path, frame, rate_range, duration_s, MOCAP_COLUMNS[1:], max_gap_fraction)


def read_trial(
    brace_path: str | Path,
    mocap_path: str | Path,
    duration_s: float,
    settings: Mapping,
    names: Mapping | None = None,
    channels: Mapping | None = None,
) -> tuple[pd.DataFrame, pd.DataFrame]:
    """A trial's brace and motion-capture files (:func:`read_brace`, :func:`read_mocap`) with the
    analysis ``settings``' gap fraction and each file's rate range; ``channels``: a ``.mat``
    array's rows per file (``emulator.mat_channels``)."""
    channels = channels or {}
    gaps = settings["max_gap_fraction"]
    brace = read_brace(brace_path, duration_s, names, max_gap_fraction=gaps,
                       rate_range_Hz=settings["brace_rate_range_Hz"],
                       channels=channels.get("brace", ()))  # fmt: skip
    mocap = read_mocap(mocap_path, duration_s, names, max_gap_fraction=gaps,
                       rate_range_Hz=settings["mocap_rate_range_Hz"],
                       channels=channels.get("mocap", ()))  # fmt: skip
    return brace, mocap


def check_steps(path: str | Path, steps: pd.DataFrame) -> None:
    """A recording must hold at least one step between heel strikes (Table 5.1 events)."""
    if steps.empty:
        raise InputError(
            path, "brace_angle_deg", "at least one step between two heel strikes", "no step"
        )
