"""The Bowden cable between the motor's pulley and the brace's: the torque it delivers for its
stretch (eqs. 5.4–5.8), through its calibration per direction of motion, its friction, damping,
creep, slack and friction bias."""

import math
from collections.abc import Mapping

import numba
import numpy as np

from .rig import BLEND_DEG_PER_S, PULLEY_RATIO, value_of

# Layout of a calibration vector: b(τ) = B·τ² + C·τ + D while flexing, then while extending.
(B_FLX, C_FLX, D_FLX, B_EXT, C_EXT, D_EXT, CALIBRATION_SIZE) = range(7)
# Layout of the real cable's vector: its calibration, then the pulley ratio A, the friction
# fraction f, the damping c (N·m·s/rad), the creep ρ (1/s), the slack p (brace degrees) and the
# friction bias τ_f (N·m).
(A_RATIO, FRICTION, VISCOUS, CREEP, SLACK, BIAS, CABLE_SIZE) = range(
    CALIBRATION_SIZE, CALIBRATION_SIZE + 7
)


@numba.njit(cache=True)
def flexing_weight(rate_deg_per_s: float) -> float:
    """Eq. 5.8's weight of the flexion curve: 1 flexing faster than 25 °/s, 0 extending, linear."""
    return min(max((rate_deg_per_s + BLEND_DEG_PER_S) / (2.0 * BLEND_DEG_PER_S), 0.0), 1.0)


@numba.njit(cache=True)
def stretch_for(torque: float, w: float, q: np.ndarray) -> float:
    """b(τ) = w·(B·τ² + C·τ + D)_flexion + (1 − w)·(B·τ² + C·τ + D)_extension (motor degrees)."""
    flexing = (q[B_FLX] * torque + q[C_FLX]) * torque + q[D_FLX]
    extending = (q[B_EXT] * torque + q[C_EXT]) * torque + q[D_EXT]
    return w * flexing + (1.0 - w) * extending


@numba.njit(cache=True)
def torque_for(stretch: float, w: float, q: np.ndarray) -> float:
    """τ ≥ 0 on b's rising branch where b(τ) = stretch; 0 while slack (≤ D), b's top beyond it."""
    b = w * q[B_FLX] + (1.0 - w) * q[B_EXT]
    c = w * q[C_FLX] + (1.0 - w) * q[C_EXT]
    excess = stretch - (w * q[D_FLX] + (1.0 - w) * q[D_EXT])
    if excess <= 0.0:
        return 0.0
    discriminant = c * c + 4.0 * b * excess
    if discriminant <= 0.0:  # past the curve's top (B < 0): the most the calibration holds
        return -c / (2.0 * b)
    return 2.0 * excess / (c + math.sqrt(discriminant))


@numba.njit(cache=True)
def delivered_torque(
    motor_deg: float, brace_deg: float, rate_deg_per_s: float, t: float, taken: float, q
) -> tuple[float, float]:
    """Cable torque ≥ 0 and the slack's state y (the stretch past the slack, backlash of width A·p).

    τ = b⁻¹(y)·(1 ± f)·(1 + ρ·t) − c·ω − τ_f with y within A·p/2 of the stretch θ_m − A·θ_b,
    + f while the brace extends, − f while it flexes, the damping and the bias only while the
    cable pulls.
    """
    stretch = motor_deg - q[A_RATIO] * brace_deg
    half = 0.5 * q[A_RATIO] * q[SLACK]
    taken = min(max(taken, stretch - half), stretch + half)
    torque = torque_for(taken, flexing_weight(rate_deg_per_s), q)
    if torque > 0.0:
        if rate_deg_per_s < 0.0:
            torque *= 1.0 + q[FRICTION]
        elif rate_deg_per_s > 0.0:
            torque *= 1.0 - q[FRICTION]
        torque = torque * (1.0 + q[CREEP] * max(t, 0.0)) - q[VISCOUS] * math.radians(rate_deg_per_s)
        torque -= q[BIAS]
    return max(torque, 0.0), taken


def calibration_vector(transmission: Mapping[str, Mapping[str, float]]) -> np.ndarray:
    """A calibration's vector from its {"flexion": {B, C, D}, "extension": {B, C, D}}."""
    return np.array([transmission[way][c] for way in ("flexion", "extension") for c in "BCD"])


def real_cable(
    violations: Mapping[str, Mapping[str, float]],
    tension_deg: float,
    calibration: np.ndarray,
    bias_Nm: float,
) -> np.ndarray:
    """The real cable on a calibration B, C, D: s·(B·τ² + C·τ) + D + o + the trial's
    re-tensioning, A·s, f, c, ρ, p, the friction bias τ_f (the reading's and the violation's)."""
    q = np.zeros(CABLE_SIZE)
    q[:CALIBRATION_SIZE] = calibration
    scale = value_of(violations, "cable_calibration.value", 1.0)
    q[[B_FLX, C_FLX, B_EXT, C_EXT]] *= scale
    q[[D_FLX, D_EXT]] += value_of(violations, "cable_calibration.offset", 0.0) + tension_deg
    q[A_RATIO] = PULLEY_RATIO * value_of(violations, "pulley_ratio.value", 1.0)
    q[FRICTION] = value_of(violations, "cable.coulomb", 0.0)
    q[VISCOUS] = value_of(violations, "cable.viscous", 0.0)
    q[CREEP] = value_of(violations, "cable.drifting", 0.0)
    q[SLACK] = value_of(violations, "cable.play", 0.0)
    q[BIAS] = bias_Nm + value_of(violations, "cable.bias", 0.0)
    return q
