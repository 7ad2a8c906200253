"""Glitch detection, resampling and unit-slip naming on signals whose truth is known."""

from __future__ import annotations

import numpy as np
import pytest

from exobench import plausibility
from exobench.phantom.recordings import gaps, glitches, resample

RNG = np.random.default_rng(2028)


def path(frames: int = 600) -> np.ndarray:
    """A marker moving smoothly (mm at 100 Hz, up to ~4 mm per frame) with 0.15 mm noise."""
    t = np.arange(frames) / 100.0
    smooth = np.column_stack([120 * np.sin(2 * np.pi * 0.5 * t), 60 * np.cos(np.pi * t), 0 * t])
    return smooth + RNG.normal(0.0, 0.15, (frames, 3))


def test_gap_runs_and_their_lengths():
    mask = np.array([0, 1, 1, 0, 1, 0, 0, 1, 1, 1], bool)
    starts, lengths = gaps.runs(mask)
    assert starts.tolist() == [1, 4, 7] and lengths.tolist() == [2, 1, 3]
    assert gaps.run_length_at(mask).tolist() == [0, 2, 2, 0, 1, 0, 0, 3, 3, 3]


def test_resampling_keeps_the_canonical_rate_exact_and_a_gap_a_gap():
    values = RNG.normal(size=(50, 3))
    np.testing.assert_array_equal(resample.resample(values, 100.0, 100.0, 50), values)
    t = np.arange(100) / 100.0  # a quadratic at 100 Hz, read at 120 Hz: cubic convolution is exact
    out = resample.resample((3 * t**2 - t)[:, None], 100.0, 120.0, 118)[:, 0]
    inside = np.arange(2, 116)
    np.testing.assert_allclose(out[inside], 3 * (inside / 120) ** 2 - inside / 120, atol=1e-12)
    fast = np.sin(2 * np.pi * 70.0 * np.arange(400) / 200.0)  # 70 Hz: above 100 Hz's Nyquist
    folded = resample.resample(fast, 200.0, 100.0, 200)
    assert np.abs(folded[20:-20]).max() < 0.05  # not read back as a 30 Hz wave
    holed = (3 * t**2 - t).copy()
    holed[60] = np.nan
    out = resample.resample(holed, 120.0, 100.0, 99)
    missing = np.flatnonzero(np.isnan(out))
    assert missing.size and np.all(np.abs(missing / 100 - 60 / 120) < 2 / 120)  # near it only
    decimated = resample.resample(np.arange(20.0), 2000.0, 1000.0, 10)
    np.testing.assert_allclose(decimated, np.arange(0.0, 20.0, 2.0), atol=2e-3)  # a ramp stays


def test_a_fast_move_that_stays_is_motion_a_move_that_returns_is_a_glitch():
    xyz = path()
    xyz[300:, 0] += 21.0  # a recoil: 21 mm in one frame, and it stays
    assert not glitches.impulses(xyz, 7, 12.0, 5.0)[0].any()
    assert not glitches.paired_jumps(xyz, 7, 12.0, 5.0, 0.5)[0].any()
    ghost = xyz.copy()
    ghost[150] += [0.0, 80.0, 0.0]  # one ghost frame
    flagged, size = glitches.impulses(ghost, 7, 12.0, 5.0)
    assert np.flatnonzero(flagged).tolist() == [150] and size[150] == pytest.approx(80, rel=0.05)
    swapped = xyz.copy()
    swapped[420:445] += [90.0, -40.0, 15.0]  # a label swap for 25 frames: jumps out and back
    flagged, _ = glitches.paired_jumps(swapped, 7, 12.0, 5.0, 0.5)
    assert np.flatnonzero(flagged).tolist() == list(range(420, 445))


def test_the_ankle_cells_consensus_keeps_a_real_transient_and_finds_a_spike():
    samples = 6000
    force = 40 + 30 * np.sin(np.arange(samples) / 300.0)
    force[2000:2004] += [-40.0, -120.0, -90.0, -20.0]  # a real transient: every cell, its share
    shares = np.array([0.36, 0.33, 0.31])
    cells = force[:, None] * shares + RNG.normal(0.0, 0.5, (samples, 3))
    cells[4500, 1] += 300.0  # an electrical spike on one cell
    departure = np.abs(glitches.consensus(cells, 11, 12.0))
    flagged = np.argwhere(np.column_stack([glitches.outliers(d, 12.0, 20.0) for d in departure.T]))
    assert flagged.tolist() == [[4500, 1]]
    alone = np.abs(glitches.departure(cells[:, :1], 11))[:, 0]
    assert glitches.outliers(alone, 12.0, 20.0)[2000:2004].any()  # without the others, it would be


def test_the_marker_off_its_rigid_segment_is_named_and_a_pair_both():
    base = path()
    offsets = {"A": [0, 0, 0], "B": [0, 300, 0], "C": [0, 0, 90], "D": [50, 0, 0]}
    points = {name: base + np.array(offset) for name, offset in offsets.items()}
    points["B"][100:104] += [0.0, 0.0, 60.0]
    found = glitches.rigid_violations(points, [["A", "B", "C"], ["A", "D"]], 12.0, 5.0)
    assert np.flatnonzero(found["B"][0]).tolist() == [100, 101, 102, 103]
    assert not found["A"][0].any() and not found["C"][0].any() and not found["D"][0].any()
    points["D"][300] += [20.0, 0.0, 0.0]
    found = glitches.rigid_violations(points, [["A", "D"]], 12.0, 5.0)
    assert found["A"][0][300] and found["D"][0][300]  # two markers: either may be the ghost


@pytest.mark.parametrize(
    ("values", "text"),
    [
        (np.r_[np.full(990, 40.0), np.full(10, 2000.0)], "N within"),  # transients: no slip
        (np.full(1000, 40_000.0), "1000× too large"),  # the whole channel in mN
    ],
)
def test_a_unit_slip_is_named_only_when_the_whole_channel_scales(values, text):
    assert text in plausibility.range_expectation(values, plausibility.ChannelRange(-1e3, 1e3, "N"))


def test_a_spring_rate_in_kN_per_m_is_a_thousand_times_too_small():
    plausible = plausibility.ChannelRange(200.0, 500_000.0, "N/m")
    assert "1000× too small" in plausibility.range_expectation(np.array([3.4, 21.7]), plausible)
