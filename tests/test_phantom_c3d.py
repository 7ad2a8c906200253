"""C3D contract of docs/rig.md §1: what the twin writes, what the reader accepts and refuses."""

from __future__ import annotations

import os
from pathlib import Path

import ezc3d
import numpy as np
import pandas as pd
import pytest

from exobench.errors import InputError
from exobench.phantom import twin_files
from exobench.phantom.recordings import c3d
from exobench.phantom.rig import ANALOG_UNITS, MARKERS, Rig
from exobench.phantom.twin import twin
from exobench.plumbing import stamp
from phantom_helpers import mean_cycle, settings, small_config

CALIBRATED = {
    "k_interface_Nm_per_rad": 55.0,
    "c_interface_Nms_per_rad": 0.8,
    "k_frame_Nm_per_rad": 900.0,
    "friction_Nm": 0.6,
}


@pytest.fixture(scope="module")
def recordings(tmp_path_factory):
    """Twin recordings of a short protocol, with noise and occlusions, as files."""
    folder = tmp_path_factory.mktemp("raw") / "phantom"
    config = small_config(
        strides=6,
        ramps=1,
        interface_compliance=55.0,
        marker_noise=0.3,
        load_cell_noise=0.5,
        occlusion={"gaps_per_marker_per_min": 20, "max_frames": 5},
    )
    trials = list(twin.simulate_trials(mean_cycle(), Rig(), settings(config), CALIBRATED))
    twin.write_recordings(trials, folder, {"rule": "test"}, ramp_strides=1)
    return folder, trials


def test_ezc3d_reads_the_contract(recordings):
    folder, _trials = recordings
    manifest = pd.read_csv(folder / "manifest.csv")
    assert list(manifest.columns) == [
        "trial",
        "file",
        "spring_stiffness_N_per_m",
        "test_order",
        "ramp_strides",
    ]
    assert manifest["spring_stiffness_N_per_m"].tolist() == [9200, 21700, 13600, 6100, 3400, 18000]
    assert len(manifest) == 6
    for file in manifest["file"]:
        data = ezc3d.c3d(str(folder / file))
        params = data["parameters"]
        assert list(params["POINT"]["LABELS"]["value"]) == list(MARKERS)
        assert params["POINT"]["UNITS"]["value"] == ["mm"]
        assert params["POINT"]["RATE"]["value"][0] == 100.0
        assert params["ANALOG"]["RATE"]["value"][0] == 1000.0
        labels = list(params["ANALOG"]["LABELS"]["value"])
        assert labels == list(ANALOG_UNITS)
        assert list(params["ANALOG"]["UNITS"]["value"]) == [ANALOG_UNITS[k] for k in labels]
        frames = data["data"]["points"].shape[2]
        assert frames == 6 * 200
        assert data["data"]["analogs"].shape == (1, 5, frames * 10)


def test_reader_round_trips_the_twin(recordings):
    folder, trials = recordings
    trial = trials[2]
    markers, analog = c3d.read_trial(folder / f"{trial.name}.c3d")
    for label in MARKERS:
        written = trial.markers_mm[label]
        read = markers[[f"{label}_{axis}_mm" for axis in "xyz"]].to_numpy()
        np.testing.assert_array_equal(np.isnan(read), np.isnan(written))
        np.testing.assert_allclose(read, written, rtol=1e-6, atol=1e-3, equal_nan=True)
    for label, unit in ANALOG_UNITS.items():
        np.testing.assert_allclose(analog[f"{label}_{unit}"], trial.analogs[label], atol=1e-3)
    sync = analog["SYNC_V"].to_numpy()
    starts = np.flatnonzero(np.diff((sync > 2.5).astype(int)) == 1) + 1
    assert sync[0] > 2.5 and np.all(np.diff(starts) == 2000)


def test_rewritten_twin_files_are_byte_identical(recordings, tmp_path):
    folder, trials = recordings
    twin.write_recordings(trials, tmp_path, {"rule": "test"}, ramp_strides=1)
    for name in ("manifest.csv", f"{trials[0].name}.c3d", f"truth/{trials[0].name}.parquet"):
        assert (tmp_path / name).read_bytes() == (folder / name).read_bytes()


def write_custom(path, labels, units="mm", rate=100.0, channels=None, analog_rate=1000.0):
    """A C3D with chosen labels, units and rates (for contract violations)."""
    channels = channels or dict(ANALOG_UNITS)
    data = ezc3d.c3d()
    frames = 24
    data["parameters"]["POINT"]["RATE"]["value"] = [rate]
    data["parameters"]["POINT"]["LABELS"]["value"] = tuple(labels)
    data["parameters"]["POINT"]["UNITS"]["value"] = [units]
    data["data"]["points"] = np.ones((4, len(labels), frames))
    data["parameters"]["ANALOG"]["RATE"]["value"] = [analog_rate]
    data["parameters"]["ANALOG"]["LABELS"]["value"] = tuple(channels)
    data["parameters"]["ANALOG"]["UNITS"]["value"] = list(channels.values())
    samples = int(frames * analog_rate / rate)
    data["data"]["analogs"] = np.zeros((1, len(channels), samples))
    data.write(str(path))
    return path


@pytest.mark.parametrize(
    ("kwargs", "field"),
    [
        ({"labels": MARKERS[:-1]}, "POINT:LABELS"),
        ({"labels": MARKERS, "units": "cm"}, "POINT:UNITS"),
        ({"labels": MARKERS, "rate": 30.0, "analog_rate": 300.0}, "POINT:RATE"),
        ({"labels": MARKERS, "rate": 1000.0, "analog_rate": 1000.0}, "POINT:RATE"),
        ({"labels": MARKERS, "analog_rate": 50.0}, "ANALOG:RATE"),  # not a whole multiple
        (
            {"labels": MARKERS, "channels": {"LC_ANKLE_1": "N", "LC_ANKLE_2": "N", "SYNC": "V"}},
            "ANALOG:LABELS",
        ),
        (
            {"labels": MARKERS, "channels": {**ANALOG_UNITS, "LC_SPRING": "V"}},
            "ANALOG:UNITS of LC_SPRING",
        ),
    ],
)
def test_contract_violations_name_file_and_field(tmp_path, kwargs, field):
    path = write_custom(tmp_path / "bad.c3d", **kwargs)
    with pytest.raises(InputError) as caught:
        c3d.read_trial(path)
    assert caught.value.field == field
    assert "bad.c3d" in str(caught.value)


def test_a_labs_labels_rates_and_metres_are_read_as_the_contract(tmp_path):
    labels = {name: f"Lab:{name.lower()}" for name in (*MARKERS, *ANALOG_UNITS)}
    channels = {labels[name]: unit for name, unit in ANALOG_UNITS.items()}
    path = write_custom(tmp_path / "lab.c3d", [labels[m] for m in MARKERS], units="m",
                        rate=120.0, channels=channels, analog_rate=2400.0)  # fmt: skip
    with pytest.raises(InputError) as caught:
        c3d.read_trial(path)  # without the map, the contract's names are missing
    assert caught.value.field == "POINT:LABELS" and "PH_HIP_MED" in caught.value.expected
    markers, analog = c3d.read_trial(path, labels)
    assert len(markers) == 20 and len(analog) == 200  # 24 frames at 120 Hz: 0.2 s
    np.testing.assert_allclose(markers.filter(like="_mm"), 1000.0)  # 1 m, in mm
    assert list(analog.columns) == ["t_s", *(f"{k}_{u}" for k, u in ANALOG_UNITS.items())]
    with pytest.raises(InputError, match=r"missing \['SpringEnd \(for EX_SPRING_B\)'\]"):
        c3d.read_trial(path, {**labels, "EX_SPRING_B": "SpringEnd"})


def test_missing_sync_is_accepted(tmp_path):
    channels = {k: v for k, v in ANALOG_UNITS.items() if k != "SYNC"}
    markers, analog = c3d.read_trial(
        write_custom(tmp_path / "nosync.c3d", MARKERS, channels=channels)
    )
    assert "SYNC_V" not in analog.columns and len(analog) == 10 * len(markers)


def test_unreadable_and_missing_files(tmp_path):
    (tmp_path / "junk.c3d").write_bytes(b"not a c3d")
    with pytest.raises(InputError, match="readable C3D"):
        c3d.read_trial(tmp_path / "junk.c3d")
    with pytest.raises(InputError, match="existing C3D"):
        c3d.read_trial(tmp_path / "absent.c3d")


def test_a_file_the_parser_has_not_read_in_time_is_refused_and_its_parser_ended(recordings):
    folder, _ = recordings
    path = sorted(folder.glob("*.c3d"))[0]
    before = _children()
    with pytest.raises(InputError, match="within 1e-06 s") as refused:
        c3d.read_recording(path, timeout_s=1e-6)  # no parse is this fast
    assert str(path) in str(refused.value) and "still reading" in str(refused.value)
    assert _children() <= before  # the parser's process killed and reaped
    assert c3d.read_recording(path, timeout_s=60.0).frames > 0  # in time: read as before


def _children() -> set[int]:
    """This process's child processes (zombies included: not yet reaped)."""
    found = set()
    for entry in (e for e in Path("/proc").iterdir() if e.name.isdigit()):
        try:
            stat = (entry / "stat").read_text().rsplit(")", 1)[1].split()
        except (OSError, IndexError):  # not a process, or one that has just ended
            continue
        if int(stat[1]) == os.getpid():
            found.add(int(entry.name))
    return found


@pytest.mark.parametrize(
    ("edit", "field"),
    [
        (lambda m: m.drop(columns="ramp_strides"), "ramp_strides"),
        (lambda m: m.assign(spring_stiffness_N_per_m="stiff"), "spring_stiffness_N_per_m"),
        (lambda m: m.assign(file="missing.c3d"), "file"),
        (lambda m: pd.concat([m, m.iloc[:1]]), "trial"),
    ],
)
def test_manifest_violations(recordings, tmp_path, edit, field):
    folder, _ = recordings
    manifest = edit(pd.read_csv(folder / "manifest.csv"))
    path = tmp_path / "manifest.csv"
    for file in pd.read_csv(folder / "manifest.csv")["file"]:
        (tmp_path / file).write_bytes(b"")
    manifest.to_csv(path, index=False)
    with pytest.raises(InputError) as caught:
        c3d.read_manifest(path)
    assert field in caught.value.field
    assert "manifest.csv" in str(caught.value)


def test_twin_refuses_to_overwrite_foreign_recordings(recordings, tmp_path):
    folder, trials = recordings
    files = twin_files(t.name for t in trials)
    stamp.check_writable(folder, files)  # the twin's own files may be rewritten
    stamp.check_writable(tmp_path, files)  # an empty folder too
    (tmp_path / "manifest.csv").write_text("trial,file\nlab1,lab1.c3d\n")
    with pytest.raises(InputError, match="acquisition=files"):
        stamp.check_writable(tmp_path, files)
    assert (tmp_path / "manifest.csv").read_text() == "trial,file\nlab1,lab1.c3d\n"
