"""The phantom's raw-file contract (docs/rig.md): C3D trials and the manifest, with ezc3d."""

from __future__ import annotations

import faulthandler
import os
import pickle
import resource
import select
import signal
import struct
import time
from collections.abc import Mapping
from dataclasses import dataclass, field
from pathlib import Path

import ezc3d
import numpy as np
import pandas as pd

from exobench import plausibility
from exobench.csvfiles import check_listed_files, read_csv_table
from exobench.errors import InputError
from exobench.phantom.recordings import resample
from exobench.phantom.rig import (
    ANALOG_RATE_HZ,
    ANALOG_UNITS,
    MANIFEST_COLUMNS,
    MARKERS,
    POINT_RATE_HZ,
    POINT_RATE_LIMITS_HZ,
    POINT_UNITS_MM,
    REQUIRED_ANALOGS,
    SPRING_RANGE,
)

POINT_UNITS = "mm"
PARAMETERS = ("RATE", "UNITS", "LABELS")
MIPS_PROCESSOR = 86  # parameter-section processor type of big-endian files (84 Intel, 85 DEC)
RATE_TOLERANCE = 1e-6  # relative: rates are stored as 32-bit floats


@dataclass(frozen=True)
class Recording:
    """One C3D trial as recorded, under the contract's names: markers (frames, 3) in mm at the
    camera's rate, analog channels in N and V at the analog rate (a whole multiple of it); the
    POINT:UNITS the file states, and (when it has no SYNC) the analog channels it holds that
    no contract name maps to, under their own labels."""

    path: Path
    point_rate_hz: float
    analog_rate_hz: float
    markers_mm: dict[str, np.ndarray]
    analogs: dict[str, np.ndarray]
    point_units: str = "mm"
    unmapped: dict[str, np.ndarray] = field(default_factory=dict)

    @property
    def frames(self) -> int:
        """Camera frames recorded."""
        return next(iter(self.markers_mm.values())).shape[0]


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


def lab_labels(path: Path, field: str, found: list[str], wanted, labels: Mapping) -> list[int]:
    """Index in ``found`` of each contract name in ``wanted``, under the lab's label that
    ``labels`` maps it to (or its own); InputError naming what is missing."""
    names = {name: str(labels.get(name, name)) for name in wanted}
    missing = [name for name, label in names.items() if label not in found]
    if missing:
        shown = [name if names[name] == name else f"{names[name]} (for {name})" for name in missing]
        raise InputError(
            path,
            field,
            "every contract label (docs/rig.md) in the file, under its own name or the one "
            f"phantom.rig.labels maps it to; missing {shown}",
            found,
        )
    return [found.index(names[name]) for name in wanted]


def read_trial(path: str | Path, labels: Mapping | None = None):
    """Markers (100 Hz) and analog channels (1000 Hz) of a C3D trial, contract checked and
    resampled to the analysis rates (:func:`analysis_tables`); no glitch screening."""
    return analysis_tables(read_recording(path, labels))


def read_recording(
    path: str | Path, labels: Mapping | None = None, timeout_s: float | None = None
) -> Recording:
    """A C3D trial checked against the contract (docs/rig.md): every marker and required channel
    (under the lab's labels, ``labels``: contract name → label), a camera rate within
    :data:`POINT_RATE_LIMITS_HZ` and an analog rate a whole multiple of it, POINT:UNITS mm or m
    (converted to mm), N and V, every frame the header promises, parsed within ``timeout_s``
    (None: however long it takes). InputError otherwise."""
    path, labels = Path(path), labels or {}
    if not path.is_file():
        raise InputError(path, "<file>", "an existing C3D file listed in the manifest")
    c3d = load_isolated(path, timeout_s)
    params = c3d["parameters"]
    point_rate = stated_rate(path, "POINT:RATE", params["POINT"]["RATE"]["value"])
    low, high = POINT_RATE_LIMITS_HZ
    if not low <= point_rate <= high:
        raise InputError(path, "POINT:RATE", f"a camera rate of {low:g} to {high:g} Hz", point_rate)
    units = [str(u).strip() for u in params["POINT"]["UNITS"]["value"]]
    if len(units) != 1 or units[0] not in POINT_UNITS_MM:
        raise InputError(path, "POINT:UNITS", f"one of {list(POINT_UNITS_MM)}", units)
    rows = lab_labels(path, "POINT:LABELS", _labels(params, "POINT"), MARKERS, labels)
    points = c3d["data"]["points"]
    frames = check_frames(path, header_frames(path), points.shape[2])
    scale = POINT_UNITS_MM[units[0]]
    markers = {
        label: scale * points[:3, row, :].T for label, row in zip(MARKERS, rows, strict=True)
    }
    analog_rate = stated_rate(path, "ANALOG:RATE", params["ANALOG"]["RATE"]["value"])
    per_frame = analog_rate / point_rate
    if round(per_frame) < 1 or abs(per_frame - round(per_frame)) > RATE_TOLERANCE * per_frame:
        raise InputError(
            path, "ANALOG:RATE", f"a whole multiple of POINT:RATE ({point_rate:g} Hz)", analog_rate
        )
    analogs = read_analogs(path, c3d, frames * round(per_frame), labels)
    unmapped = {} if "SYNC" in analogs else unmapped_analogs(c3d, labels)
    return Recording(path, point_rate, analog_rate, markers, analogs, units[0], unmapped)


def unmapped_analogs(c3d, labels: Mapping) -> dict[str, np.ndarray]:
    """The file's analog channels that no contract name is (or is mapped to), by their label."""
    found = _labels(c3d["parameters"], "ANALOG")
    taken = {str(labels.get(name, name)) for name in ANALOG_UNITS}
    data = c3d["data"]["analogs"][0]
    return {
        label: data[row].astype(float)
        for row, label in enumerate(found)
        if label not in taken and row < data.shape[0]
    }


def analysis_tables(recording: Recording) -> tuple[pd.DataFrame, pd.DataFrame]:
    """The recording at the analysis rates: markers ``t_s``, ``<MARKER>_<x|y|z>_mm`` (100 Hz) and
    analog ``t_s``, ``<CHANNEL>_<N|V>`` (1000 Hz, 10 samples per frame), resampled by cubic
    convolution where the file's rates differ; a missing sample stays NaN."""
    frames = resample.analysis_frames(recording.frames, recording.point_rate_hz, POINT_RATE_HZ)
    samples = frames * round(ANALOG_RATE_HZ / POINT_RATE_HZ)
    markers = {"t_s": np.arange(frames) / POINT_RATE_HZ}
    for label, xyz in recording.markers_mm.items():
        xyz = resample.resample(xyz, recording.point_rate_hz, POINT_RATE_HZ, frames)
        for axis, values in zip("xyz", xyz.T, strict=True):
            markers[f"{label}_{axis}_mm"] = values
    analog = {"t_s": np.arange(samples) / ANALOG_RATE_HZ}
    for label, values in recording.analogs.items():
        analog[f"{label}_{ANALOG_UNITS[label]}"] = resample.resample(
            values, recording.analog_rate_hz, ANALOG_RATE_HZ, samples
        )
    return pd.DataFrame(markers), pd.DataFrame(analog)


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


def load_isolated(path: Path, timeout_s: float | None = None) -> dict:
    """Parse a C3D in a forked child and return its parameters and data.

    Some damaged files crash ezc3d (segfault) or keep it busy (a damaged parameter section); in
    a child that is an InputError, not the end of the workflow's process, and a child still
    parsing after ``timeout_s`` is ended (None: no limit).
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
    payload = _drained(read_end, timeout_s)
    if payload is None:
        os.kill(child, signal.SIGKILL)
        os.waitpid(child, 0)
        expected = (f"a C3D file the parser reads within {timeout_s:g} s "
                    "(phantom.chain.read_timeout_s)")  # fmt: skip
        raise InputError(path, "<file>", expected, "the parser was still reading")
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


def _drained(fd: int, timeout_s: float | None) -> bytes | None:
    """Everything written to pipe ``fd`` until its writer closes it (the fd is closed), or None
    when that takes longer than ``timeout_s``."""
    deadline = None if timeout_s is None else time.monotonic() + timeout_s
    chunks = []
    ready = select.poll()  # not select.select: it refuses descriptors from 1024 on
    ready.register(fd, select.POLLIN)
    with os.fdopen(fd, "rb", buffering=0) as pipe:
        while True:
            wait = None if deadline is None else max(deadline - time.monotonic(), 0.0) * 1000
            if not ready.poll(wait):
                return None
            chunk = pipe.read(1 << 20)
            if not chunk:
                return b"".join(chunks)
            chunks.append(chunk)


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


def read_analogs(path: Path, c3d, samples: int, labels: Mapping) -> dict[str, np.ndarray]:
    """The contract's analog channels (SYNC optional) under the lab's labels, with their units
    checked (N or V), ``samples`` of each."""
    params = c3d["parameters"]
    found = _labels(params, "ANALOG")
    units = [str(u).strip() for u in params["ANALOG"]["UNITS"]["value"]]
    rows = lab_labels(path, "ANALOG:LABELS", found, REQUIRED_ANALOGS, labels)
    sync = str(labels.get("SYNC", "SYNC"))
    names = [*REQUIRED_ANALOGS, *(["SYNC"] if sync in found else [])]
    rows += [found.index(sync)] if sync in found else []
    data = c3d["data"]["analogs"][0]
    if data.shape[0] < len(found):
        raise InputError(path, "ANALOG:LABELS", f"{len(found)} channels of data", data.shape[0])
    if data.shape[1] != samples:
        raise InputError(path, "ANALOG samples", f"{samples} (ANALOG:RATE × header frames)",
                         data.shape[1])  # fmt: skip
    out = {}
    for name, row in zip(names, rows, strict=True):
        unit = ANALOG_UNITS[name]
        if row >= len(units) or units[row] != unit:
            found_unit = units[row] if row < len(units) else None
            raise InputError(
                path, f"ANALOG:UNITS of {found[row]}", f"'{unit}' ({name})", found_unit
            )
        out[name] = data[row].astype(float)
    return out


def stated_rate(path: Path, field: str, value) -> float:
    """A rate the file states, a positive finite number (InputError otherwise)."""
    rate = float(np.asarray(value).ravel()[0]) if np.size(value) else float("nan")
    if not (np.isfinite(rate) and rate > 0):
        raise InputError(path, field, "a positive rate in Hz", rate)
    return rate


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
    """Manifest of the phantom trials, checked: columns, types, physical ranges (a spring rate
    in N/m, :data:`SPRING_RANGE`), whole numbers, unique trials, files present."""
    path = Path(path)
    if not path.is_file():
        raise InputError(path, "<file>", "a manifest.csv (docs/rig.md)")
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
    plausibility.check_range(
        path, "spring_stiffness_N_per_m", table["spring_stiffness_N_per_m"], SPRING_RANGE
    )
    for column in ("test_order", "ramp_strides"):
        if (table[column] % 1 != 0).any():
            raise InputError(path, column, "whole numbers", table[column].tolist())
    if table["trial"].duplicated().any():
        raise InputError(path, "trial", "unique trial names", table["trial"].tolist())
    table["test_order"] = table["test_order"].astype(int)
    table["ramp_strides"] = table["ramp_strides"].astype(int)
    check_listed_files(path, table, ("file",))
    return table[list(MANIFEST_COLUMNS)]
