"""The phantom analysis chain against the twin's truth, and its documented behaviours."""

from __future__ import annotations

import numpy as np
import pandas as pd
import pytest
import yaml
from scipy.signal import butter, sosfreqz

from conftest import SMALL_RUN
from exobench import tables
from exobench.phantom.chain import filtering, metrics, segmentation
from exobench.phantom.chain import kinetics as chain_kinetics
from exobench.phantom.rig import ANALOG_RATE_HZ
from phantom_helpers import workflow_config

# shares the small run (its tests touch its folder): one pytest-xdist worker runs the group
pytestmark = [pytest.mark.slow, SMALL_RUN]

DT = 1.0 / ANALOG_RATE_HZ


@pytest.fixture
def chain(small_run):
    return small_run


def truth_pairs(root, trial):
    folder = root / "results/phantom"
    files = {kind: folder / kind / f"{trial}.parquet" for kind in ("kinetics", "angles", "moments")}
    kinetics = chain_kinetics.read(
        {**files, "filtered": folder / f"filtered/{trial}_analog.parquet"}
    )
    truth = tables.read_table(root / "raw/phantom/truth" / f"{trial}.parquet").data
    index = np.round(kinetics["t_s"].to_numpy() * ANALOG_RATE_HZ).astype(int)
    return kinetics, truth, index


def trials(root):
    return pd.read_csv(root / "raw/phantom/manifest.csv")["trial"].tolist()


def test_kinetics_match_truth(chain):
    for trial in trials(chain):
        kinetics, truth, index = truth_pairs(chain, trial)
        strides = kinetics["stride"].nunique()
        moment_error = kinetics["knee_moment_Nm"] - truth["knee_moment_Nm"].to_numpy()[index]
        rmse = np.sqrt((moment_error.to_numpy().reshape(strides, -1) ** 2).mean(1))
        assert rmse.mean() < 0.2, (trial, rmse.mean())
        errors = {}
        for angle in ("phantom_knee_angle_rad", "exo_knee_angle_rad"):
            errors[angle] = np.rad2deg(kinetics[angle].to_numpy() - truth[angle].to_numpy()[index])
            per_stride = np.sqrt((errors[angle].reshape(strides, -1) ** 2).mean(1))
            assert per_stride.max() < 0.3, (trial, angle, per_stride.max())
        assert np.abs(errors["phantom_knee_angle_rad"]).max() < 0.3


def test_stride_metrics_match_truth(chain):
    table = tables.read_table(chain / "results/phantom/metrics.parquet").data
    protocol = yaml.safe_load((chain / "config/config.yaml").read_text())["phantom"]["protocol"]
    for trial in trials(chain):
        kinetics, truth, index = truth_pairs(chain, trial)
        numbers = kinetics["stride"].unique()
        columns = [*metrics.SIGNALS, "spring_extension_m"]
        whole = {c: truth[c].to_numpy() for c in columns}
        powers = metrics.power_partition(*(whole[c] for c in columns), DT)
        grid = index.reshape(numbers.size, -1)
        signals = {c: whole[c][grid] for c in metrics.SIGNALS}
        expected = metrics.stride_metrics(
            signals, {c: p[grid] for c, p in powers.items()}, DT, protocol
        )
        rows = table[table["trial"] == trial].set_index("stride").loc[numbers]
        for column in metrics.WORK_COLUMNS:
            error = np.abs(rows[column].to_numpy() - expected[column])
            assert error.mean() < 0.02, (trial, column, error.mean())
        for column in ("phantom_stance_flexion_deg", "exo_stance_flexion_deg"):
            error = np.abs(rows[column].to_numpy() - expected[column])
            assert error.mean() < 0.3, (trial, column, error.mean())


def test_every_programmed_stride_keeps_a_row(chain):
    table = tables.read_table(chain / "results/phantom/metrics.parquet").data
    for _, rows in table.groupby("trial"):
        assert rows["stride"].tolist() == list(range(30))
        ramps = rows[rows["exclusion_reason"] == segmentation.RAMP]["stride"].tolist()
        assert ramps == [0, 1, 2, 3, 4, 25, 26, 27, 28, 29]
        assert rows["peak_moment_Nm"].notna().sum() == 20
        low = rows["exclusion_reason"] == segmentation.LOW_FORCE
        assert not rows.loc[low, "included"].any()
        assert rows.loc[rows["included"], "exclusion_reason"].eq("").all()


def test_the_filter_stage_writes_markers_at_their_rate_and_channels_at_the_analog_rate(chain):
    trial = trials(chain)[0]
    folder = chain / "results/phantom/filtered"
    markers = tables.read_table(folder / f"{trial}_markers.parquet").data
    channels = tables.read_table(folder / f"{trial}_analog.parquet").data
    assert list(markers.columns) == ["t_s", *filtering.MARKER_COLUMNS]
    assert {"LC_SPRING_N", "SYNC_V", "marker_gap"} <= set(channels.columns)
    per_frame = round(ANALOG_RATE_HZ / 100.0)  # the markers' own 100 Hz
    np.testing.assert_array_equal(markers["t_s"], channels["t_s"].to_numpy()[::per_frame])


def test_missing_sync_falls_back_to_kinematics(chain):
    trial = trials(chain)[0]
    filtered = tables.read_table(
        chain / "results/phantom/filtered" / f"{trial}_analog.parquet"
    ).data
    angles = tables.read_table(chain / "results/phantom/angles" / f"{trial}.parquet").data
    args = (5, 0.7495, workflow_config()["phantom"]["chain"], 5.0, trial)
    with_sync = segmentation.segment(filtered, angles, *args)
    without = segmentation.segment(filtered.drop(columns="SYNC_V"), angles, *args)
    assert with_sync["segmentation"].iloc[0] == "sync"
    assert without["segmentation"].iloc[0] == "kinematics"
    assert len(without) == len(with_sync)
    offset = np.abs(without["start_s"] - with_sync["start_s"])
    assert offset.max() < 0.015


def test_gaps_short_are_filled_long_exclude_their_stride(chain):
    trial = trials(chain)[1]
    markers = tables.read_table(chain / "results/phantom/acquired" / f"{trial}_markers.parquet")
    analog = tables.read_table(chain / "results/phantom/acquired" / f"{trial}_analog.parquet")
    data = markers.data.copy()
    column = "PH_KNEE_LAT_x_mm"
    reference = data[column].interpolate().to_numpy()
    data.loc[1210:1217, column] = np.nan  # 8 frames: filled (limit 10)
    data.loc[1630:1660, column] = np.nan  # 31 frames in stride 8: excluded
    settings = {"filter_cutoff_Hz": 6.0, "filter_order": 4, "max_gap_frames": 10}
    filtered = filtering.filter_trial(data, analog.data, settings, "test")
    short = filtered[column].to_numpy()[12100:12180:10]
    assert np.abs(short - reference[1210:1218]).max() < 1.0
    flags = filtered["marker_gap"].to_numpy()
    assert flags[16300:16610].all() and not flags[12100:12180].any()
    table = segmentation.stride_table(
        np.arange(30) * 2000,
        2000,
        len(filtered),
        5,
        flags,
        np.full(len(filtered), 20.0),
        5.0,
        filtered["load_cell_saturated"].to_numpy(),
    )
    assert table.loc[8, "exclusion_reason"] == segmentation.GAP
    assert table.loc[6, "exclusion_reason"] == ""


def test_butterworth_is_zero_phase_and_minus_3db_at_cutoff():
    rate, cutoff, order = 100.0, 6.0, 4
    sos = butter(order // 2, filtering.pass_cutoff_hz(rate, cutoff, order), fs=rate, output="sos")
    _, response = sosfreqz(sos, worN=[cutoff], fs=rate)
    assert np.abs(response[0]) ** 2 == pytest.approx(1 / np.sqrt(2), rel=1e-9)
    t = np.arange(400) / rate
    slow = np.sin(2 * np.pi * 1.0 * t)
    out = filtering.butterworth_zero_phase(slow[:, None], rate, cutoff, order)[:, 0]
    lag = np.argmax(np.correlate(out[100:300], slow[100:300], "full")) - 199
    assert lag == 0
    fast = np.sin(2 * np.pi * 6.0 * t)
    gain = np.std(filtering.butterworth_zero_phase(fast[:, None], rate, cutoff, order)[100:300])
    assert gain / np.std(fast[100:300]) == pytest.approx(1 / np.sqrt(2), rel=0.02)
