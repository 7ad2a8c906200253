"""Planar Newton–Euler of the phantom's thigh and shank (docs/rig.md §1).

The hip is a fixed frictionless hinge, the ankle is driven along the vertical under it. The
moment balance of the whole leg about the hip and of the shank about the knee,

    (A − H) × R_A = Σ_i [(G_i − H) × m_i (a_i − g) + I_i α_i]          (leg about hip)
    (A − K) × R_A = (G_2 − K) × m_2 (a_2 − g) + I_2 α_2 − M            (shank about knee)

tie the ankle force R_A to the net (exoskeleton) knee moment M, extensor positive. The analysis
solves them for M and the unmeasured horizontal ankle force given the measured vertical one
(the twin derives its ankle forces apart from these, by Lagrange's equations).
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import cached_property

import numpy as np

from exobench.phantom.rig import GRAVITY_M_PER_S2, Rig

GRAVITY = np.array([0.0, -GRAVITY_M_PER_S2])


def cross(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """z-component of the planar cross product a × b over the last axis."""
    return a[..., 0] * b[..., 1] - a[..., 1] * b[..., 0]


@dataclass(frozen=True)
class Balance:
    """Lever arms and the inertial and gravity terms of the two moment balances, per sample,
    segment by segment: each term is a mass part (G − J) × m(a − g) about a joint J and an
    inertia part I·α, and each mass part's change per unit scale of its centre-of-mass
    distance c (c·∂/∂c: G = J + c·u, a = J̈ + c·ü; computed when asked for, from the
    segments' motion kept here: the knee moment alone needs none of them)."""

    hip_arm: np.ndarray  # A − H (m)
    knee_arm: np.ndarray  # A − K (m)
    thigh_mass: np.ndarray  # (G1−H)×m1(a1−g)  (N·m)
    thigh_inertia: np.ndarray  # I1α1
    shank_mass_knee: np.ndarray  # (G2−K)×m2(a2−g)
    shank_mass_hip: np.ndarray  # (G2−H)×m2(a2−g)
    shank_inertia: np.ndarray  # I2α2
    thigh_rate: np.ndarray  # the thigh's counter-clockwise angular velocity (rad/s)
    thigh_angle: np.ndarray  # the thigh's counter-clockwise angle from the downward vertical
    thigh_dir: np.ndarray  # u1, unit vector hip → knee
    shank_dir: np.ndarray  # u2, unit vector knee → ankle
    thigh_turn: np.ndarray  # ü1 (1/s²)
    shank_turn: np.ndarray  # ü2 (1/s²)
    shank_acc: np.ndarray  # a2 − g (m/s²)
    shank_com_from_hip: np.ndarray  # G2 − H (m)
    rig: Rig

    @cached_property
    def thigh_com2(self) -> np.ndarray:
        """The part of thigh_mass quadratic in c1, m1·c1²·u1×ü1 (N·m)."""
        rig = self.rig
        return rig.thigh_mass_kg * rig.thigh_com_m**2 * cross(self.thigh_dir, self.thigh_turn)

    @cached_property
    def shank_com2(self) -> np.ndarray:
        """The part of either shank mass term quadratic in c2, m2·c2²·u2×ü2 (N·m)."""
        rig = self.rig
        return rig.shank_mass_kg * rig.shank_com_m**2 * cross(self.shank_dir, self.shank_turn)

    @property
    def thigh_com(self) -> np.ndarray:
        """c1·∂/∂c1 of thigh_mass, (G1−H)×m1(a1−g) + m1·c1²·u1×ü1 (N·m)."""
        return self.thigh_mass + self.thigh_com2

    @property
    def shank_com_knee(self) -> np.ndarray:
        """c2·∂/∂c2 of shank_mass_knee, (G2−K)×m2(a2−g) + m2·c2²·u2×ü2 (N·m)."""
        return self.shank_mass_knee + self.shank_com2

    @property
    def shank_com_hip(self) -> np.ndarray:
        """c2·∂/∂c2 of shank_mass_hip, m2·c2·(u2×(a2−g) + (G2−H)×ü2) (N·m)."""
        m2, c2 = self.rig.shank_mass_kg, self.rig.shank_com_m
        arm, turn = self.shank_com_from_hip, self.shank_turn
        return m2 * c2 * (cross(self.shank_dir, self.shank_acc) + cross(arm, turn))

    @property
    def thigh_term(self) -> np.ndarray:
        """(G1−H)×m1(a1−g) + I1α1, the thigh's share of the leg's term (N·m)."""
        return self.thigh_mass + self.thigh_inertia

    @property
    def shank_term(self) -> np.ndarray:
        """(G2−K)×m2(a2−g) + I2α2, the shank about the knee (N·m)."""
        return self.shank_mass_knee + self.shank_inertia

    @property
    def leg_term(self) -> np.ndarray:
        """Σ (G−H)×m(a−g) + Iα over both segments, the leg about the hip (N·m)."""
        return self.thigh_term + self.shank_mass_hip + self.shank_inertia


def balance(hip_m, knee_m, ankle_m, dt_s: float, rig: Rig) -> Balance:
    """Inertial and gravity terms of the leg from joint-centre paths (..., samples, 2) in m."""
    thigh_dir = _unit(knee_m - hip_m)
    shank_dir = _unit(ankle_m - knee_m)
    hip_acc, knee_acc = (second_derivative(x, dt_s, axis=-2) - GRAVITY for x in (hip_m, knee_m))
    thigh_turn, shank_turn = (second_derivative(u, dt_s, axis=-2) for u in (thigh_dir, shank_dir))
    c1, c2 = rig.thigh_com_m, rig.shank_com_m
    m1, m2 = rig.thigh_mass_kg, rig.shank_mass_kg
    acc_thigh = hip_acc + c1 * thigh_turn
    acc_shank = knee_acc + c2 * shank_turn
    thigh_angle = orientation(thigh_dir) + 0.5 * np.pi
    rate_thigh = np.gradient(thigh_angle, dt_s, axis=-1)
    alpha_thigh = np.gradient(rate_thigh, dt_s, axis=-1)
    alpha_shank = second_derivative(orientation(shank_dir), dt_s, axis=-1)
    knee_from_hip = knee_m - hip_m + c2 * shank_dir
    return Balance(
        hip_arm=ankle_m - hip_m,
        knee_arm=ankle_m - knee_m,
        thigh_mass=m1 * cross(c1 * thigh_dir, acc_thigh),
        thigh_inertia=rig.thigh_inertia_kgm2 * alpha_thigh,
        shank_mass_knee=m2 * cross(c2 * shank_dir, acc_shank),
        shank_mass_hip=m2 * cross(knee_from_hip, acc_shank),
        shank_inertia=rig.shank_inertia_kgm2 * alpha_shank,
        thigh_rate=rate_thigh,
        thigh_angle=thigh_angle,
        thigh_dir=thigh_dir,
        shank_dir=shank_dir,
        thigh_turn=thigh_turn,
        shank_turn=shank_turn,
        shank_acc=acc_shank,
        shank_com_from_hip=knee_from_hip,
        rig=rig,
    )


def _unit(vectors: np.ndarray) -> np.ndarray:
    """Unit vectors v/√(v_x² + v_y²) along the last (x, y) axis."""
    return vectors / np.sqrt(vectors[..., 0:1] ** 2 + vectors[..., 1:2] ** 2)


def orientation(direction: np.ndarray) -> np.ndarray:
    """Unwrapped counter-clockwise angle (rad) of unit vectors over the samples axis."""
    return unwrap(np.arctan2(direction[..., 1], direction[..., 0]))


def unwrap(angle: np.ndarray) -> np.ndarray:
    """``np.unwrap`` over the last axis; where every |Δφ| < π, φ itself (+0 after the first)."""
    if (np.abs(np.diff(angle, axis=-1)) < np.pi).all():
        out = angle.copy()
        out[..., 1:] += 0.0
        return out
    return np.unwrap(angle, axis=-1)


def second_derivative(values: np.ndarray, dt_s: float, axis: int) -> np.ndarray:
    """Second time derivative by repeated second-order central differences."""
    return np.gradient(np.gradient(values, dt_s, axis=axis), dt_s, axis=axis)


def knee_moment(bal: Balance, ankle_vertical_N: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Net knee moment (extensor +) and horizontal ankle force from the vertical ankle force."""
    hx, hy = bal.hip_arm[..., 0], bal.hip_arm[..., 1]
    horizontal = (hx * ankle_vertical_N - bal.leg_term) / hy
    moment = bal.shank_term - cross(bal.knee_arm, np.stack([horizontal, ankle_vertical_N], -1))
    return moment, horizontal


# The rig's segment values the inverse dynamics takes as given (docs/assumptions.md rows).
SEGMENT_VALUES = ("thigh_mass", "thigh_com", "thigh_inertia", "shank_mass", "shank_com",
                  "shank_inertia")  # fmt: skip


def value_sensitivities(bal: Balance) -> dict[str, np.ndarray]:
    """P·∂M/∂P of :func:`knee_moment`'s M for each segment value P (N·m per unit scale of P):
    M = S − (k_y/h_y)·L + (terms of F_y), S the shank's term about the knee, L the leg's about
    the hip, each linear in the masses and inertias."""
    ratio = bal.knee_arm[..., 1] / bal.hip_arm[..., 1]
    return {
        "thigh_mass": -ratio * bal.thigh_mass,
        "thigh_com": -ratio * bal.thigh_com,
        "thigh_inertia": -ratio * bal.thigh_inertia,
        "shank_mass": bal.shank_mass_knee - ratio * bal.shank_mass_hip,
        "shank_com": bal.shank_com_knee - ratio * bal.shank_com_hip,
        "shank_inertia": (1.0 - ratio) * bal.shank_inertia,
    }


def value_curvatures(bal: Balance) -> dict[str, np.ndarray]:
    """The part of :func:`knee_moment`'s M quadratic in each centre-of-mass distance, C·c²
    (N·m): a scale s of c changes M by (s − 1)·c·∂M/∂c + (s − 1)²·C·c²."""
    ratio = bal.knee_arm[..., 1] / bal.hip_arm[..., 1]
    return {"thigh_com": -ratio * bal.thigh_com2, "shank_com": (1.0 - ratio) * bal.shank_com2}


def moment_per_knee_shift(hip_m, knee_m, ankle_m, dt_s: float, rig: Rig, ankle_vertical_N,
                          step_m: float = 1e-3) -> np.ndarray:  # fmt: skip
    """∂M/∂o of :func:`knee_moment`'s M for the knee's centre moved o anterior, square to the
    thigh (N·m per m; a central difference of ± ``step_m``): what knee markers off the joint's
    axis do to the moment."""
    thigh = _unit(knee_m - hip_m)
    anterior = np.stack([-thigh[..., 1], thigh[..., 0]], axis=-1)
    moments = [knee_moment(balance(hip_m, knee_m + sign * step_m * anterior, ankle_m, dt_s, rig),
                           ankle_vertical_N)[0] for sign in (1.0, -1.0)]  # fmt: skip
    return (moments[0] - moments[1]) / (2.0 * step_m)


def moment_per_hip_moment(bal: Balance) -> np.ndarray:
    """∂M/∂M_hip of :func:`knee_moment`: a moment M_hip of the hip on the thigh (counter-
    clockwise) that the analysis takes as zero shifts the horizontal ankle force by M_hip/h_y,
    and M by −(k_y/h_y)·M_hip."""
    return -bal.knee_arm[..., 1] / bal.hip_arm[..., 1]


def moment_per_vertical_force(bal: Balance) -> np.ndarray:
    """∂M/∂F_y of :func:`knee_moment`: the knee moment's change per newton of vertical ankle
    force (the horizontal force follows from the hip balance), −(k_x − k_y·h_x/h_y) (m)."""
    hx, hy = bal.hip_arm[..., 0], bal.hip_arm[..., 1]
    kx, ky = bal.knee_arm[..., 0], bal.knee_arm[..., 1]
    return -(kx - ky * hx / hy)
