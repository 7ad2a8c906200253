"""The brace against the knee: its hinge beside the knee's axis, and the cuffs and soft tissue
through which the brace torque turns it off the knee (compliance with its lag, stiffening,
friction, drift, play)."""

import math
from collections.abc import Mapping

import numba
import numpy as np

from .rig import value_of

# Layout of the cuffs' vector: compliance c (deg/(N·m)), the tissue's time constant T (s), the
# stiffening β (1/(N·m)), the straps' friction τ_s (N·m), the drift ρ (1/s), the play p (deg).
(COMPLIANCE, TIME_CONSTANT, STIFFENING, FRICTION, DRIFT, PLAY, CUFF_SIZE) = range(7)


def hinge_angle(knee_deg: np.ndarray, offset_ratio: float) -> np.ndarray:
    """The brace's hinge turns θ + a·sin θ (θ in rad) when the knee turns θ; degrees in and out."""
    if offset_ratio == 0.0:
        return knee_deg
    return knee_deg + np.degrees(offset_ratio * np.sin(np.radians(knee_deg)))


@numba.njit(cache=True)
def deflection(torque: float, compliance: float, stiffening: float) -> float:
    """δ = c·τ / (1 + β·|τ|): the cuffs' static deflection under the brace torque (deg)."""
    return compliance * torque / (1.0 + stiffening * abs(torque))


@numba.njit(cache=True)
def carried(delta: float, compliance: float, stiffening: float) -> float:
    """τ_el(δ) = δ / (c − β·|δ|): the torque the cuffs' spring carries at a deflection δ."""
    return delta / (compliance - stiffening * abs(delta))


@numba.njit(cache=True)
def cuff_step(
    torque: float, hinge_deg: float, brace_prev: float, delta_prev: float, t: float, h: float, q
) -> tuple[float, float]:
    """Brace angle and elastic deflection δ after a step h under the brace torque τ (flexion +).

    δ relaxes towards c(t)·τ' / (1 + β|τ'|) with the tissue's time constant, c(t) = c·(1 + ρt),
    τ' = τ ∓ τ_s once |τ − τ_el(δ)| > τ_s (else δ sticks); the brace sits at hinge + δ + b, the
    play b = clip(brace_prev − hinge − δ, −p/2, p/2): it stays where it was until the limb's
    motion takes it along at an edge of the dead band, whatever the torque.
    """
    delta = 0.0
    compliance = q[COMPLIANCE] * (1.0 + q[DRIFT] * max(t, 0.0))
    if compliance > 0.0:
        excess = torque - carried(delta_prev, compliance, q[STIFFENING])
        delta = delta_prev
        if abs(excess) > q[FRICTION]:
            moving = torque - math.copysign(q[FRICTION], excess)
            target = deflection(moving, compliance, q[STIFFENING])
            delta = target + (delta_prev - target) * math.exp(-h / q[TIME_CONSTANT])
    half = 0.5 * q[PLAY]
    play = min(max(brace_prev - hinge_deg - delta, -half), half)
    return hinge_deg + delta + play, delta


def real_cuffs(
    violations: Mapping[str, Mapping[str, float]], compliance: float, time_constant_s: float
) -> np.ndarray:
    """The trial's cuffs: its compliance and time constant, the table's β, τ_s, ρ and p."""
    q = np.zeros(CUFF_SIZE)
    q[COMPLIANCE], q[TIME_CONSTANT] = compliance, time_constant_s
    q[STIFFENING] = value_of(violations, "cuff.stiffening", 0.0)
    q[FRICTION] = value_of(violations, "cuff.coulomb", 0.0)
    q[DRIFT] = value_of(violations, "cuff.drifting", 0.0)
    q[PLAY] = value_of(violations, "cuff.play", 0.0)
    return q
