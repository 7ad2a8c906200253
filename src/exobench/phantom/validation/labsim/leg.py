"""The hexapod's programmed knee motion, the two-link leg's equations of motion (the ankle
force) and the markers on the real geometry."""

from collections.abc import Mapping
from pathlib import Path
from typing import NamedTuple

import numpy as np
import pandas as pd
from scipy.interpolate import PchipInterpolator

from .rig import (
    BAR_Z_MM,
    COM_SHANK,
    COM_THIGH,
    FS_ANALOG,
    HIP_MM,
    I_SHANK,
    I_THIGH,
    JOINT_HALF_WIDTH_MM,
    L_SHANK,
    L_THIGH,
    M_SHANK,
    M_THIGH,
    MARKERS,
    SHANK_BAR_MARKERS_M,
    SPRING_ANTERIOR_M,
    SPRING_FIXED_FROM_HINGE_M,
    SPRING_Z_MM,
    STRIDE_S,
    THIGH_BAR_MARKERS_M,
    G,
    value_of,
)


class KneeMotion(NamedTuple):
    """Programmed phantom knee flexion and its time derivatives (rad, rad/s, rad/s²)."""

    theta: np.ndarray
    omega: np.ndarray
    alpha: np.ndarray


class Leg(NamedTuple):
    """The phantom's real segments (m, kg, kg·m²) and its ankle line's offset o (m, anterior)."""

    thigh_length: float
    shank_length: float
    thigh_mass: float
    shank_mass: float
    thigh_com: float
    shank_com: float
    thigh_inertia: float
    shank_inertia: float
    ankle_offset: float = 0.0


NOMINAL_LEG = Leg(L_THIGH, L_SHANK, M_THIGH, M_SHANK, COM_THIGH, COM_SHANK, I_THIGH, I_SHANK)


def real_leg(violations: Mapping[str, Mapping[str, float]]) -> Leg:
    """The real leg: segment values and both lengths s × the rig's, the ankle line o anterior."""
    length = value_of(violations, "segment_lengths.value", 1.0)

    def scaled(key: str, nominal: float) -> float:
        return nominal * value_of(violations, f"{key}.value", 1.0)

    return Leg(
        L_THIGH * length,
        L_SHANK * length,
        scaled("thigh_mass", M_THIGH),
        scaled("shank_mass", M_SHANK),
        scaled("thigh_com", COM_THIGH),
        scaled("shank_com", COM_SHANK),
        scaled("thigh_inertia", I_THIGH),
        scaled("shank_inertia", I_SHANK),
        value_of(violations, "ankle_path.offset", 0.0) / 1000.0,
    )


def smoothstep(x: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Quintic step S(x) = 10x³ − 15x⁴ + 6x⁵ on [0, 1] (clipped) with S′ and S″."""
    x = np.clip(x, 0.0, 1.0)
    return (
        x**3 * (10 - 15 * x + 6 * x**2),
        30 * x**2 * (1 - x) ** 2,
        60 * x * (1 - x) * (1 - 2 * x),
    )


def read_mean_cycle(cycle_csv: Path) -> np.ndarray:
    """Mean knee cycle θ̄(t) in rad, 2000 samples over one 2 s stride (checked)."""
    table = pd.read_csv(cycle_csv)
    if list(table.columns) != ["gait_cycle_pct", "knee_flexion_deg"]:
        raise ValueError(f"{cycle_csv}: columns must be gait_cycle_pct,knee_flexion_deg")
    pct = table["gait_cycle_pct"].to_numpy(float)
    n = int(STRIDE_S * FS_ANALOG)
    if pct.size != n or not np.allclose(pct, np.arange(n) * 100.0 / n, atol=1e-6):
        raise ValueError(f"{cycle_csv}: expected {n} rows at 0.00 … 99.95 %")
    return np.deg2rad(table["knee_flexion_deg"].to_numpy(float))


def cycle_extrema(cycle: np.ndarray) -> np.ndarray:
    """Indices of the periodic cycle's peaks and valleys (slope sign changes, flats skipped)."""
    slope = np.sign(np.diff(np.append(cycle, cycle[0])))
    nonzero = np.flatnonzero(slope)
    last = np.searchsorted(nonzero, np.arange(slope.size), side="right") - 1
    slope = slope[nonzero[last]]  # index −1 wraps to the cycle's last non-flat step
    return np.flatnonzero(slope != np.roll(slope, 1))


def cycle_series(cycle: np.ndarray, t: np.ndarray, harmonics: int) -> list[np.ndarray]:
    """Fourier series θ̄(t) = Re Σ_{h≤H} w_h c_h e^{i2πht/T} of the mean cycle, θ̄′ and θ̄″."""
    coef = np.fft.rfft(cycle)[: harmonics + 1] / cycle.size
    coef[1:] *= 2.0
    omega = 2j * np.pi * np.arange(coef.size) / STRIDE_S
    phase, where = np.unique(np.mod(t, STRIDE_S), return_inverse=True)
    basis = np.exp(np.outer(phase, omega))
    return [((basis * (omega**k * coef)).sum(axis=1).real)[where] for k in range(3)]


def knee_motion(
    cycle: np.ndarray, shifts_rad: np.ndarray, ramp_strides: int, t: np.ndarray, harmonics: int = 25
) -> KneeMotion:
    """Programmed θ = θ_m + a(t)·(θ̄ + Δ − θ_m): cycle, PCHIP peak/valley shifts Δ, ramps a(t)."""
    strides = shifts_rad.shape[0]
    ext_t = cycle_extrema(cycle) * STRIDE_S / cycle.size
    knots = (np.arange(strides)[:, None] * STRIDE_S + ext_t[None, :]).ravel()
    knots = np.concatenate([[ext_t[-1] - STRIDE_S], knots, [strides * STRIDE_S + ext_t[0]]])
    offset = PchipInterpolator(knots, np.concatenate([[0.0], shifts_rad.ravel(), [0.0]]))
    c, dc, ddc = (m + offset(t, k) for k, m in enumerate(cycle_series(cycle, t, harmonics)))
    mean_posture = float(np.mean(cycle))
    a, da, dda = np.ones_like(t), np.zeros_like(t), np.zeros_like(t)
    if ramp_strides:
        span = ramp_strides * STRIDE_S
        total = strides * STRIDE_S
        up, dup, ddup = smoothstep(t / span)
        down, ddown, dddown = smoothstep((total - t) / span)
        a = up * down
        da = dup * down / span - up * ddown / span
        dda = ddup * down / span**2 - 2 * dup * ddown / span**2 + up * dddown / span**2
    dev = c - mean_posture
    return KneeMotion(mean_posture + a * dev, da * dev + a * dc, dda * dev + 2 * da * dc + a * ddc)


def leg_angles(
    motion: KneeMotion, leg: Leg = NOMINAL_LEG
) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """φ1 = asin(o/D) + atan2(L2 sin θ, L1 + L2 cos θ), φ2 = φ1 − θ (CCW from −Y), rates, accel."""
    th, om, al = motion
    l1, l2, o = leg.thigh_length, leg.shank_length, leg.ankle_offset
    q = l1 * l2
    d2 = l1**2 + l2**2 + 2 * q * np.cos(th)  # D², hip to ankle squared
    if np.any(d2 <= o * o):
        raise ValueError(f"the ankle's vertical line {1000 * o:g} mm off the hip is out of reach")
    num = q * np.cos(th) + l2**2
    dphi = num / d2
    ddphi = q * np.sin(th) * (2 * num - d2) / d2**2
    if o != 0.0:  # the hip–ankle line turns by ψ = asin(o/D) as D changes with θ
        h = np.sqrt(d2 - o * o)
        dpsi = o * q * np.sin(th) / (d2 * h)
        d_denominator = -2 * q * np.sin(th) * (2 * h * h + d2) / (2 * h)
        ddpsi = (o * q * np.cos(th) * d2 * h - o * q * np.sin(th) * d_denominator) / (d2 * h) ** 2
        psi = np.arctan2(o, h)
        dphi, ddphi = dphi + dpsi, ddphi + ddpsi
    else:
        psi = 0.0
    phi1 = psi + np.arctan2(l2 * np.sin(th), l1 + l2 * np.cos(th))
    w1 = dphi * om
    a1 = ddphi * om**2 + dphi * al
    return phi1, phi1 - th, w1, w1 - om, a1, a1 - al


def _cross(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Planar cross product a × b = a_x b_y − a_y b_x."""
    return a[0] * b[1] - a[1] * b[0]


def ankle_forces(
    motion: KneeMotion,
    knee_moment: np.ndarray,
    leg: Leg = NOMINAL_LEG,
    hip_viscous: float = 0.0,
    hip_friction: float = 0.0,
    hip_elastic: float = 0.0,
) -> tuple[np.ndarray, np.ndarray]:
    """Hexapod force (F_x, F_y) on the ankle (N), Newton–Euler: leg about hip, shank about knee.

    Whole leg about the fixed hip: x_A F_y − y_A F_x = Σ(I α + m r × a) + g Σ m x − M_hip, with
    M_hip = −(c φ̇1 + τ sign φ̇1 + k φ1) the hip's moment on the thigh; shank about the knee:
    (A − K) × F = I2 α2 + m2 (c2 − K) × a2 + m2 g (c2 − K)_x − M_knee.
    """
    m1, m2, c1, c2 = leg.thigh_mass, leg.shank_mass, leg.thigh_com, leg.shank_com
    i1, i2, l1, l2 = leg.thigh_inertia, leg.shank_inertia, leg.thigh_length, leg.shank_length
    p1, p2, w1, w2, a1, a2 = leg_angles(motion, leg)
    e1 = np.stack([np.sin(p1), -np.cos(p1)])
    e2 = np.stack([np.sin(p2), -np.cos(p2)])
    n1 = np.stack([np.cos(p1), np.sin(p1)])
    n2 = np.stack([np.cos(p2), np.sin(p2)])
    unit_acc1 = a1 * n1 - w1**2 * e1
    unit_acc2 = a2 * n2 - w2**2 * e2
    r1, r2 = c1 * e1, l1 * e1 + c2 * e2
    acc1 = c1 * unit_acc1
    acc2 = l1 * unit_acc1 + c2 * unit_acc2
    ankle = l1 * e1 + l2 * e2
    shank = l2 * e2
    hip_moment = -(hip_viscous * w1 + hip_friction * np.sign(w1))
    if hip_elastic:
        hip_moment = hip_moment - hip_elastic * p1
    leg_rhs = (
        i1 * a1 + m1 * _cross(r1, acc1) + i2 * a2 + m2 * _cross(r2, acc2)
        + G * (m1 * r1[0] + m2 * r2[0]) - hip_moment
    )  # fmt: skip
    rel = c2 * e2
    shank_rhs = i2 * a2 + m2 * _cross(rel, acc2) + m2 * G * rel[0] - knee_moment
    det = ankle[1] * shank[0] - ankle[0] * shank[1]
    fy = (ankle[1] * shank_rhs - shank[1] * leg_rhs) / det
    fx = (ankle[0] * shank_rhs - shank[0] * leg_rhs) / det
    return fx, fy


def ankle_vertical_force(
    motion: KneeMotion, knee_moment: np.ndarray, leg: Leg = NOMINAL_LEG
) -> np.ndarray:
    """Ankle F_y (N, up) of ankle_forces for a frictionless hip."""
    return ankle_forces(motion, knee_moment, leg)[1]


def phantom_knee_moment(
    motion: KneeMotion, violations: Mapping[str, Mapping[str, float]]
) -> np.ndarray:
    """The phantom knee's own extensor moment M_k = k·θ + c·θ̇ + τ·sign(θ̇) (N·m)."""
    return (
        value_of(violations, "knee.elastic", 0.0) * motion.theta
        + value_of(violations, "knee.viscous", 0.0) * motion.omega
        + value_of(violations, "knee.coulomb", 0.0) * np.sign(motion.omega)
    )


def marker_positions(
    theta: np.ndarray,
    delta: np.ndarray,
    spring_len_m: np.ndarray,
    leg: Leg = NOMINAL_LEG,
    bar_offset_rad: float = 0.0,
    knee_marker_offset_mm: float = 0.0,
) -> np.ndarray:
    """Markers (3, 12, n) in mm: joints, bars at φ1 + a − δ/2 and φ2 + δ/2, spring on the thigh bar.

    The knee markers sit knee_marker_offset_mm anterior of the knee's axis, fixed to the thigh.
    """
    p1, p2, *_ = leg_angles(KneeMotion(theta, np.zeros_like(theta), np.zeros_like(theta)), leg)

    def unit(phi: np.ndarray) -> np.ndarray:
        return np.stack([np.sin(phi), -np.cos(phi), np.zeros_like(phi)])

    def anterior(direction: np.ndarray) -> np.ndarray:
        return np.stack([-direction[1], direction[0], np.zeros_like(theta)])

    hip = np.broadcast_to(HIP_MM[:, None], (3, theta.size))
    knee = hip + 1000 * leg.thigh_length * unit(p1)
    ankle = knee + 1000 * leg.shank_length * unit(p2)
    zhat = np.array([0.0, 0.0, 1.0])[:, None]
    out = {}
    knee_markers = knee + knee_marker_offset_mm * anterior(unit(p1))
    for name, centre in (("HIP", hip), ("KNEE", knee_markers), ("ANK", ankle)):
        half = JOINT_HALF_WIDTH_MM[name]
        out[f"PH_{name}_MED"] = centre - half * zhat
        out[f"PH_{name}_LAT"] = centre + half * zhat
    hinge = knee + BAR_Z_MM * zhat
    thigh_dir, shank_dir = unit(p1 + bar_offset_rad - delta / 2), unit(p2 + delta / 2)
    for name, dist in THIGH_BAR_MARKERS_M.items():
        out[name] = hinge - 1000 * dist * thigh_dir
    for name, dist in SHANK_BAR_MARKERS_M.items():
        out[name] = hinge + 1000 * dist * shank_dir
    fixed = (
        knee + SPRING_Z_MM * zhat
        - 1000 * SPRING_FIXED_FROM_HINGE_M * thigh_dir
        + 1000 * SPRING_ANTERIOR_M * anterior(thigh_dir)
    )  # fmt: skip
    out["EX_SPRING_A"] = fixed
    out["EX_SPRING_B"] = fixed + 1000 * spring_len_m * thigh_dir
    return np.stack([out[name] for name in MARKERS], axis=1)
