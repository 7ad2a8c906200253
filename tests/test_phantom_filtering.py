"""The filter stage's two files: marker paths apart from the 1000 Hz channels and flags."""

from __future__ import annotations

import numpy as np
import pandas as pd
from scipy.interpolate import CubicSpline

from exobench.phantom.chain import angles, filtering


def test_split_gives_the_markers_at_their_rate_and_the_channels_every_column_once():
    rng = np.random.default_rng(0)
    columns = ["t_s", *filtering.MARKER_COLUMNS, "LC_SPRING_N", "SYNC_V", "marker_gap"]
    filtered = pd.DataFrame(rng.normal(size=(50, len(columns))), columns=columns)
    markers, channels = filtering.split(filtered)
    assert list(markers.columns) == ["t_s", *filtering.MARKER_COLUMNS]
    assert list(channels.columns) == ["t_s", "LC_SPRING_N", "SYNC_V", "marker_gap"]
    every_frame = filtered.iloc[::10].reset_index(drop=True)
    pd.testing.assert_frame_equal(markers, every_frame[markers.columns])
    pd.testing.assert_frame_equal(channels, filtered[channels.columns])


def test_the_markers_file_at_100_hz_gives_back_the_1000_hz_paths():
    """The filtered marker paths the later stages use (1000 Hz) are the cubic spline through
    the 100 Hz file's rows: the file keeps everything the chain used."""
    rng = np.random.default_rng(1)
    frames = 400
    t_points = np.arange(frames) / 100.0
    markers = pd.DataFrame({"t_s": t_points})
    for i, name in enumerate(filtering.MARKER_COLUMNS):
        markers[name] = 100.0 * np.sin(2 * np.pi * 0.5 * t_points + i) + rng.normal(0, 0.2, frames)
    t = np.arange(frames * 10) / 1000.0
    analog = pd.DataFrame({"t_s": t, "LC_SPRING_N": 20.0 + rng.normal(0, 0.5, t.size)})
    chain = {"filter_cutoff_Hz": 6.0, "filter_order": 4, "max_gap_frames": 10}
    filtered = filtering.filter_trial(markers, analog, chain, "test")
    at_100_hz, _ = filtering.split(filtered)
    columns = filtering.MARKER_COLUMNS
    again = CubicSpline(at_100_hz["t_s"], at_100_hz[columns].to_numpy(), axis=0)(t)
    np.testing.assert_allclose(again, filtered[columns].to_numpy(), rtol=0, atol=1e-9)


def test_the_angles_file_and_the_100_hz_markers_give_back_the_joint_centres():
    """The angles stage's file keeps its own columns; its joint centres (the filtered markers'
    midpoints) come back from the filtered stage's 100 Hz file as the chain computed them."""
    rng = np.random.default_rng(2)
    frames = 300
    t_points = np.arange(frames) / 100.0
    markers = pd.DataFrame({"t_s": t_points})
    for i, name in enumerate(filtering.MARKER_COLUMNS):
        base = 300.0 * (i % 5) + 50.0 * np.cos(2 * np.pi * 0.5 * t_points + i)
        markers[name] = base + rng.normal(0, 0.2, frames)
    t = np.arange(frames * 10) / 1000.0
    analog = pd.DataFrame({"t_s": t, "LC_SPRING_N": 20.0 + rng.normal(0, 0.5, t.size)})
    chain = {"filter_cutoff_Hz": 6.0, "filter_order": 4, "max_gap_frames": 10}
    filtered = filtering.filter_trial(markers, analog, chain, "test")
    whole = angles.knee_angles(filtered)
    at_100_hz, _ = filtering.split(filtered)
    again = angles.with_centres(whole[angles.OWN_COLUMNS], at_100_hz)
    assert list(again.columns) == list(whole.columns)
    np.testing.assert_allclose(again.to_numpy(), whole.to_numpy(), rtol=0, atol=1e-9)
