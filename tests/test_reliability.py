"""Damaged and implausible recordings and configs: refused with file and field, or excluded."""

from __future__ import annotations

import copy
import hashlib
import os
import shutil
import socket
import subprocess
import sys
import time

import numpy as np
import pandas as pd
import pytest
import yaml

from conftest import snakemake
from exobench.emulator import config_rules as emulator_rules
from exobench.emulator.recordings import acquire as emulator_acquire
from exobench.errors import InputError
from exobench.phantom import config_rules as phantom_rules
from exobench.phantom.chain import segmentation, trial
from exobench.phantom.recordings import acquire, c3d
from exobench.phantom.rig import ANALOG_RATE_HZ, Rig
from exobench.plumbing import config_checks, provenance, results_lock, runner
from exobench.sts import config_rules as sts_rules
from phantom_helpers import workflow_config
from reliability_helpers import (
    EMULATOR_DURATION_S,
    edit_c3d,
    saturate,
    write_emulator,
    write_phantom,
)

CHAIN = workflow_config()["phantom"]["chain"]
SATURATION_RUN_S = CHAIN["glitches"]["saturation_run_s"]

# every group's cross-field checks, as the Snakefile runs them
NO_CODE = provenance.code_sha256([])  # a record's code hash: of no package file
SETTINGS_CHECKS = (phantom_rules.check, sts_rules.check, emulator_rules.check)


def screened(path):
    """Markers, analog channels and QC events of a trial, as the acquisition stage reads it."""
    return acquire.screened_trial(path, {}, CHAIN)


@pytest.fixture(scope="module")
def phantom_raw(tmp_path_factory):
    return write_phantom(tmp_path_factory.mktemp("raw") / "phantom")


@pytest.fixture(scope="module")
def emulator_raw(tmp_path_factory):
    return write_emulator(tmp_path_factory.mktemp("raw") / "emulator")


def first_trial(folder):
    return folder / pd.read_csv(folder / "manifest.csv")["file"].iloc[0]


def test_valid_recording_reads_without_saturation_or_glitch(phantom_raw):
    markers, analog, events = screened(first_trial(phantom_raw))
    assert len(analog) == 10 * len(markers) == 6 * 2000
    assert not analog["load_cell_saturated"].any()
    assert events.empty  # noisy, without occlusions: nothing to repair


def test_c3d_cut_in_half_is_refused(phantom_raw, tmp_path):
    data = first_trial(phantom_raw).read_bytes()
    (tmp_path / "half.c3d").write_bytes(data[: len(data) // 2])
    with pytest.raises(InputError) as caught:
        c3d.read_trial(tmp_path / "half.c3d")
    assert caught.value.field in ("POINT frames", "<file>")
    assert "half.c3d" in str(caught.value)


def test_short_c3d_is_refused_against_the_protocol(phantom_raw, tmp_path):
    markers, analog = c3d.read_trial(first_trial(phantom_raw))
    frames = 250  # 2.5 s: less than 2 ramp strides + 1 stride of 2 s
    c3d.write_trial(
        tmp_path / "short.c3d",
        {m: markers[[f"{m}_{a}_mm" for a in "xyz"]].to_numpy()[:frames] for m in c3d.MARKERS},
        {
            label: analog[f"{label}_{unit}"].to_numpy()[: frames * 10]
            for label, unit in c3d.ANALOG_UNITS.items()
        },
    )
    row = pd.read_csv(phantom_raw / "manifest.csv").iloc[0]
    settings = {"chain": CHAIN, "stride_time_s": 2.0, "min_spring_force_N": 5.0}
    with pytest.raises(InputError) as caught:
        trial.run(tmp_path / "short.c3d", row, settings, 0.6, Rig())
    assert caught.value.field == "POINT frames" and caught.value.found == frames
    assert "short.c3d" in str(caught.value) and "at least 600" in str(caught.value)


def test_saturated_load_cell_flags_only_its_samples(phantom_raw, tmp_path):
    start, stop = 4200, 5200  # 1 s inside stride 2
    path = edit_c3d(
        first_trial(phantom_raw), tmp_path / "sat.c3d", saturate("LC_ANKLE_2", start, stop)
    )
    _markers, analog, events = screened(path)
    flagged = np.flatnonzero(analog["load_cell_saturated"].to_numpy())
    assert flagged.min() == start and flagged.max() == stop - 1 and flagged.size == stop - start
    row = events[events["kind"] == "saturated"].iloc[0]
    assert (row["channel"], row["start_s"], row["end_s"]) == ("LC_ANKLE_2", 4.2, 5.2)


def test_saturated_samples_exclude_their_strides_with_the_reason():
    total, stride = 12000, 2000
    saturated = np.zeros(total, bool)
    saturated[4200:5200] = True
    table = segmentation.stride_table(
        np.arange(6) * stride,
        stride,
        total,
        1,
        np.zeros(total, bool),
        np.full(total, 50.0),
        5.0,
        saturated,
    )
    assert table.loc[2, "exclusion_reason"] == segmentation.SATURATED
    assert not table.loc[2, "included"] and not table.loc[2, "analysed"]
    assert table.loc[[1, 3, 4], "included"].all()


def test_short_flat_top_is_not_saturation():
    values = np.sin(np.linspace(0, 20, 5000))
    values[100 : 100 + round(SATURATION_RUN_S * ANALOG_RATE_HZ) - 1] = 2.0
    from exobench.plausibility import flat_runs_at_extremes

    assert not flat_runs_at_extremes(values, round(SATURATION_RUN_S * ANALOG_RATE_HZ), True).any()


def _all_saturated_trial(saturated: bool):
    total = 12000
    sync = np.zeros(total)
    sync[(np.arange(6) * 2000)[:, None] + np.arange(20)] = 5.0
    filtered = pd.DataFrame(
        {
            "SYNC_V": sync,
            "marker_gap": np.zeros(total, bool),
            "LC_SPRING_N": np.full(total, 50.0),
            "load_cell_saturated": np.full(total, saturated),
        }
    )
    return filtered


def test_trial_with_every_stride_excluded_is_one_input_error():
    args = (1, 0.75, CHAIN, 5.0, "trial k9200")
    assert segmentation.segment(_all_saturated_trial(False), None, *args)["included"].sum() == 4
    with pytest.raises(InputError) as caught:
        segmentation.segment(_all_saturated_trial(True), None, *args)
    assert caught.value.field == "strides" and "k9200" in str(caught.value)
    assert segmentation.SATURATED in str(caught.value)


def test_recording_without_strides_is_one_input_error():
    angles = pd.DataFrame({"phantom_knee_angle_rad": np.zeros(3000)})
    filtered = _all_saturated_trial(False).iloc[:3000].drop(columns="SYNC_V")
    with pytest.raises(InputError, match="two strides") as caught:
        segmentation.segment(filtered, angles, 1, 0.75, CHAIN, 5.0, "trial x")
    assert "trial x" in str(caught.value)


def _scale(label, factor, offset=0.0):
    def edit(_points, analogs, labels):
        row = labels.index(label)
        analogs[row] = factor * analogs[row] + offset * analogs[row].max()

    return edit


@pytest.mark.parametrize(
    ("edit", "field", "text"),
    [
        (_scale("LC_ANKLE_1", 1000.0), "ANALOG LC_ANKLE_1", "1000× too large"),
        (_scale("LC_SPRING", -1.0), "ANALOG LC_SPRING", "N within"),
        (_scale("LC_SPRING", -1.0, offset=1.0), "ANALOG LC_SPRING", "sign reversed"),
    ],
)
def test_implausible_channels_are_refused(phantom_raw, tmp_path, edit, field, text):
    source = first_trial(phantom_raw)
    before = source.read_bytes()
    path = edit_c3d(source, tmp_path / "bad.c3d", edit)
    with pytest.raises(InputError) as caught:
        screened(path)
    assert caught.value.field == field
    assert text in str(caught.value) and "bad.c3d" in str(caught.value)
    assert source.read_bytes() == before


def _jump(points, _analogs, _labels):
    points[0, 3, 500:505] += 80.0  # PH_KNEE_LAT moves 8 cm for 50 ms


def _transients(_points, analogs, labels):
    row = labels.index("LC_ANKLE_1")
    for start, sign in ((2300, 1.0), (4650, -1.0), (8820, 1.0)):  # 3 ms each, in three strides
        analogs[row, start : start + 3] = sign * 2000.0


@pytest.mark.parametrize(
    ("edit", "channel", "start_s", "end_s"),
    [(_jump, "PH_KNEE_LAT", 5.0, 5.05), (_transients, "LC_ANKLE_1", 2.3, 2.303)],
)
def test_a_jump_or_transients_are_repaired_not_refused(
    phantom_raw, tmp_path, edit, channel, start_s, end_s
):
    path = edit_c3d(first_trial(phantom_raw), tmp_path / "glitch.c3d", edit)
    markers, analog, events = screened(path)
    assert events["repair"].eq("filled").all() and set(events["channel"]) == {channel}
    first = events.iloc[0]
    assert first["start_s"] == pytest.approx(start_s) and first["end_s"] == pytest.approx(end_s)
    clean, _, _ = screened(first_trial(phantom_raw))
    in_frames = analog.isna().any(axis=1).to_numpy().reshape(-1, 10).any(1)
    blank = markers.isna().any(axis=1) | in_frames
    assert blank.sum() == (5 if channel.startswith("PH") else 3)  # only the glitch's frames
    pd.testing.assert_frame_equal(markers[~blank], clean[~blank])


@pytest.mark.parametrize(("content", "found"), [(b"", "an empty file"), (None, "a header only")])
@pytest.mark.parametrize("reader", [c3d.read_manifest, emulator_acquire.read_manifest])
def test_empty_and_header_only_manifests(phantom_raw, tmp_path, content, found, reader):
    header = (phantom_raw / "manifest.csv").read_text().splitlines()[0] + "\n"
    path = tmp_path / "manifest.csv"
    path.write_bytes(header.encode() if content is None else content)
    with pytest.raises(InputError) as caught:
        reader(path)
    assert caught.value.found == found and "manifest.csv" in str(caught.value)


@pytest.mark.parametrize("name", ["", "absent.csv"])
@pytest.mark.parametrize(
    ("reader", "folder", "column"),
    [
        (c3d.read_manifest, "phantom_raw", "file"),
        (emulator_acquire.read_manifest, "emulator_raw", "file"),
        (emulator_acquire.read_manifest, "emulator_raw", "mocap_file"),
    ],
)
def test_a_manifest_row_without_its_file_names_column_and_trial(
    request, tmp_path, reader, folder, column, name
):
    raw = request.getfixturevalue(folder)
    manifest = pd.read_csv(raw / "manifest.csv")
    for file in set(manifest["file"]) | set(manifest.get("mocap_file", [])):
        shutil.copy(raw / file, tmp_path / file)
    manifest.loc[1, column] = name
    manifest.to_csv(tmp_path / "manifest.csv", index=False)
    with pytest.raises(InputError) as caught:
        reader(tmp_path / "manifest.csv")
    assert caught.value.field == column
    assert f"trial {manifest['trial'].iloc[1]}" in caught.value.expected
    assert caught.value.found == (name or "an empty cell")


def _emulator_copy(emulator_raw, tmp_path, edit):
    source = emulator_raw / "v08_k35_brace.csv"
    frame = edit(pd.read_csv(source))
    frame.to_csv(tmp_path / "v08_k35_brace.csv", index=False)
    return tmp_path / "v08_k35_brace.csv"


def _reading(kind: str) -> dict:
    """The default config's reading settings for a brace or motion-capture file."""
    analysis = workflow_config()["emulator"]["analysis"]
    return {"max_gap_fraction": analysis["max_gap_fraction"],
            "rate_range_Hz": analysis[f"{kind}_rate_range_Hz"]}  # fmt: skip


@pytest.mark.parametrize(
    ("edit", "field", "text"),
    [
        (
            lambda f: f.assign(brace_torque_Nm=1000 * f["brace_torque_Nm"]),
            "brace_torque_Nm",
            "expected N·m, values look 1000× too large",
        ),
        (
            lambda f: f.assign(brace_angle_deg=f["brace_angle_deg"] + 200),
            "brace_angle_deg",
            "deg within",
        ),
        (lambda f: f.iloc[: len(f) // 2], "time_s", "6 s recorded"),
    ],
)
def test_emulator_implausible_or_short_recordings(emulator_raw, tmp_path, edit, field, text):
    path = _emulator_copy(emulator_raw, tmp_path, edit)
    with pytest.raises(InputError) as caught:
        emulator_acquire.read_brace(path, EMULATOR_DURATION_S, **_reading("brace"))
    assert caught.value.field == field and text in str(caught.value)
    assert "v08_k35_brace.csv" in str(caught.value)


def test_valid_emulator_recording_reads(emulator_raw):
    brace = emulator_acquire.read_brace(
        emulator_raw / "v08_k35_brace.csv", EMULATOR_DURATION_S, **_reading("brace")
    )
    mocap = emulator_acquire.read_mocap(
        emulator_raw / "v08_k35_mocap.csv", EMULATOR_DURATION_S, **_reading("mocap")
    )
    assert len(brace) == 1000 * EMULATOR_DURATION_S and len(mocap) == 100 * EMULATOR_DURATION_S


def _config_with(edit):
    config = copy.deepcopy(workflow_config())
    edit(config)
    return config


@pytest.mark.parametrize(
    ("edit", "keys"),
    [
        (
            lambda c: c["phantom"]["protocol"].update(test_order_N_per_m=[9200, 21700]),
            "test_order_N_per_m",
        ),
        (
            lambda c: c["phantom"]["protocol"].update(
                test_order_N_per_m=[9200, 21700, 13600, 6100, 3400, 3400]
            ),
            "test_order_N_per_m",
        ),
        (lambda c: c["phantom"]["protocol"].update(strides=10, ramp_strides=5), "ramp_strides"),
        (lambda c: c["phantom"]["calibration"].update(strides=10), "calibration.strides"),
        (lambda c: c["phantom"]["protocol"].update(clutch_off_pct=120.0), "clutch_off_pct"),
        (  # two samples of a 2 s stride: no stiffness slope
            lambda c: c["phantom"]["protocol"].update(clutch_on_pct=0.0, clutch_off_pct=0.1),
            "clutch_off_pct",
        ),
        (lambda c: c["phantom"]["protocol"].update(work_window_s=2.5), "work_window_s"),
        (lambda c: c["phantom"]["discrepancy"].update(window_pct=[0.0, 50.0]), "window_pct"),
        (lambda c: c["emulator"]["protocol"].update(speeds_m_per_s=[1.0]), "speeds_m_per_s"),
        (lambda c: c["sts"].update(sample_rate_Hz=7), "sts.sample_rate_Hz"),
        (
            lambda c: c["phantom"]["rig"].update(labels={"PH_HIP_MED": "Hip", "PH_HIP_LAT": "Hip"}),
            "phantom.rig.labels",
        ),
        (
            lambda c: c["emulator"].update(columns={"time_s": "t", "knee_flexion_deg": "t"}),
            "columns",
        ),
    ],
)
def test_cross_field_config_checks_name_the_keys(edit, keys):
    config_checks.check(workflow_config(), SETTINGS_CHECKS)
    with pytest.raises(InputError) as caught:
        config_checks.check(_config_with(edit), SETTINGS_CHECKS)
    assert keys in caught.value.field and str(caught.value).startswith("config:")


def test_provenance_names_inputs_relative_to_their_location(tmp_path, monkeypatch):
    records = []
    for name, reference in (("a", "raw/reference"), ("b", "elsewhere")):  # inside raw, or not
        root = tmp_path / name
        (root / "raw" / "phantom").mkdir(parents=True)
        (root / "res" / "x").mkdir(parents=True)
        (root / reference).mkdir(parents=True)
        (root / "raw" / "phantom" / "t.c3d").write_bytes(b"recording")
        (root / "res" / "x" / "t.parquet").write_bytes(b"table")
        (root / reference / "cycle.csv").write_bytes(b"reference")
        config = {"raw_dir": str(root / "raw"), "results_dir": str(root / "res"),
                  "reference_dir": str(root / reference), "seed": 0}  # fmt: skip
        inputs = [root / "res" / "x" / "t.parquet", root / "raw" / "phantom" / "t.c3d",
                  root / reference / "cycle.csv"]  # fmt: skip
        records.append(provenance.build("rule", inputs, {"seed": 0}, NO_CODE, config))
    assert records[0] == records[1]
    assert list(records[0]["inputs"]) == [
        "<raw_dir>/phantom/t.c3d",
        "<reference_dir>/cycle.csv",
        "<results_dir>/x/t.parquet",
    ]
    assert records[0]["inputs"]["<raw_dir>/phantom/t.c3d"] == provenance.sha256_file(
        tmp_path / "a" / "raw" / "phantom" / "t.c3d"
    )
    monkeypatch.chdir(tmp_path / "a")
    assert provenance.relative_name(tmp_path / "a" / "ref.csv", {}) == "ref.csv"


def test_every_input_is_hashed_from_its_bytes_and_left_untouched(tmp_path):
    """Provenance hashes each input's bytes on every read (a rewrite of the same size and time is
    seen) and writes nothing to the file: no attribute, the same bytes and times."""
    (tmp_path / "res" / "raw").mkdir(parents=True)
    table, raw = tmp_path / "res" / "t.parquet", tmp_path / "res" / "raw" / "t.c3d"
    table.write_bytes(b"table")
    raw.write_bytes(b"recording")
    past = time.time_ns() - 10**10
    for path in (table, raw):
        os.utime(path, ns=(past, past))
    config = {"raw_dir": str(tmp_path / "res" / "raw"), "results_dir": str(tmp_path / "res")}
    first = provenance.build("rule", [table, raw], {}, NO_CODE, config)["inputs"]
    assert first["<results_dir>/t.parquet"] == hashlib.sha256(b"table").hexdigest()
    assert first["<raw_dir>/t.c3d"] == hashlib.sha256(b"recording").hexdigest()
    table.write_bytes(b"TABLE")  # same size, same times: a new digest all the same
    os.utime(table, ns=(past, past))
    again = provenance.build("rule", [table], {}, NO_CODE, config)["inputs"]
    assert again["<results_dir>/t.parquet"] == hashlib.sha256(b"TABLE").hexdigest()
    for path in (table, raw):
        assert os.stat(path).st_mtime_ns == past
        assert not os.listxattr(path)


def test_lock_refuses_a_live_owner_and_takes_over_a_stale_one(tmp_path, caplog):
    path = results_lock.acquire(tmp_path)
    assert path.is_file() and results_lock.acquire(tmp_path) == path  # re-entrant for its owner
    results_lock.release(tmp_path)
    assert not path.exists()
    other = subprocess.Popen([sys.executable, "-c", "import time; time.sleep(30)"])
    try:
        path.write_text(f'{{"pid": {other.pid}, "host": "{socket.gethostname()}"}}')
        with pytest.raises(InputError, match="delete") as caught:
            results_lock.acquire(tmp_path)
        assert str(other.pid) in str(caught.value)
        results_lock.release(tmp_path)  # not ours: left alone
        assert path.is_file()
    finally:
        other.kill()
        other.wait()
    results_lock.acquire(tmp_path)  # the owner is gone: stale, taken over
    assert "stale" in caplog.text
    results_lock.release(tmp_path)
    assert not path.exists()


def test_recording_without_a_step_is_refused():
    empty = pd.DataFrame({"trial": [], "step": []})
    with pytest.raises(InputError, match="at least one step") as caught:
        emulator_acquire.check_steps("flat_brace.csv", empty)
    assert caught.value.field == "brace_angle_deg" and "flat_brace.csv" in str(caught.value)
    emulator_acquire.check_steps("ok.csv", pd.DataFrame({"step": [0]}))


def test_bad_input_at_dag_build_is_one_line_and_exit_2(workflow_copy, capsys):
    with pytest.raises(SystemExit) as stopped:
        runner.at_dag_build(config_checks.check, _config_with(
            lambda c: c["phantom"]["protocol"].update(strides=10, ramp_strides=5)),
            SETTINGS_CHECKS)  # fmt: skip
    assert stopped.value.code == 2
    assert capsys.readouterr().err.startswith("bad input: config: field 'phantom.protocol.strides")
    override = {"phantom": {"protocol": {"test_order_N_per_m": [9200, 9200]}}}
    (workflow_copy / "bad.yaml").write_text(yaml.safe_dump(override))
    process = snakemake(workflow_copy, "-n", "--configfile", "bad.yaml", check=False)
    assert process.returncode == 2
    assert "test_order_N_per_m" in process.stderr and "Traceback" not in process.stderr
    assert 'File "' not in process.stdout + process.stderr


def test_a_labs_own_emulator_columns_are_read_through_the_map(emulator_raw, tmp_path):
    names = {"time_s": "Time", "brace_angle_deg": "KneeEncoder", "knee_flexion_deg": "RKneeAngle"}
    for kind in ("brace", "mocap"):
        frame = pd.read_csv(emulator_raw / f"v08_k35_{kind}.csv")
        frame.rename(columns={k: v for k, v in names.items()}).to_csv(
            tmp_path / f"{kind}.csv", index=False
        )
    brace = emulator_acquire.read_brace(
        tmp_path / "brace.csv", EMULATOR_DURATION_S, names, **_reading("brace")
    )
    mocap = emulator_acquire.read_mocap(
        tmp_path / "mocap.csv", EMULATOR_DURATION_S, names, **_reading("mocap")
    )
    canonical = emulator_acquire.read_brace(
        emulator_raw / "v08_k35_brace.csv", EMULATOR_DURATION_S, **_reading("brace")
    )
    pd.testing.assert_frame_equal(brace, canonical)
    assert list(mocap.columns) == ["time_s", "knee_flexion_deg"]
    with pytest.raises(InputError) as caught:
        emulator_acquire.read_brace(
            tmp_path / "brace.csv", EMULATOR_DURATION_S, **_reading("brace")
        )
    assert caught.value.field == "time_s" and "brace.csv" in str(caught.value)
    with pytest.raises(InputError) as caught:
        emulator_acquire.read_brace(
            tmp_path / "brace.csv",
            EMULATOR_DURATION_S,
            {**names, "brace_angle_deg": "Encoder"},
            **_reading("brace"),
        )
    assert caught.value.field == "Encoder" and "emulator.columns" in caught.value.expected


def test_a_manifest_in_kN_per_m_is_refused_with_the_column_named(phantom_raw, tmp_path):
    manifest = pd.read_csv(phantom_raw / "manifest.csv")
    for file in manifest["file"]:
        shutil.copy(phantom_raw / file, tmp_path / file)
    rate = "spring_stiffness_N_per_m"
    manifest.assign(**{rate: manifest[rate] / 1000}).to_csv(tmp_path / "manifest.csv", index=False)
    with pytest.raises(InputError) as caught:
        c3d.read_manifest(tmp_path / "manifest.csv")
    assert caught.value.field == rate and "1000× too small" in str(caught.value)
    assert "N/m" in caught.value.expected and "manifest.csv" in str(caught.value)


def _metres_under_mm(points, _analogs, _labels):
    points[:3] *= 0.001


def _kN_under_N(_points, analogs, labels):
    for cell in ("LC_ANKLE_1", "LC_ANKLE_2", "LC_ANKLE_3"):
        analogs[labels.index(cell)] *= 0.001


@pytest.mark.parametrize(
    ("edit", "field", "slip"),
    [
        (_metres_under_mm, "POINT:UNITS", "markers look to be in metres while POINT:UNITS says mm"),
        (_kN_under_N, "ANALOG:UNITS of LC_ANKLE_1, LC_ANKLE_2, LC_ANKLE_3",
         "the ankle load cells look to be in kN"),
    ],
)  # fmt: skip
def test_a_recording_1000x_off_the_rig_is_refused_naming_the_slip(phantom_raw, tmp_path, edit,
                                                                  field, slip):  # fmt: skip
    path = edit_c3d(first_trial(phantom_raw), tmp_path / "slip.c3d", edit)
    with pytest.raises(InputError) as caught:
        screened(path)
    assert caught.value.field == field and slip in str(caught.value)
    assert "slip.c3d" in str(caught.value)


def test_an_unmapped_sync_channel_is_a_warning_and_a_qc_row(phantom_raw, tmp_path, caplog):
    import ezc3d

    data = ezc3d.c3d(str(first_trial(phantom_raw)))
    labels = [str(x).strip() for x in data["parameters"]["ANALOG"]["LABELS"]["value"]]
    data["parameters"]["ANALOG"]["LABELS"]["value"] = [
        "Trigger" if label == "SYNC" else label for label in labels
    ]
    path = tmp_path / "trigger.c3d"
    data.write(str(path))
    with caplog.at_level("WARNING", logger="exobench"):
        _markers, analog, events = screened(path)
    assert "SYNC_V" not in analog.columns
    warnings = [r.getMessage() for r in caplog.records if r.levelname == "WARNING"]
    assert len(warnings) == 1 and "trigger.c3d" in warnings[0]
    assert "'Trigger' is not mapped but looks like a sync pulse train" in warnings[0]
    assert "phantom.rig.labels: {SYNC: Trigger}" in warnings[0]
    row = events[events["channel"] == "Trigger"]
    assert row["kind"].tolist() == ["not mapped: looks like a sync pulse train"]
    assert row["repair"].tolist() == ["not read: map it with phantom.rig.labels"]
    _markers, analog, events = acquire.screened_trial(path, {"SYNC": "Trigger"}, CHAIN)
    assert "SYNC_V" in analog.columns and "Trigger" not in set(events["channel"])
