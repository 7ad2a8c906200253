"""The walker's knee on the treadmill: a smooth gait through per-stride landmarks that vary from
stride to stride, and its phase (0 at heel strike, 1 at the next)."""

from typing import NamedTuple

import numpy as np
from scipy.interpolate import CubicSpline

# One stride's knee-flexion landmarks from heel strike (chosen: typical able-bodied treadmill
# walking; the loading peak after heel strike, the stance minimum, toe-off, the swing peak, and
# the peak extension of terminal swing just before the next heel strike): % of the stride →
# degrees at 0.8 and at 1.2 m/s, linear in the speed between and beyond; stride times likewise.
PHASE_PCT = np.array([0.0, 6.0, 14.0, 28.0, 42.0, 52.0, 60.0, 67.0, 73.0, 80.0, 87.0, 93.0, 97.0])
SLOW_DEG = np.array([3.0, 9.0, 14.0, 10.0, 5.0, 8.0, 20.0, 41.0, 57.5, 53.0, 34.0, 13.0, 2.5])
FAST_DEG = np.array([3.0, 11.0, 19.0, 12.0, 6.0, 9.0, 24.0, 46.0, 61.0, 56.0, 36.0, 13.0, 2.0])
SLOW_FAST_M_PER_S = (0.8, 1.2)
STRIDE_S = (1.22, 1.08)
# Stride-to-stride variability (chosen): stride time and the stride's amplitude vary by these
# coefficients of variation, each landmark by this SD besides.
STRIDE_CV, AMPLITUDE_CV, LANDMARK_SD_DEG = 0.02, 0.03, 0.7


class Gait(NamedTuple):
    """The knee's flexion (deg) as a C² spline of time (s) and the heel strikes (s) it walks by."""

    knee: CubicSpline
    heel_strikes: np.ndarray


def stride_shape(speed_m_per_s: float) -> tuple[np.ndarray, float]:
    """Landmarks (deg) and stride time (s) at a speed: linear in v through the two anchors."""
    slow, fast = SLOW_FAST_M_PER_S
    w = (speed_m_per_s - slow) / (fast - slow)
    return (1 - w) * SLOW_DEG + w * FAST_DEG, (1 - w) * STRIDE_S[0] + w * STRIDE_S[1]


def treadmill_gait(
    speed_m_per_s: float, start_s: float, stop_s: float, rng: np.random.Generator
) -> Gait:
    """θ(t) through stride i's landmarks a_i·θ_j + e_ij at h_i + p_j·T_i, T_i = T(1 + cv·z_i)."""
    if not speed_m_per_s > 0.0:
        raise ValueError(f"the treadmill's speed must be > 0 m/s, got {speed_m_per_s}")
    shape, stride = stride_shape(speed_m_per_s)
    count = int(np.ceil((stop_s - start_s) / (stride * (1 - 4 * STRIDE_CV)))) + 4
    durations = stride * (1.0 + STRIDE_CV * rng.standard_normal(count))
    amplitudes = 1.0 + AMPLITUDE_CV * rng.standard_normal(count)
    jitter = LANDMARK_SD_DEG * rng.standard_normal((count, shape.size))
    first = start_s - stride * (1.0 + rng.random())  # the walk began earlier, at any phase
    heel = first + np.concatenate([[0.0], np.cumsum(durations)])
    times = heel[:-1, None] + PHASE_PCT[None, :] / 100.0 * durations[:, None]
    values = amplitudes[:, None] * shape[None, :] + jitter
    return Gait(CubicSpline(times.ravel(), values.ravel()), heel)


def gait_phase(gait: Gait, t: np.ndarray) -> np.ndarray:
    """φ = (t − h_i)/(h_{i+1} − h_i) for h_i ≤ t < h_{i+1}: 0 at heel strike, 1 at the next."""
    i = np.clip(np.searchsorted(gait.heel_strikes, t, side="right") - 1, 0, None)
    i = np.minimum(i, gait.heel_strikes.size - 2)
    start, end = gait.heel_strikes[i], gait.heel_strikes[i + 1]
    return (t - start) / (end - start)
