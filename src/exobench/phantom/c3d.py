"""The phantom's raw-file contract (RIG.md §1): C3D trials and the manifest, with ezc3d."""

from __future__ import annotations

import faulthandler
import os
import pickle
import resource
import struct
from collections.abc import Mapping
from pathlib import Path

import ezc3d
import numpy as np
import pandas as pd

from exobench import plausibility
from exobench.csvfiles import check_listed_files, read_csv_table
from exobench.errors import InputError
from exobench.phantom.rig import (
    ANALOG_RANGES,
    ANALOG_RATE_HZ,
    ANALOG_UNITS,
    MANIFEST_COLUMNS,
    MARKER_RANGE,
    MARKERS,
    MAX_MARKER_STEP_MM,
    POINT_RATE_HZ,
    REQUIRED_ANALOGS,
    SATURATION_RUN_S,
)

POINT_UNITS = "mm"
PARAMETERS = ("RATE", "UNITS", "LABELS")
MIPS_PROCESSOR = 86  # parameter-section processor type of big-endian files (84 Intel, 85 DEC)
RATE_TOLERANCE = 1e-6


def write_trial(path: str | Path, markers_mm: Mapping[str, np.ndarray], analogs: Mapping) -> None:
    """Write one trial: markers (frames, 3) in mm at 100 Hz, analog channels at 1000 Hz."""
    c3d = ezc3d.c3d()
    labels = [label for label in MARKERS if label in markers_mm]
    frames = markers_mm[labels[0]].shape[0]
    points = np.ones((4, len(labels), frames))
    for index, label in enumerate(labels):
        points[:3, index, :] = np.asarray(markers_mm[label]).T
    channels = [label for label in ANALOG_UNITS if label in analogs]
    params = c3d["parameters"]
    params["POINT"]["RATE"]["value"] = [POINT_RATE_HZ]
    params["POINT"]["LABELS"]["value"] = tuple(labels)
    params["POINT"]["UNITS"]["value"] = [POINT_UNITS]
    params["ANALOG"]["RATE"]["value"] = [ANALOG_RATE_HZ]
    params["ANALOG"]["LABELS"]["value"] = tuple(channels)
    params["ANALOG"]["UNITS"]["value"] = [ANALOG_UNITS[label] for label in channels]
    c3d["data"]["points"] = points
    c3d["data"]["analogs"] = np.stack([np.asarray(analogs[c], float) for c in channels])[None]
    c3d.write(str(path))


def _labels(params, group: str) -> list[str]:
    return [str(label).strip() for label in params[group]["LABELS"]["value"]]


def read_trial(path: str | Path) -> tuple[pd.DataFrame, pd.DataFrame]:
    """Markers (100 Hz) and analog channels (1000 Hz) of a C3D trial, checked against RIG.md.

    Returns two tables with time ``t_s`` and columns ``<MARKER>_<x|y|z>_mm`` and
    ``<CHANNEL>_<N|V>`` and ``load_cell_saturated`` (samples in a flat run at a load cell's
    extreme). Every contract violation or implausible value raises :class:`InputError`.
    """
    path = Path(path)
    if not path.is_file():
        raise InputError(path, "<file>", "an existing C3D file listed in the manifest")
    c3d = load_isolated(path)
    params = c3d["parameters"]
    check_rate(path, "POINT:RATE", params["POINT"]["RATE"]["value"], POINT_RATE_HZ)
    units = [str(u).strip() for u in params["POINT"]["UNITS"]["value"]]
    if units != [POINT_UNITS]:
        raise InputError(path, "POINT:UNITS", f"'{POINT_UNITS}'", units)
    labels = _labels(params, "POINT")
    missing = [label for label in MARKERS if label not in labels]
    if missing:
        raise InputError(path, "POINT:LABELS", f"all 12 RIG.md markers; missing {missing}", labels)
    points = c3d["data"]["points"]
    frames = check_frames(path, header_frames(path), points.shape[2])
    markers = {"t_s": np.arange(frames) / POINT_RATE_HZ}
    for label in MARKERS:
        xyz = points[:3, labels.index(label), :]
        check_marker(path, label, xyz)
        for axis, values in zip("xyz", xyz, strict=True):
            markers[f"{label}_{axis}_mm"] = values
    analog = read_analogs(path, c3d, frames)
    check_spring_sign(path, markers, analog["LC_SPRING_N"].to_numpy())
    return pd.DataFrame(markers), analog


def _extract(path: Path) -> dict:
    """The parameters and data :func:`read_trial` uses, as plain Python and numpy objects."""
    c3d = ezc3d.c3d(str(path))
    params = c3d["parameters"]
    return {
        "parameters": {
            group: {name: {"value": params[group][name]["value"]} for name in PARAMETERS}
            for group in ("POINT", "ANALOG")
        },
        "data": {key: np.asarray(c3d["data"][key]) for key in ("points", "analogs")},
    }


def load_isolated(path: Path) -> dict:
    """Parse a C3D in a forked child and return its parameters and data.

    Some damaged files crash ezc3d (segfault); in a child that is an InputError, not the end
    of the workflow's process.
    """
    read_end, write_end = os.pipe()
    child = os.fork()
    if child == 0:  # pragma: no cover - runs in the child, which reports through the pipe
        os.close(read_end)
        faulthandler.disable()  # a crash is reported by the exit status, without a dump
        resource.setrlimit(resource.RLIMIT_CORE, (0, 0))
        try:
            result = ("ok", _extract(path))
        except KeyError as error:
            result = ("error", f"missing C3D parameter {error}")
        except Exception as error:  # ezc3d raises plain RuntimeError/IOError
            result = ("error", str(error))
        try:
            with os.fdopen(write_end, "wb") as pipe:
                pickle.dump(result, pipe)
        finally:
            os._exit(0)
    os.close(write_end)
    with os.fdopen(read_end, "rb") as pipe:
        payload = pipe.read()
    _, status = os.waitpid(child, 0)
    if os.WIFSIGNALED(status):
        crash = f"ezc3d crashed (signal {os.WTERMSIG(status)})"
        raise InputError(path, "<file>", "a C3D file the parser can read", crash)
    try:
        kind, value = pickle.loads(payload)
    except (pickle.UnpicklingError, EOFError, ValueError) as error:
        raise InputError(path, "<file>", "a readable C3D file", str(error)) from error
    if kind == "error":
        raise InputError(path, "<file>", "a readable C3D file", value)
    return value


def header_frames(path: Path) -> int | None:
    """Frames the file's own C3D header promises (words 4–5), None when it cannot say (≥ 65535).

    Read from the bytes: ezc3d rewrites its header to the frames it found in a truncated file.
    """
    with open(path, "rb") as handle:
        header = handle.read(512)
        if len(header) < 512:
            raise InputError(path, "<header>", "a 512-byte C3D header", f"{len(header)} bytes")
        handle.seek(max(header[0] - 1, 0) * 512 + 3)
        processor = handle.read(1)
    order = ">" if processor == bytes([MIPS_PROCESSOR]) else "<"
    first, last = struct.unpack(order + "HH", header[6:10])
    return None if last == 0xFFFF else last - first + 1


def check_frames(path: Path, promised: int | None, point_frames: int) -> int:
    """The point frames read, checked against the frames the header promises."""
    if promised is not None and point_frames != promised:
        raise InputError(path, "POINT frames", f"{promised} frames (C3D header)", point_frames)
    if point_frames < 1:
        raise InputError(path, "POINT frames", "at least one frame", point_frames)
    return point_frames


def check_marker(path: Path, label: str, xyz: np.ndarray) -> None:
    """Marker coordinates inside the capture volume and no jump between consecutive frames."""
    plausibility.check_range(path, f"POINT {label}", xyz, MARKER_RANGE)
    steps = np.linalg.norm(np.diff(xyz, axis=1), axis=0)
    jumps = np.flatnonzero(steps > MAX_MARKER_STEP_MM)
    if jumps.size:
        raise InputError(
            path,
            f"POINT {label}",
            f"moves of at most {MAX_MARKER_STEP_MM:g} mm between frames (a jump: swap or ghost)",
            f"{steps[jumps[0]]:.1f} mm at frame {jumps[0] + 1}",
        )


def check_spring_sign(path: Path, markers: dict, spring_force: np.ndarray) -> None:
    """LC_SPRING tension must rise with the spring length EX_SPRING_A–EX_SPRING_B."""
    ends = [
        np.stack([markers[f"{m}_{a}_mm"] for a in "xyz"]) for m in ("EX_SPRING_A", "EX_SPRING_B")
    ]
    length = np.linalg.norm(ends[1] - ends[0], axis=0)
    force = spring_force[:: round(ANALOG_RATE_HZ / POINT_RATE_HZ)][: length.size]
    valid = np.isfinite(length) & np.isfinite(force)
    if valid.sum() < 3 or np.ptp(length[valid]) == 0 or np.ptp(force[valid]) == 0:
        return
    correlation = float(np.corrcoef(length[valid], force[valid])[0, 1])
    if correlation < 0:
        raise InputError(
            path,
            "ANALOG LC_SPRING",
            "spring tension rising with the spring length (EX_SPRING_A–EX_SPRING_B)",
            f"correlation {correlation:.2f}: sign reversed",
        )


def read_analogs(path: Path, c3d, frames: int) -> pd.DataFrame:
    """Analog channels of RIG.md with their units, 10 samples per frame; SYNC is optional."""
    params = c3d["parameters"]
    check_rate(path, "ANALOG:RATE", params["ANALOG"]["RATE"]["value"], ANALOG_RATE_HZ)
    labels = _labels(params, "ANALOG")
    units = [str(u).strip() for u in params["ANALOG"]["UNITS"]["value"]]
    missing = [label for label in REQUIRED_ANALOGS if label not in labels]
    if missing:
        raise InputError(path, "ANALOG:LABELS", f"channels {list(REQUIRED_ANALOGS)}", labels)
    data = c3d["data"]["analogs"][0]
    if data.shape[0] < len(labels):
        raise InputError(path, "ANALOG:LABELS", f"{len(labels)} channels of data", data.shape[0])
    expected_samples = round(frames * ANALOG_RATE_HZ / POINT_RATE_HZ)
    if data.shape[1] != expected_samples:
        raise InputError(
            path, "ANALOG samples", f"{expected_samples} (10 per header frame)", data.shape[1]
        )
    table = {"t_s": np.arange(data.shape[1]) / ANALOG_RATE_HZ}
    saturated = np.zeros(data.shape[1], bool)
    for label, unit in ANALOG_UNITS.items():
        if label not in labels:
            continue
        index = labels.index(label)
        if index >= len(units) or units[index] != unit:
            found = units[index] if index < len(units) else None
            raise InputError(path, f"ANALOG:UNITS of {label}", f"'{unit}'", found)
        values = data[index].astype(float)
        if not np.isfinite(values).all():
            raise InputError(path, f"ANALOG {label}", "finite numbers in every sample")
        plausible = ANALOG_RANGES[label]
        plausibility.check_range(path, f"ANALOG {label}", values, plausible)
        if label in REQUIRED_ANALOGS:
            saturated |= plausibility.flat_runs_at_extremes(
                values, round(SATURATION_RUN_S * ANALOG_RATE_HZ), plausible.clip_low
            )
        table[f"{label}_{unit}"] = values
    table["load_cell_saturated"] = saturated
    return pd.DataFrame(table)


def check_rate(path: Path, field: str, value, expected: float) -> None:
    """Refuse a sampling rate other than the contract's."""
    rate = float(np.asarray(value).ravel()[0]) if np.size(value) else float("nan")
    if not abs(rate - expected) <= RATE_TOLERANCE:
        raise InputError(path, field, f"{expected:g} Hz", rate)


def check_duration(path: Path, frames: int, ramp_strides: int, stride_time_s: float) -> None:
    """A trial holds at least its ramp strides at both ends and one analysable stride."""
    needed = round((2 * ramp_strides + 1) * stride_time_s * POINT_RATE_HZ)
    if frames < needed:
        raise InputError(
            path,
            "POINT frames",
            f"at least {needed} ({2 * ramp_strides} ramp strides + 1, {stride_time_s:g} s each)",
            frames,
        )


def read_manifest(path: str | Path) -> pd.DataFrame:
    """Manifest of the phantom trials, checked: columns, types, unique trials, files present."""
    path = Path(path)
    if not path.is_file():
        raise InputError(path, "<file>", "a manifest.csv (RIG.md §1)")
    table = read_csv_table(path, {"trial": str, "file": str})
    missing = [column for column in MANIFEST_COLUMNS if column not in table.columns]
    if missing:
        raise InputError(
            path, ", ".join(missing), f"columns {','.join(MANIFEST_COLUMNS)}", list(table.columns)
        )
    for column in ("spring_stiffness_N_per_m", "test_order", "ramp_strides"):
        values = pd.to_numeric(table[column], errors="coerce")
        if values.isna().any() or (values < 0).any():
            raise InputError(path, column, "non-negative numbers", table[column].tolist())
        table[column] = values
    if (table["spring_stiffness_N_per_m"] <= 0).any():
        raise InputError(path, "spring_stiffness_N_per_m", "positive stiffness in N/m")
    if table["trial"].duplicated().any():
        raise InputError(path, "trial", "unique trial names", table["trial"].tolist())
    table["test_order"] = table["test_order"].astype(int)
    table["ramp_strides"] = table["ramp_strides"].astype(int)
    check_listed_files(path, table, ("file",))
    return table[list(MANIFEST_COLUMNS)]
