"""Valid small recordings and damaged copies of them, for the reliability tests and cases."""

from __future__ import annotations

import copy
from pathlib import Path

import ezc3d
import numpy as np
import yaml

from conftest import REPO
from exobench.emulator.twin import twin as emulator_twin
from exobench.phantom.rig import Rig
from exobench.phantom.twin import twin
from phantom_helpers import mean_cycle, settings, small_config

CALIBRATED = {
    "k_interface_Nm_per_rad": 55.0,
    "c_interface_Nms_per_rad": 0.8,
    "k_frame_Nm_per_rad": 900.0,
    "friction_Nm": 0.6,
}
PHANTOM_STRIDES, PHANTOM_RAMPS = 6, 1
EMULATOR_DURATION_S = 6.0


def write_phantom(folder: Path) -> Path:
    """Twin recordings of a short noisy protocol (6 strides, 1 ramp stride) in ``folder``."""
    config = small_config(
        strides=PHANTOM_STRIDES,
        ramps=PHANTOM_RAMPS,
        interface_compliance=55.0,
        marker_noise=0.15,
        load_cell_noise=0.5,
    )
    trials = twin.simulate_trials(mean_cycle(), Rig(), settings(config), CALIBRATED)
    twin.write_recordings(trials, folder, {"rule": "test"}, ramp_strides=PHANTOM_RAMPS)
    return folder


def emulator_block(duration_s: float = EMULATOR_DURATION_S) -> dict:
    """The default emulator config with a short protocol (two conditions)."""
    block = copy.deepcopy(yaml.safe_load((REPO / "config" / "config.yaml").read_text()))
    block = block["emulator"]
    block["protocol"].update(
        {"speeds_m_per_s": [0.8], "stiffnesses_Nm_per_rad": [0.0, 3.5], "duration_s": duration_s}
    )
    return block


def write_emulator(folder: Path) -> Path:
    """Emulator twin recordings of the short protocol in ``folder``."""
    emulator_twin.write_recordings(emulator_twin.run(emulator_block(), 0), folder)
    return folder


def edit_c3d(source: Path, target: Path, edit) -> Path:
    """Copy of a C3D with ``edit(points, analogs, labels)`` applied to its data in place."""
    data = ezc3d.c3d(str(source))
    points = np.array(data["data"]["points"])
    analogs = np.array(data["data"]["analogs"])
    labels = [str(x).strip() for x in data["parameters"]["ANALOG"]["LABELS"]["value"]]
    edit(points, analogs[0], labels)
    data["data"]["points"] = points
    data["data"]["analogs"] = analogs
    data.write(str(target))
    return target


def saturate(label: str, start: int, stop: int):
    """Edit: an analog channel stuck at its full scale (1.2 × its peak) over samples start:stop."""

    def edit(_points, analogs, labels):
        row = labels.index(label)
        analogs[row, start:stop] = 1.2 * analogs[row].max()

    return edit
