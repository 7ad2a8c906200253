"""Energy stored per step in the emulated spring: −∫ τ dθ while the clutch is engaged
(docs/rig.md §3).

The integral is the trapezoidal sum over sample intervals that start engaged; steps run from
one detected heel strike to the next.
"""

from __future__ import annotations

import numpy as np


def interval_energy_J(torque_Nm: np.ndarray, angle_deg: np.ndarray, engaged: np.ndarray):
    """Energy stored over each sample interval, −½(τ_i + τ_i+1)(θ_i+1 − θ_i); 0 if disengaged."""
    dtheta = np.diff(np.radians(angle_deg))
    return -0.5 * (torque_Nm[1:] + torque_Nm[:-1]) * dtheta * engaged[:-1]


def per_step(interval_J: np.ndarray, heel_strikes: np.ndarray) -> np.ndarray:
    """Sum of interval energies between consecutive heel strikes (one value per step)."""
    cumulative = np.concatenate([[0.0], np.cumsum(interval_J)])
    return np.diff(cumulative[heel_strikes])


def closed_form_J(stiffness_Nm_per_rad: float, deflection_deg) -> np.ndarray:
    """Energy of a linear spring deflected by Δθ from rest, ½·κ·Δθ²."""
    return 0.5 * stiffness_Nm_per_rad * np.radians(np.asarray(deflection_deg)) ** 2
