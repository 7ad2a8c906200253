"""Gait events and clutch state recomputed offline from a brace recording (Tables 5.1, 6.1).

The controller's causal velocity estimate (:mod:`controller`) and the rules of Tables 5.1 and
6.1, evaluated over the whole recording: candidate samples are found with array operations, then
the few candidates per stride are walked in time order to honour the flags (a peak extension
needs a peak flexion before it, a heel strike a peak extension).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from exobench import signals
from exobench.emulator.chain.controller import lowpass
from exobench.emulator.rig import (
    CLUTCH_ANGLE_DEG,
    HEEL_STRIKE_DEG,
    PEAK_FLEXION_DEG,
)


@dataclass(frozen=True)
class Detected:
    """Sample indices of the events and the clutch state per sample."""

    peak_flexion: np.ndarray
    peak_extension: np.ndarray
    heel_strike: np.ndarray
    engaged: np.ndarray


def brace_velocity(angle_deg: np.ndarray, cutoff_Hz: float, rate_Hz: float) -> np.ndarray:
    """Causal velocity (deg/s): backward difference through the 6 Hz low-pass of the controller,
    both at the recording's rate ``rate_Hz``."""
    raw = np.concatenate([[0.0], np.diff(angle_deg) * rate_Hz])
    return signals.cascade(lowpass(cutoff_Hz, rate_Hz), raw)


def previous(omega: np.ndarray) -> np.ndarray:
    """The velocity one sample earlier (0 before the first), as the controller compares them."""
    return np.concatenate([[0.0], omega[:-1]])


def detect(angle_deg: np.ndarray, omega: np.ndarray) -> Detected:
    """Table 5.1 events (knee) and the Table 6.1 clutch over a whole recording."""
    prev = previous(omega)
    flexion_peak = np.flatnonzero((angle_deg > PEAK_FLEXION_DEG) & (prev >= 0.0) & (omega < 0.0))
    turn_up = np.flatnonzero((prev <= 0.0) & (omega > 0.0))
    rising = np.flatnonzero((angle_deg < HEEL_STRIKE_DEG) & (omega > prev))
    peak_flexion, peak_extension, heel_strike = [], [], []
    k = 0
    while k < len(flexion_peak):
        start = flexion_peak[k]
        peak_flexion.append(start)
        j = np.searchsorted(turn_up, start, side="right")
        if j == len(turn_up):
            break
        extension = turn_up[j]
        k = np.searchsorted(flexion_peak, start, side="right")
        if k < len(flexion_peak) and flexion_peak[k] <= extension:
            continue  # a new peak flexion came first: it restarts the sequence
        peak_extension.append(extension)
        h = np.searchsorted(rising, extension, side="right")
        next_flexion = flexion_peak[k] if k < len(flexion_peak) else len(angle_deg)
        if h < len(rising) and rising[h] < next_flexion:
            heel_strike.append(rising[h])
    return Detected(
        np.array(peak_flexion, dtype=int),
        np.array(peak_extension, dtype=int),
        np.array(heel_strike, dtype=int),
        clutch(angle_deg, omega),
    )


def clutch(angle_deg: np.ndarray, omega: np.ndarray, latched: bool = False) -> np.ndarray:
    """Table 6.1: engaged from a peak flexion above 40° to the next peak extension (``latched``:
    an arm that stays set once the knee has passed 40°, so from every peak flexion after that)."""
    prev = previous(omega)
    armed = angle_deg > CLUTCH_ANGLE_DEG
    if latched:
        armed = np.maximum.accumulate(armed)
    engage = np.flatnonzero(armed & (prev > 0.0) & (omega <= 0.0))
    release = np.flatnonzero((prev < 0.0) & (omega >= 0.0))
    engaged = np.zeros(len(angle_deg), dtype=bool)
    position = 0
    while True:
        e = np.searchsorted(engage, position, side="left")
        if e == len(engage):
            break
        on = engage[e]
        r = np.searchsorted(release, on, side="right")
        off = release[r] if r < len(release) else len(angle_deg)
        engaged[on:off] = True
        position = off
    return engaged
