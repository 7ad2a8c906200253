"""Treadmill knee-flexion trajectories: a normative cycle with speed-dependent shape and timing.

The cycle is a periodic cubic spline through landmarks of able-bodied knee flexion (heel strike
at 0 %, loading-response peak, mid-stance minimum, swing peak, terminal-swing extension); the
loading and swing peaks and the stride time depend on walking speed (config). Stride-to-stride
variability scales each stride's duration and excursion.
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import TYPE_CHECKING

import numpy as np

from exobench.emulator.rig import LANDMARK_PCT

if TYPE_CHECKING:
    from scipy.interpolate import CubicSpline


def _landmark_angles(shape: Mapping) -> list[float]:
    return [
        shape["heel_strike_deg"],
        shape["loading_peak_deg"],
        shape["midstance_min_deg"],
        shape["toe_off_deg"],
        shape["swing_peak_deg"],
        0.5 * (shape["swing_peak_deg"] + shape["peak_extension_deg"]),
        shape["peak_extension_deg"],
        shape["heel_strike_deg"],
    ]


def shape_for(shapes: list[Mapping], speed_m_per_s: float) -> Mapping:
    """The configured gait shape of a walking speed."""
    for shape in shapes:
        if abs(shape["speed_m_per_s"] - speed_m_per_s) < 1e-9:
            return shape
    raise KeyError(f"no gait shape for {speed_m_per_s} m/s in emulator.gait.shapes")


def cycle(shape: Mapping) -> CubicSpline:
    """Periodic knee-flexion cycle (deg) over the gait-cycle fraction 0–1."""
    # imported here: the config check at every DAG build reads this module (scipy takes ~1 s)
    from scipy.interpolate import CubicSpline

    return CubicSpline(np.array(LANDMARK_PCT) / 100.0, _landmark_angles(shape), bc_type="periodic")


def trajectory(
    shape: Mapping, duration_s: float, rate_Hz: float, variability: Mapping, rng
) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """Knee flexion (deg) at ``rate_Hz`` for ``duration_s``, the heel-strike times from the first
    sample to the last, cycle phase (0–1).

    Each stride's duration is the nominal stride time × N(1, CV); each stride's excursion about
    the heel-strike angle is scaled by N(1, amplitude CV); the cycle starts at a random phase.
    """
    spline = cycle(shape)
    stride = shape["stride_time_s"]
    count = int(np.ceil(duration_s / stride)) + 3
    durations = stride * (1.0 + variability["stride_time_cv"] * rng.standard_normal(count))
    scales = 1.0 + variability["amplitude_cv"] * rng.standard_normal(count)
    start = -rng.uniform(0.0, 1.0) * durations[0]
    heel_strikes = start + np.concatenate([[0.0], np.cumsum(durations)])
    t = np.arange(round(duration_s * rate_Hz)) / rate_Hz
    k = np.searchsorted(heel_strikes, t, side="right") - 1
    phase = (t - heel_strikes[k]) / durations[k]
    base = shape["heel_strike_deg"]
    angle = base + scales[k] * (spline(phase) - base)
    inside = heel_strikes[(heel_strikes >= 0.0) & (heel_strikes <= t[-1])]  # recorded ones
    return t, angle, inside, phase
