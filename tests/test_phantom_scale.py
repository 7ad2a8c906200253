"""Unit slips of a whole recording (exobench.phantom.recordings.scale) and analog channels left
unmapped (exobench.phantom.recordings.qc): refused or reported, on small arrays."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pandas as pd
import pytest

from exobench.errors import InputError
from exobench.phantom.recordings import qc, scale
from exobench.phantom.recordings.c3d import Recording
from exobench.phantom.rig import GRAVITY_M_PER_S2, LOAD_CELLS, Rig
from phantom_helpers import workflow_config

FACTORS = workflow_config()["phantom"]["chain"]["unit_slips"]
RIG = Rig()
WEIGHT_N = (RIG.thigh_mass_kg + RIG.shank_mass_kg) * GRAVITY_M_PER_S2


def recording(marker_scale=1.0, force_scale=1.0, units="mm", unmapped=None) -> Recording:
    """The nominal rig standing at 20° of knee flexion for 1 s (100 Hz, 1000 Hz), its markers
    and ankle cells scaled, its POINT:UNITS and unmapped channels as given."""
    frames = 100
    angle = np.radians(20.0)
    hip = np.array([0.0, 900.0])
    knee = hip + 1000 * RIG.thigh_length_m * np.array([np.sin(angle / 2), -np.cos(angle / 2)])
    ankle = knee + 1000 * RIG.shank_length_m * np.array([-np.sin(angle / 2), -np.cos(angle / 2)])
    markers = {}
    for name, (x, y) in {"PH_HIP": hip, "PH_KNEE": knee, "PH_ANK": ankle}.items():
        for side, z in (("MED", -40.0), ("LAT", 40.0)):
            markers[f"{name}_{side}"] = marker_scale * np.tile([x, y, z], (frames, 1))
    rng = np.random.default_rng(3)
    analogs = {
        c: force_scale * (WEIGHT_N / 3 + rng.normal(0, 0.5, 10 * frames)) for c in LOAD_CELLS
    }
    analogs["LC_SPRING"] = np.full(10 * frames, 3.0)
    return Recording(Path("lab/trial1.c3d"), 100.0, 1000.0, markers, analogs, units,
                     unmapped or {})  # fmt: skip


def test_the_nominal_rig_and_mismatches_short_of_1000x_pass():
    scale.check(recording(), RIG, FACTORS, {})
    scale.check(recording(marker_scale=1.5, force_scale=4.0), RIG, FACTORS, {})
    assert scale.leg_length_mm(recording().markers_mm) == pytest.approx(603.0)
    assert [scale.slip(r, 3.0) for r in (1.0, 0.001, 0.0025, 1000.0, 0.03, np.nan)] == [
        0, -1, -1, 1, 0, 0,
    ]  # fmt: skip


def test_markers_in_metres_under_mm_are_refused_naming_the_slip():
    with pytest.raises(InputError) as caught:
        scale.check(recording(marker_scale=0.001), RIG, FACTORS, {})
    error = caught.value
    assert error.field == "POINT:UNITS" and "lab/trial1.c3d" in str(error)
    assert "markers look to be in metres while POINT:UNITS says mm" in str(error)
    assert "joint centres 0.603 mm apart" in str(error)


def test_markers_in_mm_under_metres_are_refused_naming_the_slip():
    with pytest.raises(InputError, match="markers look to be in millimetres while POINT:UNITS "
                       "says m") as caught:  # fmt: skip
        scale.check(recording(marker_scale=1000.0, units="m"), RIG, FACTORS, {})
    assert caught.value.field == "POINT:UNITS"


def test_load_cells_in_kN_under_N_are_refused_naming_the_cells_and_the_slip():
    labels = {"LC_ANKLE_1": "Fz1", "LC_ANKLE_2": "Fz2", "LC_ANKLE_3": "Fz3"}
    with pytest.raises(InputError) as caught:
        scale.check(recording(force_scale=0.001), RIG, FACTORS, labels)
    error = caught.value
    assert error.field == "ANALOG:UNITS of Fz1, Fz2, Fz3"
    assert "the ankle load cells look to be in kN" in str(error)
    assert "46.8 N" in str(error) and "lab/trial1.c3d" in str(error)


def pulses(samples=1000, every=200, width=20, high=5.0) -> np.ndarray:
    return np.where(np.arange(samples) % every < width, high, 0.0)


def test_a_sync_pulse_train_is_told_from_other_channels():
    assert qc.sync_edges(pulses(), 2.5) == 5
    assert qc.sync_edges(np.zeros(1000), 2.5) == 0
    assert qc.sync_edges(5.0 - pulses(), 2.5) == 0  # high most of the time: not a pulse train
    assert qc.sync_edges(np.sin(np.linspace(0, 20, 1000)), 2.5) == 0


def test_an_unmapped_channel_without_sync_is_one_warning_line_and_a_qc_row():
    trial = recording(unmapped={"Trigger": pulses(), "Temp": np.full(1000, 21.0)})
    line = qc.unmapped_warning(trial, 2.5)
    assert "\n" not in line and line.startswith("lab/trial1.c3d: no SYNC channel")
    assert "'Trigger' is not mapped but looks like a sync pulse train (5 rising edges" in line
    assert "phantom.rig.labels: {SYNC: Trigger}" in line and "also not mapped: Temp" in line
    events = qc.unmapped_events(trial, 2.5)
    assert events[["channel", "kind", "repair"]].values.tolist() == [
        ["Trigger", qc.LOOKS_LIKE_SYNC, qc.NOT_READ], ["Temp", qc.NOT_MAPPED, qc.NOT_READ],
    ]  # fmt: skip
    strides = pd.DataFrame({"start_s": [0.0, 0.5], "end_s": [0.5, 1.0],
                            "exclusion_reason": ["ramp", ""]})  # fmt: skip
    table = qc.qc_table("t", events, strides)
    assert table["stride"].tolist() == [-1, -1] and not table["stride_excluded"].any()
    assert qc.unmapped_warning(recording(), 2.5) is None
