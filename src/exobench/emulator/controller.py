"""The emulator's real-time controller (seed 002 ch. 5–6) as causal, sample-by-sample rules.

- brace velocity: backward difference of the encoder angle through a 2nd-order Butterworth
  low-pass (6 Hz), the causal estimate the controller sees;
- gait events, knee column of Table 5.1: peak flexion (angle above 40°, velocity turns
  negative), peak extension (after a peak flexion, velocity turns positive), heel strike (after
  a peak extension, angle below 20° and velocity rising);
- virtual clutch, Table 6.1: engages at a peak flexion above 40°, disengages at the next peak
  extension;
- position-based torque control: motor set point of eqs. (5.6)–(5.8) tracked by a PID on the
  motor angle (eq. 5.3, backward-Euler integral, filtered derivative) driving a first-order
  motor velocity response.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, field

import numpy as np
from scipy.signal import butter

from exobench.emulator.rig import CLUTCH_ANGLE_DEG, HEEL_STRIKE_DEG, PEAK_FLEXION_DEG


def velocity_filter(cutoff_Hz: float, rate_Hz: float) -> tuple[np.ndarray, np.ndarray]:
    """Coefficients (b, a) of the causal 2nd-order Butterworth low-pass of the brace velocity."""
    b, a = butter(2, cutoff_Hz, fs=rate_Hz)
    return b, a


@dataclass
class Events:
    """Flags of Table 5.1 and the clutch flag SPR of Table 6.1."""

    flexion: bool = False
    extension: bool = False
    engaged: bool = False


def update_events(state: Events, angle_deg: float, omega: float, omega_prev: float) -> str:
    """Advance the Table 5.1 / 6.1 logic by one sample; returns the event detected, or ''."""
    event = ""
    if angle_deg > PEAK_FLEXION_DEG and omega_prev >= 0.0 and omega < 0.0:
        state.flexion, state.extension = True, False
        event = "peak_flexion"
    elif state.flexion and omega_prev <= 0.0 and omega > 0.0:
        state.flexion, state.extension = False, True
        event = "peak_extension"
    elif state.extension and angle_deg < HEEL_STRIKE_DEG and omega > omega_prev:
        state.extension = False
        event = "heel_strike"
    if not state.engaged and angle_deg > CLUTCH_ANGLE_DEG and omega_prev > 0.0 >= omega:
        state.engaged = True
    elif state.engaged and omega_prev < 0.0 <= omega:
        state.engaged = False
    return event


def direction_weight(omega_deg_per_s, blend_deg_per_s: float):
    """Weight of the extension reference in eq. (5.8): 1 below −blend, 0 above +blend."""
    return np.minimum(np.maximum(0.5 - omega_deg_per_s / (2.0 * blend_deg_per_s), 0.0), 1.0)


def cable_offset_deg(torque_Nm, coefficients: Mapping):
    """Motor-angle offset b(τ) = B·τ² + C·τ + D of one direction (eqs. 5.6 / 5.7)."""
    return (coefficients["B"] * torque_Nm + coefficients["C"]) * torque_Nm + coefficients["D"]


def set_point_deg(
    brace_deg, torque_Nm, omega_deg_per_s, transmission: Mapping, blend_deg_per_s: float
):
    """Motor set point of eqs. (5.6)–(5.8): A·θ_b + b(τ), blended by direction of motion."""
    ratio = transmission["brace_pulley_radius_m"] / transmission["motor_pulley_radius_m"]
    w = direction_weight(omega_deg_per_s, blend_deg_per_s)
    offset = w * cable_offset_deg(torque_Nm, transmission["extension"]) + (
        1.0 - w
    ) * cable_offset_deg(torque_Nm, transmission["flexion"])
    return ratio * brace_deg + offset


def cable_torque_Nm(offset_deg, coefficients: Mapping):
    """Torque whose cable offset is ``offset_deg``: the root of b(τ) continuous with B = 0.

    τ = 2(b − D) / (C + √(C² + 4B(b − D))), zero when the cable is slack (b below D).
    """
    excess = offset_deg - coefficients["D"]
    root = np.sqrt(np.maximum(coefficients["C"] ** 2 + 4.0 * coefficients["B"] * excess, 0.0))
    return np.maximum(2.0 * excess / (coefficients["C"] + root), 0.0)


@dataclass
class Pid:
    """Discrete PID of eq. (5.3) on the motor angle, output a motor velocity command (deg/s)."""

    kp_per_s: float
    ki_per_s2: float
    kd: float
    derivative_filter_N: float
    dt: float
    integral: float = 0.0
    derivative: float = 0.0
    error_prev: float = 0.0
    started: bool = field(default=False)

    def __call__(self, error: float) -> float:
        """Controller output for this sample's error (forward-Euler integral and filter)."""
        if not self.started:
            self.error_prev, self.started = error, True
        n_dt = self.derivative_filter_N * self.dt
        self.derivative = (1.0 - n_dt) * self.derivative + (
            self.kd * self.derivative_filter_N * (error - self.error_prev)
        )
        output = self.kp_per_s * error + self.integral + self.derivative
        self.integral += self.ki_per_s2 * self.dt * error
        self.error_prev = error
        return output
