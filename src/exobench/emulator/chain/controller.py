"""The emulator controller's laws the analysis reuses (seed 002 ch. 5), vectorised.

- brace velocity: backward difference of the encoder angle through a 2nd-order Butterworth
  low-pass (6 Hz), the causal estimate the controller sees;
- recorded brace torque: the load cell through the same kind of low-pass (20 Hz, §5.2);
- direction blend of eq. (5.8) between the extension and flexion calibrations;
- the pulley ratio A, the transmission calibration b(τ) of eqs. (5.6)–(5.7) and its inverse,
  the cable torque.

The twin runs its own controller, sample by sample (:mod:`twin_loop`).
"""

from __future__ import annotations

import functools
from collections.abc import Mapping

import numpy as np

from exobench import signals


def lowpass(cutoff_Hz: float, rate_Hz: float) -> np.ndarray:
    """Second-order sections of the controller's causal 2nd-order Butterworth low-pass (the
    brace velocity's, the load cell's)."""
    return signals.butterworth(2, cutoff_Hz, rate_Hz)


def recorded_torque_Nm(torque_Nm: np.ndarray, cutoff_Hz: float | None, rate_Hz: float):
    """A torque as the real-time model records it (Heer §5.2): through the causal low-pass along
    the last axis, each row settled on its first sample; unchanged when ``cutoff_Hz`` is None."""
    if cutoff_Hz is None:
        return torque_Nm
    # the engine filters its prediction at every evaluation: scipy's lfilter runs the recursion
    # about 3× faster than the banded solve of signals.causal (the per-trial chain never calls it)
    from scipy.signal import lfilter

    b, a, settled = _settled_lowpass(float(cutoff_Hz), float(rate_Hz))
    torque_Nm = np.asarray(torque_Nm, float)
    return lfilter(b, a, torque_Nm, axis=-1, zi=np.multiply.outer(torque_Nm[..., 0], settled))[0]


@functools.cache
def _settled_lowpass(cutoff_Hz: float, rate_Hz: float) -> tuple[np.ndarray, ...]:
    """(b, a) of :func:`lowpass` and its state settled on a unit input (designed once: the
    engine filters its torque prediction at every evaluation)."""
    (section,) = lowpass(cutoff_Hz, rate_Hz)
    return section[:3], section[3:], signals.settled_state(section)


def direction_weight(omega_deg_per_s, blend_deg_per_s: float):
    """Weight of the extension reference in eq. (5.8): 1 below −blend, 0 above +blend."""
    return np.minimum(np.maximum(0.5 - omega_deg_per_s / (2.0 * blend_deg_per_s), 0.0), 1.0)


def pulley_ratio(transmission: Mapping) -> float:
    """A = r_brace / r_motor (eq. 5.6)."""
    return transmission["brace_pulley_radius_m"] / transmission["motor_pulley_radius_m"]


def cable_offset_deg(torque_Nm, coefficients: Mapping):
    """The calibration's cable offset at a torque: b(τ) = B·τ² + C·τ + D (eqs. 5.6–5.7)."""
    return (coefficients["B"] * torque_Nm + coefficients["C"]) * torque_Nm + coefficients["D"]


def cable_torque_Nm(offset_deg, coefficients: Mapping):
    """Torque whose cable offset is ``offset_deg``: the root of b(τ) continuous with B = 0.

    τ = 2(b − D) / (C + √(C² + 4B(b − D))), zero when the cable is slack (b below D).
    """
    excess = offset_deg - coefficients["D"]
    root = np.sqrt(np.maximum(coefficients["C"] ** 2 + 4.0 * coefficients["B"] * excess, 0.0))
    return np.maximum(2.0 * excess / (coefficients["C"] + root), 0.0)
