"""A lab's own recordings of the twin's motion: its labels, camera and analog rates, metres."""

from __future__ import annotations

from pathlib import Path

import ezc3d
import numpy as np
import pandas as pd
from scipy.interpolate import CubicSpline

from exobench.phantom.rig import (
    ANALOG_RATE_HZ,
    ANALOG_UNITS,
    MANIFEST_COLUMNS,
    MARKERS,
    POINT_RATE_HZ,
    REQUIRED_ANALOGS,
    SYNC_HIGH_V,
    SYNC_WIDTH_S,
)

# The twin's effects at values near its calibration to seed 000 (fixed, so the tests need no
# calibration run).
CALIBRATED = {
    "k_interface_Nm_per_rad": 65.0,
    "c_interface_Nms_per_rad": 1.0,
    "k_frame_Nm_per_rad": 1000.0,
    "friction_Nm": 0.8,
    "k_drive_N_per_m": 55000.0,
}
# Vicon-style names a lab might give the contract's markers and channels.
LAB_LABELS = {
    "PH_HIP_MED": "RHipMed", "PH_HIP_LAT": "RHipLat", "PH_KNEE_MED": "RKneeMed",
    "PH_KNEE_LAT": "RKneeLat", "PH_ANK_MED": "RAnkleMed", "PH_ANK_LAT": "RAnkleLat",
    "EX_THIGH_PROX": "ExoThighUp", "EX_THIGH_DIST": "ExoThighLow", "EX_SHANK_PROX": "ExoShankUp",
    "EX_SHANK_DIST": "ExoShankLow", "EX_SPRING_A": "SpringFixed", "EX_SPRING_B": "SpringCable",
    "LC_ANKLE_1": "Force.Fz1", "LC_ANKLE_2": "Force.Fz2", "LC_ANKLE_3": "Force.Fz3",
    "LC_SPRING": "SpringForce", "SYNC": "Trigger",
}  # fmt: skip


def at_rate(values: np.ndarray, rate_in_hz: float, rate_out_hz: float) -> np.ndarray:
    """Values (n, ...) recorded at ``rate_in_hz`` as a recorder at ``rate_out_hz`` sees the same
    motion over the same span (cubic spline through the samples)."""
    t_in = np.arange(values.shape[0]) / rate_in_hz
    count = int(np.floor(values.shape[0] * rate_out_hz / rate_in_hz + 1e-9))
    return CubicSpline(t_in, values, axis=0)(np.arange(count) / rate_out_hz)


def sync_pulses(samples: int, stride_time_s: float, rate_hz: float) -> np.ndarray:
    """The SYNC channel at ``rate_hz``: 5 V for 20 ms at the start of every stride."""
    t = np.arange(samples) / rate_hz
    return np.where(np.mod(t, stride_time_s) < SYNC_WIDTH_S - 1e-9, SYNC_HIGH_V, 0.0)


def lab_trial(markers_mm, analogs, point_rate_hz, analog_rate_hz, stride_time_s, rng, noise):
    """A twin trial (noise-free markers at 100 Hz, channels at 1000 Hz) as the lab's recorders
    take it: its rates, then sensor noise (``noise``: marker and load-cell SDs in mm and N)."""
    markers = {}
    for label in sorted(markers_mm):
        xyz = at_rate(markers_mm[label], POINT_RATE_HZ, point_rate_hz)
        markers[label] = xyz + rng.normal(0.0, noise[0], xyz.shape)
    frames = next(iter(markers.values())).shape[0]
    samples = frames * round(analog_rate_hz / point_rate_hz)
    out = {}
    for label in REQUIRED_ANALOGS:
        values = at_rate(analogs[label], ANALOG_RATE_HZ, analog_rate_hz)[:samples]
        out[label] = values + rng.normal(0.0, noise[1], values.shape)
    out["SYNC"] = sync_pulses(samples, stride_time_s, analog_rate_hz)
    return markers, out


def write_lab_c3d(path: Path, markers_mm, analogs, point_rate_hz, analog_rate_hz, labels=LAB_LABELS,
                  units="m") -> Path:  # fmt: skip
    """A C3D as the lab writes it: its labels, rates and POINT:UNITS."""
    scale = {"m": 0.001, "mm": 1.0}[units]
    data = ezc3d.c3d()
    frames = next(iter(markers_mm.values())).shape[0]
    points = np.ones((4, len(MARKERS), frames))
    for index, label in enumerate(MARKERS):
        points[:3, index, :] = scale * np.asarray(markers_mm[label]).T
    params = data["parameters"]
    params["POINT"]["RATE"]["value"] = [point_rate_hz]
    params["POINT"]["LABELS"]["value"] = tuple(labels.get(m, m) for m in MARKERS)
    params["POINT"]["UNITS"]["value"] = [units]
    params["ANALOG"]["RATE"]["value"] = [analog_rate_hz]
    channels = [c for c in ANALOG_UNITS if c in analogs]
    params["ANALOG"]["LABELS"]["value"] = tuple(labels.get(c, c) for c in channels)
    params["ANALOG"]["UNITS"]["value"] = [ANALOG_UNITS[c] for c in channels]
    data["data"]["points"] = points
    data["data"]["analogs"] = np.stack([np.asarray(analogs[c], float) for c in channels])[None]
    path.parent.mkdir(parents=True, exist_ok=True)
    data.write(str(path))
    return path


def write_manifest(folder: Path, rows) -> Path:
    """manifest.csv of (trial, file, spring N/m, test order, ramp strides) rows."""
    folder.mkdir(parents=True, exist_ok=True)
    pd.DataFrame(rows, columns=list(MANIFEST_COLUMNS)).to_csv(folder / "manifest.csv", index=False)
    return folder / "manifest.csv"
