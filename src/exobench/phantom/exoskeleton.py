"""Exoskeleton mechanics in series with the phantom: interface → frame → clutch → spring.

While the clutch is engaged the knee moment M passes through three elements in series:
- interface (soft tissue + straps), Kelvin–Voigt: M = k_i·δ + c_i·δ̇, δ = θ_phantom − θ_exo;
- frame (bars, clutch, chain): M = k_f·σ, σ = θ_exo − θ_spring-side;
- spring side: M = M_s(s) ± τ_c (Coulomb friction while it slides), s = spring-side rotation
  since engagement, with M_s = k_θ·s (seed 000 eqs. 2.1–2.2) as long as the extension spring
  is taut (F = F0 + k_l·r·(T/t)·s ≥ 0); past that the cable is slack and only the tensioner
  holds, with stiffness (T/t)²·k_tensioner.
A disabled compliance is rigid (its deflection is 0). The clutch engages at once; it releases
as the hexapod tilt's smooth step lowers: its torque capacity falls from the moment it holds to
0 over the release ramp, and where the load exceeds the capacity the clutch slips and the spring
unwinds. The system is solved with implicit Euler steps, stick–slip by a trial stick step; the
loop runs over the samples of a stride and is vectorised over all strides.
"""

from __future__ import annotations

from dataclasses import dataclass, replace

import numpy as np


@dataclass(frozen=True)
class Mechanics:
    """Per-stride parameters (arrays broadcast over strides) of the series chain."""

    joint_stiffness_Nm_per_rad: np.ndarray
    spring_stiffness_N_per_m: np.ndarray
    travel_m_per_rad: float
    pretension_N: float
    tensioner_knee_stiffness_Nm_per_rad: float
    k_interface_Nm_per_rad: float = np.inf
    c_interface_Nms_per_rad: float = 0.0
    k_frame_Nm_per_rad: float = np.inf
    friction_Nm: float = 0.0

    @property
    def slack_rotation_rad(self) -> np.ndarray:
        """Spring-side rotation at which the extension spring's force reaches 0."""
        return -self.pretension_N / (self.spring_stiffness_N_per_m * self.travel_m_per_rad)

    def spring_moment(self, rotation_rad: np.ndarray) -> np.ndarray:
        """Knee moment of spring + tensioner at a spring-side rotation (taut or slack)."""
        kink = self.slack_rotation_rad
        taut = self.joint_stiffness_Nm_per_rad * rotation_rad
        slack = (
            self.joint_stiffness_Nm_per_rad * kink
            + self.tensioner_knee_stiffness_Nm_per_rad * (rotation_rad - kink)
        )
        return np.where(rotation_rad >= kink, taut, slack)

    def spring_rotation(self, moment_Nm: np.ndarray) -> np.ndarray:
        """Spring-side rotation that holds a moment (inverse of :meth:`spring_moment`)."""
        kink = self.slack_rotation_rad
        taut = moment_Nm / self.joint_stiffness_Nm_per_rad
        slack = kink + (moment_Nm - self.joint_stiffness_Nm_per_rad * kink) / (
            self.tensioner_knee_stiffness_Nm_per_rad
        )
        return np.where(taut >= kink, taut, slack)

    def spring_force(self, rotation_rad: np.ndarray) -> np.ndarray:
        """Spring tension F = F0 + k_l·r·(T/t)·s, 0 when slack."""
        travel = self.spring_stiffness_N_per_m * self.travel_m_per_rad * rotation_rad
        return np.maximum(self.pretension_N + travel, 0.0)

    def spring_extension(self, rotation_rad: np.ndarray) -> np.ndarray:
        """Spring elongation from its pre-tensioned length, r·(T/t)·s, stopped at free length."""
        return self.travel_m_per_rad * np.maximum(rotation_rad, self.slack_rotation_rad)


def _compliance(stiffness: float) -> float:
    return 0.0 if np.isinf(stiffness) else 1.0 / stiffness


def simulate(
    phantom_rad: np.ndarray, clutch: np.ndarray, dt_s: float, mech: Mechanics
) -> dict[str, np.ndarray]:
    """Moment and deflections of every stride, shape (strides, samples), from the phantom angle.

    ``clutch`` is the engagement level per sample: 1 engaged, 0 free, in between releasing.
    """
    strides, samples = phantom_rad.shape
    shape = (strides,)
    k_theta = np.broadcast_to(mech.joint_stiffness_Nm_per_rad, shape)
    kink = np.broadcast_to(mech.slack_rotation_rad, shape)
    k_slack = mech.tensioner_knee_stiffness_Nm_per_rad
    # Taut branch: M_s = k_θ·s; slack branch: M_s = k_slack·s + (k_θ − k_slack)·kink.
    branches = ((k_theta, np.zeros(shape)), (np.full(shape, k_slack), (k_theta - k_slack) * kink))
    damping_rate = mech.c_interface_Nms_per_rad / dt_s
    c_int = _compliance(mech.k_interface_Nm_per_rad + damping_rate)
    c_frame = _compliance(mech.k_frame_Nm_per_rad)
    tau = mech.friction_Nm

    out = {
        name: np.zeros((strides, samples)) for name in ("moment", "interface", "frame", "spring")
    }
    delta = np.zeros(shape)
    rotation = np.zeros(shape)
    reference = phantom_rad[:, 0].copy()
    was_on = np.zeros(shape, bool)
    moment = np.zeros(shape)
    hold = np.zeros(shape)
    per_stride = replace(mech, joint_stiffness_Nm_per_rad=k_theta)
    for i in range(samples):
        level = clutch[:, i]
        on = level > 0
        capacity = np.where(level >= 1, np.inf, level * hold)
        theta = phantom_rad[:, i]
        starting = on & ~was_on
        reference = np.where(starting, theta - delta, reference)
        rotation = np.where(on & was_on, rotation, 0.0)
        pull = damping_rate * delta  # viscous memory of the interface: M = (k_i + c_i/h)δ − pull
        total = theta - reference
        # Trial stick step: the spring side holds still, interface and frame take the motion.
        series = c_int + c_frame
        held = per_stride.spring_moment(rotation) if tau > 0 else 0.0
        free = total - rotation - c_int * pull
        with np.errstate(divide="ignore", invalid="ignore"):
            m_stick = np.where(series > 0, free / series, 0.0)
        stick = (series > 0) & (np.abs(m_stick - held) <= tau) & (tau > 0)
        direction = np.where(series > 0, np.sign(m_stick - held), np.sign(total - rotation))
        friction = direction * tau
        m_slip, s_slip = _slip(total, c_int * pull, series, friction, branches[0])
        slack = s_slip < kink
        if slack.any():
            m_b, s_b = _slip(total, c_int * pull, series, friction, branches[1])
            m_slip, s_slip = np.where(slack, m_b, m_slip), np.where(slack, s_b, s_slip)
        moment = np.where(stick, m_stick, m_slip)
        rotation = np.where(stick, rotation, s_slip)
        slipping = np.abs(moment) > capacity
        if slipping.any():
            moment = np.where(slipping, np.sign(moment) * capacity, moment)
            rotation = np.where(slipping, per_stride.spring_rotation(moment), rotation)
        moment = np.where(on, moment, 0.0)
        rotation = np.where(on, rotation, 0.0)
        hold = np.where(level >= 1, np.abs(moment), hold)
        delta = c_int * (moment + pull)
        out["moment"][:, i] = moment
        out["interface"][:, i] = delta
        out["frame"][:, i] = c_frame * moment
        out["spring"][:, i] = rotation
        was_on = on
    columns = replace(
        mech,
        joint_stiffness_Nm_per_rad=k_theta[:, None],
        spring_stiffness_N_per_m=np.broadcast_to(mech.spring_stiffness_N_per_m, shape)[:, None],
    )
    return {
        "knee_moment_Nm": out["moment"],
        "interface_deflection_rad": out["interface"],
        "frame_deflection_rad": out["frame"],
        "spring_side_rotation_rad": out["spring"],
        "exo_knee_angle_rad": phantom_rad - out["interface"],
        "spring_force_N": columns.spring_force(out["spring"]),
        "spring_extension_m": columns.spring_extension(out["spring"]),
    }


def _slip(total, pulled, series, friction, branch):
    """Sliding step on one spring branch M_s = K·s + M0: returns (moment, spring-side rotation)."""
    stiffness, offset = branch
    moment = (total - pulled + (offset + friction) / stiffness) / (series + 1.0 / stiffness)
    return moment, (moment - offset - friction) / stiffness
