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

import numpy as np

from exobench.phantom.rig import GRAVITY_M_PER_S2, Rig

GRAVITY = np.array([0.0, -GRAVITY_M_PER_S2])


def cross(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """z-component of the planar cross product a × b over the last axis."""
    return a[..., 0] * b[..., 1] - a[..., 1] * b[..., 0]


@dataclass(frozen=True)
class Balance:
    """Lever arms and inertial terms of the two moment balances, per sample."""

    hip_arm: np.ndarray  # A − H (m)
    knee_arm: np.ndarray  # A − K (m)
    leg_term: np.ndarray  # Σ (G−H)×m(a−g) + Iα  (N·m)
    shank_term: np.ndarray  # (G2−K)×m2(a2−g) + I2α2  (N·m)
    thigh_term: np.ndarray  # (G1−H)×m1(a1−g) + I1α1, the thigh's share of leg_term (N·m)


def balance(hip_m, knee_m, ankle_m, dt_s: float, rig: Rig) -> Balance:
    """Inertial and gravity terms of the leg from joint-centre paths (..., samples, 2) in m."""
    thigh = knee_m - hip_m
    shank = ankle_m - knee_m
    thigh_dir = thigh / np.linalg.norm(thigh, axis=-1, keepdims=True)
    shank_dir = shank / np.linalg.norm(shank, axis=-1, keepdims=True)
    com_thigh = hip_m + rig.thigh_com_m * thigh_dir
    com_shank = knee_m + rig.shank_com_m * shank_dir
    acc_thigh = second_derivative(com_thigh, dt_s, axis=-2) - GRAVITY
    acc_shank = second_derivative(com_shank, dt_s, axis=-2) - GRAVITY
    alpha_thigh = second_derivative(orientation(thigh_dir), dt_s, axis=-1)
    alpha_shank = second_derivative(orientation(shank_dir), dt_s, axis=-1)
    shank_term = (
        rig.shank_mass_kg * cross(com_shank - knee_m, acc_shank)
        + rig.shank_inertia_kgm2 * alpha_shank
    )
    thigh_term = (
        rig.thigh_mass_kg * cross(com_thigh - hip_m, acc_thigh)
        + rig.thigh_inertia_kgm2 * alpha_thigh
    )
    leg_term = (
        thigh_term
        + rig.shank_mass_kg * cross(com_shank - hip_m, acc_shank)
        + rig.shank_inertia_kgm2 * alpha_shank
    )
    return Balance(ankle_m - hip_m, ankle_m - knee_m, leg_term, shank_term, thigh_term)


def orientation(direction: np.ndarray) -> np.ndarray:
    """Unwrapped counter-clockwise angle (rad) of unit vectors over the samples axis."""
    return np.unwrap(np.arctan2(direction[..., 1], direction[..., 0]), axis=-1)


def second_derivative(values: np.ndarray, dt_s: float, axis: int) -> np.ndarray:
    """Second time derivative by repeated second-order central differences."""
    return np.gradient(np.gradient(values, dt_s, axis=axis), dt_s, axis=axis)


def knee_moment(bal: Balance, ankle_vertical_N: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Net knee moment (extensor +) and horizontal ankle force from the vertical ankle force."""
    hx, hy = bal.hip_arm[..., 0], bal.hip_arm[..., 1]
    horizontal = (hx * ankle_vertical_N - bal.leg_term) / hy
    moment = bal.shank_term - cross(bal.knee_arm, np.stack([horizontal, ankle_vertical_N], -1))
    return moment, horizontal


def segment_moments(bal: Balance) -> tuple[np.ndarray, np.ndarray]:
    """The parts of :func:`knee_moment`'s M due to the thigh's and the shank's mass and inertia,
    −(k_y/h_y)·T₁ and S − (k_y/h_y)·(L − T₁) (N·m): each scales with its segment's mass and
    inertia, M = parts + F_y·∂M/∂F_y."""
    ratio = bal.knee_arm[..., 1] / bal.hip_arm[..., 1]
    return -ratio * bal.thigh_term, bal.shank_term - ratio * (bal.leg_term - bal.thigh_term)


def moment_per_vertical_force(bal: Balance) -> np.ndarray:
    """∂M/∂F_y of :func:`knee_moment`: the knee moment's change per newton of vertical ankle
    force (the horizontal force follows from the hip balance), −(k_x − k_y·h_x/h_y) (m)."""
    hx, hy = bal.hip_arm[..., 0], bal.hip_arm[..., 1]
    kx, ky = bal.knee_arm[..., 0], bal.knee_arm[..., 1]
    return -(kx - ky * hx / hy)
