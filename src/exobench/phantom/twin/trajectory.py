"""Knee-flexion trajectories the hexapod imposes on the phantom (seed 000 §2.3, docs/rig.md §1)."""

from __future__ import annotations

import numpy as np
from scipy.interpolate import PchipInterpolator

EXTREMUM_PROMINENCE_DEG = 0.5


def cycle_extrema(flexion_deg: np.ndarray) -> np.ndarray:
    """Indices of the stride boundary (0 %) and every peak and valley of a mean cycle."""
    peaks = prominent_peaks(flexion_deg, EXTREMUM_PROMINENCE_DEG)
    valleys = prominent_peaks(-flexion_deg, EXTREMUM_PROMINENCE_DEG)
    return np.unique(np.concatenate([[0], peaks, valleys]))


def prominent_peaks(values: np.ndarray, prominence: float) -> np.ndarray:
    """Local maxima rising at least ``prominence`` above the higher of their two bases.

    A flat top counts at its middle sample (rounded down); a peak's base on each side is the
    lowest value between it and the nearest higher sample (or the signal's end). This is the
    definition of scipy.signal.find_peaks, written here so that the twin and its calibration
    need not import scipy.signal (about 1.3 s of each job's start-up). Finite values only; the
    cost grows with peaks × samples, meant for a mean cycle's few extrema.
    """
    values = np.asarray(values, float)
    if not np.isfinite(values).all():
        raise ValueError("prominent_peaks needs finite values")
    if values.size < 3:
        return np.zeros(0, dtype=int)
    change = np.flatnonzero(np.diff(values) != 0)
    starts = np.concatenate([[0], change + 1])  # runs of equal values
    ends = np.concatenate([change, [values.size - 1]])
    level = values[starts]
    inner = np.arange(1, starts.size - 1)
    top = inner[(level[inner - 1] < level[inner]) & (level[inner + 1] < level[inner])]
    kept = []
    for peak in (starts[top] + ends[top]) // 2:  # each step vectorised over the samples
        higher = np.flatnonzero(values > values[peak])
        left = higher[higher < peak]
        right = higher[higher > peak]
        left_base = values[(left[-1] + 1 if left.size else 0) : peak + 1].min()
        right_base = values[peak : (right[0] if right.size else values.size)].min()
        if values[peak] - max(left_base, right_base) >= prominence:
            kept.append(peak)
    return np.array(kept, dtype=int)


def programmed_trials(
    mean_cycle_deg: np.ndarray,
    strides: int,
    ramp_strides: int,
    sd_deg: float,
    rng: np.random.Generator,
) -> np.ndarray:
    """Knee flexion (deg) of every programmed stride, shape (strides, samples per stride).

    Every extremum of the mean cycle (and the stride boundary, shared by neighbouring strides)
    is shifted by N(0, sd); the shifts are joined by one shape-preserving cubic (PCHIP) over the
    whole trial, so timings stay fixed and the trajectory is smooth across stride boundaries.
    The hexapod's ramp strides scale the motion about the start angle from 0 to 1 and back.
    """
    samples = mean_cycle_deg.size
    knots_in_cycle = cycle_extrema(mean_cycle_deg)
    knots = (np.arange(strides)[:, None] * samples + knots_in_cycle[None, :]).ravel()
    knots = np.append(knots, strides * samples)
    shifts = rng.normal(0.0, sd_deg, size=knots.size)
    offset = PchipInterpolator(knots, shifts)(np.arange(strides * samples))
    flexion = np.tile(mean_cycle_deg, strides) + offset
    return ramp(flexion, samples, ramp_strides).reshape(strides, samples)


def ramp(flexion_deg: np.ndarray, samples: int, ramp_strides: int) -> np.ndarray:
    """Scale the motion about its start angle by a smooth 0→1 ramp in and 1→0 ramp out."""
    if ramp_strides == 0:
        return flexion_deg
    total = flexion_deg.size
    position = np.arange(total) / (ramp_strides * samples)
    rising = np.clip(position, 0.0, 1.0)
    falling = np.clip((total - 1 - np.arange(total)) / (ramp_strides * samples), 0.0, 1.0)
    scale = smoothstep(np.minimum(rising, falling))
    start = flexion_deg[0]
    return start + scale * (flexion_deg - start)


def smoothstep(x: np.ndarray) -> np.ndarray:
    """Cubic smooth step 3x² − 2x³ on [0, 1]."""
    return x * x * (3.0 - 2.0 * x)
