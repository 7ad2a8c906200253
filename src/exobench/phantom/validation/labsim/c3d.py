"""The C3D writer: markers at the point rate, analog channels at the analog rate."""

from pathlib import Path

import ezc3d
import numpy as np

from .rig import CHANNEL_UNITS, CHANNELS, FS_ANALOG, FS_POINT, MARKERS


def write_c3d(path: Path, points_mm: np.ndarray, analogs: np.ndarray) -> None:
    """Write markers (3, 12, frames) at 100 Hz and analog channels (5, samples) at 1000 Hz."""
    c3d = ezc3d.c3d()
    c3d["parameters"]["POINT"]["RATE"]["value"] = np.array([float(FS_POINT)])
    c3d["parameters"]["POINT"]["LABELS"]["value"] = list(MARKERS)
    c3d["parameters"]["ANALOG"]["RATE"]["value"] = np.array([float(FS_ANALOG)])
    c3d["parameters"]["ANALOG"]["LABELS"]["value"] = list(CHANNELS)
    c3d["parameters"]["ANALOG"]["UNITS"]["value"] = list(CHANNEL_UNITS)
    c3d.add_parameter("POINT", "UNITS", ["mm"])
    data = np.ones((4, len(MARKERS), points_mm.shape[2]))
    data[:3] = points_mm
    c3d["data"]["points"] = data
    c3d["data"]["analogs"] = analogs[None, :, :]
    c3d.write(str(path))
