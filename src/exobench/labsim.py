"""Independent recording generator for the phantom + passive knee exoskeleton rig (docs/rig.md §1).

Writes the raw files a lab would write (one C3D per spring and ``manifest.csv``) from the rig
contract and the physics alone: the hexapod drives the knee kinematically along the measured
mean cycle with per-stride peak/valley shifts, the clutched exoskeleton transmits one moment
through interface → bars → frame → play → spring side, and the ankle load cells record the
hexapod's force on the ankle from the two-link leg's equations of motion.

A recording can violate any relaxation of docs/assumptions.md: ``violations`` maps a term key
``row.family`` to {parameter: value} (``VIOLATIONS`` lists them, ``REQUIRES`` their needs). The
laws are written here from each relaxation's one-line law and the rig contract:

- Chain (limb → interface δ → bars → frame ε → play → spring side s, all in knee rotation, one
  moment M through them): the interface and the frame are each k(t)·(x + β·x³) + c·ẋ + τ·sign ẋ
  = M, the friction in parallel with the spring (x sticks while |M − k(t)(x + βx³)| ≤ τ), with
  k(t) = k·(1 + ρ·t); a present ``*.elastic`` makes the element compliant. The spring side is
  M_s = n·(r·F − max(r·F0 + k_t·n·s, 0)) with F = F0 + k(t)·x·(1 + a·|x|) + c·ẋ, x = r·n·s,
  pulling through the cable while F > 0 (the |x| keeps the law monotone below the pretension
  point); its friction τ (chain and clutch) sticks s while |M − M_s| ≤ τ; the tensioner, like
  the chain, cannot push. Play p: the chain pulls only once the knee has turned p since the
  engagement (M ≥ 0). Implicit Euler at the sub-stepped rate, the nearest root from the last
  state (a snap where the tensioner's negative stiffness outweighs a soft interface or frame).
- Leg: Newton–Euler with the real segments (the analysis keeps the rig's), the ankle on the
  vertical line o anterior of the hip, the phantom knee's own extensor moment
  k·θ + c·θ̇ + τ·sign θ̇ beside M, the hip's moment −(c·φ̇1 + τ·sign φ̇1) on the thigh. The
  hexapod is programmed so that the knee follows the mean cycle whatever the real geometry.
- Load cells: each records g·(its true force + s·the other true force)(t − d − D) + o + ḃ·t
  + noise, t the stamp since the trial's first sample; the ankle cells' true force is their
  share of F_y·cos α + F_x·sin α, their crosstalk a share of the spring's tension, the spring
  cell's a share of the vertical ankle force F_y; D (the analog clock) also delays SYNC.
- Markers follow the real geometry; the thigh bar (and the spring on it) is turned by a about
  the hinge; the knee markers sit o anterior of the axis, on the thigh.

Sign conventions: X anterior, Y up, Z lateral; knee flexion θ positive; an extensor moment M
is positive (it acts counter-clockwise about +Z on the shank and clockwise on the thigh).
"""

import math
from collections.abc import Mapping, Sequence
from numbers import Real
from pathlib import Path
from typing import NamedTuple

import ezc3d
import numba
import numpy as np
import pandas as pd
from scipy.interpolate import PchipInterpolator

# Rig constants: the nominal rig of the contract (docs/rig.md §1; the spring's pretension and free
# length and the clutch release are the project's nominal values). The analysis uses these; a
# violation changes the real rig the recording comes from.
G = 9.81
L_THIGH, L_SHANK = 0.299, 0.304
M_THIGH, M_SHANK = 2.51 + 0.64, 1.23 + 0.39
COM_THIGH, COM_SHANK = 0.152, 0.113
I_THIGH, I_SHANK = 0.0165, 0.0130
PULLEY_R = 0.030
CHAIN_RATIO = 5.0
K_TENSIONER = 0.1
F0_N = 3.0
SPRING_LEN_M = 0.080
STRIDE_S = 2.0
FS_ANALOG = 1000
FS_POINT = 100
CLUTCH_RELEASE_FRACTION = 0.35
SYNC_V, SYNC_S = 5.0, 0.020
SHIFT_SD_DEG = 4.0

# Lab geometry of the markers (chosen): hip centre position and lateral (+Z) offsets, mm.
HIP_MM = np.array([0.0, 950.0, 0.0])
JOINT_HALF_WIDTH_MM = {"HIP": 70.0, "KNEE": 50.0, "ANK": 35.0}
BAR_Z_MM, SPRING_Z_MM = 85.0, 100.0
THIGH_BAR_MARKERS_M = {"EX_THIGH_PROX": 0.22, "EX_THIGH_DIST": 0.07}
SHANK_BAR_MARKERS_M = {"EX_SHANK_PROX": 0.07, "EX_SHANK_DIST": 0.22}
SPRING_FIXED_FROM_HINGE_M, SPRING_ANTERIOR_M = 0.21, 0.03

MARKERS = (
    "PH_HIP_MED",
    "PH_HIP_LAT",
    "PH_KNEE_MED",
    "PH_KNEE_LAT",
    "PH_ANK_MED",
    "PH_ANK_LAT",
    "EX_THIGH_PROX",
    "EX_THIGH_DIST",
    "EX_SHANK_PROX",
    "EX_SHANK_DIST",
    "EX_SPRING_A",
    "EX_SPRING_B",
)
ANKLE_CELLS = ("LC_ANKLE_1", "LC_ANKLE_2", "LC_ANKLE_3")
LOAD_CELLS = (*ANKLE_CELLS, "LC_SPRING")
CHANNELS = (*LOAD_CELLS, "SYNC")
CHANNEL_UNITS = ("N", "N", "N", "N", "V")
MANIFEST_COLUMNS = ("trial", "file", "spring_stiffness_N_per_m", "test_order", "ramp_strides")

# Every relaxation of docs/assumptions.md: term key → its parameter (the table's name).
VIOLATIONS: dict[str, tuple[str, ...]] = {
    "interface.elastic": ("k_interface_Nm_per_rad",),
    "interface.stiffening": ("stiffening_per_rad2",),
    "interface.viscous": ("c_interface_Nms_per_rad",),
    "interface.coulomb": ("friction_Nm",),
    "interface.drifting": ("drift_per_s",),
    "frame.elastic": ("k_frame_Nm_per_rad",),
    "frame.stiffening": ("stiffening_per_rad2",),
    "frame.viscous": ("c_frame_Nms_per_rad",),
    "frame.drifting": ("drift_per_s",),
    "spring.value": ("scale",),
    "spring.stiffening": ("quadratic_per_m",),
    "spring.viscous": ("c_spring_Ns_per_m",),
    "spring.coulomb": ("friction_Nm",),
    "spring.drifting": ("drift_per_s",),
    "transmission.play": ("play_rad",),
    "clutch.delay": ("delay_s",),
    "pulley_radius.value": ("scale",),
    "chain_ratio.value": ("scale",),
    "tensioner.value": ("scale",),
    "knee.elastic": ("k_Nm_per_rad",),
    "knee.viscous": ("c_Nms_per_rad",),
    "knee.coulomb": ("friction_Nm",),
    "hip.viscous": ("c_Nms_per_rad",),
    "hip.coulomb": ("friction_Nm",),
    "thigh_mass.value": ("scale",),
    "thigh_com.value": ("scale",),
    "thigh_inertia.value": ("scale",),
    "shank_mass.value": ("scale",),
    "shank_com.value": ("scale",),
    "shank_inertia.value": ("scale",),
    "bars.offset": ("angle_rad",),
    "segment_lengths.value": ("scale",),
    "ankle_path.offset": ("offset_mm",),
    "cell_direction.tilt": ("tilt_rad",),
    "knee_markers.offset": ("offset_mm",),
    **{
        f"{cell}.{family}": (parameter,)
        for cell in LOAD_CELLS
        for family, parameter in (
            ("gain", "gain"),
            ("offset", "offset_N"),
            ("drift", "drift_N_per_s"),
            ("delay", "delay_s"),
            ("crosstalk", "share"),
        )
    },
    "clocks.delay": ("analog_delay_s",),
}
# Term key → the term keys it needs present (the table's "needs").
REQUIRES: dict[str, tuple[str, ...]] = {
    **{f"interface.{f}": ("interface.elastic",) for f in ("stiffening", "viscous", "coulomb")},
    "interface.drifting": ("interface.elastic",),
    **{f"frame.{f}": ("frame.elastic",) for f in ("stiffening", "viscous", "drifting")},
}

# The values a violation may take (beyond being a finite real number).
_POSITIVE = (
    "interface.elastic",
    "frame.elastic",
    "spring.value",
    "pulley_radius.value",
    "chain_ratio.value",
    "segment_lengths.value",
    *(f"{seg}_{what}.value" for seg in ("thigh", "shank") for what in ("mass", "com", "inertia")),
    *(f"{cell}.gain" for cell in LOAD_CELLS),
)
_NON_NEGATIVE = (
    *(f"{el}.{f}" for el in ("interface", "frame") for f in ("stiffening", "viscous")),
    "interface.coulomb",
    *(f"spring.{f}" for f in ("stiffening", "viscous", "coulomb")),
    "transmission.play",
    "tensioner.value",
    *(f"knee.{f}" for f in ("elastic", "viscous", "coulomb")),
    *(f"hip.{f}" for f in ("viscous", "coulomb")),
)
_BOUNDED = {  # key → (lowest, highest) allowed, open at a finite end unless it is 0
    "clutch.delay": (0.0, CLUTCH_RELEASE_FRACTION * STRIDE_S),
    "bars.offset": (-math.pi / 2, math.pi / 2),
    "cell_direction.tilt": (-math.pi / 2, math.pi / 2),
    **{f"{cell}.delay": (0.0, STRIDE_S) for cell in LOAD_CELLS},
    **{f"{cell}.crosstalk": (-1.0, 1.0) for cell in LOAD_CELLS},
    "clocks.delay": (-STRIDE_S, STRIDE_S),
}
DRIFTS = ("interface.drifting", "frame.drifting", "spring.drifting")


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


class ExoResponse(NamedTuple):
    """Exoskeleton per sample: M (N·m), δ, ε, s (rad), tension (N), spring length (m)."""

    moment: np.ndarray
    interface: np.ndarray
    frame: np.ndarray
    spring_side: np.ndarray
    tension: np.ndarray
    spring_length: np.ndarray


class Trial(NamedTuple):
    """One simulated trial: markers (3, 12, frames) in mm and analog channels (5, samples)."""

    name: str
    spring_N_per_m: float
    points_mm: np.ndarray
    analogs: np.ndarray


def checked_violations(violations: Mapping[str, Mapping[str, float]] | None) -> dict:
    """Validated copy of violations: known keys, exact parameters, needs met, physical values."""
    out = {}
    for key, params in (violations or {}).items():
        if key not in VIOLATIONS:
            raise ValueError(f"unknown violation {key!r}; expected one of {sorted(VIOLATIONS)}")
        if not isinstance(params, Mapping) or set(params) != set(VIOLATIONS[key]):
            got = sorted(params) if isinstance(params, Mapping) else params
            raise ValueError(f"violation {key!r} needs exactly {VIOLATIONS[key]}, got {got}")
        (name,) = VIOLATIONS[key]
        value = params[name]
        if isinstance(value, bool) or not isinstance(value, Real) or not math.isfinite(value):
            raise ValueError(f"violation {key!r}: {name} must be a finite number, got {value!r}")
        value = float(value)
        if key in _POSITIVE and not value > 0.0:
            raise ValueError(f"violation {key!r}: {name} must be > 0, got {value}")
        if key in _NON_NEGATIVE and not value >= 0.0:
            raise ValueError(f"violation {key!r}: {name} must be ≥ 0, got {value}")
        if key in _BOUNDED:
            low, high = _BOUNDED[key]
            if not ((low <= value if low == 0.0 else low < value) and value < high):
                raise ValueError(
                    f"violation {key!r}: {name} must lie in [{low}, {high}), got {value}"
                )
        out[key] = {name: value}
    for key in out:
        missing = [need for need in REQUIRES.get(key, ()) if need not in out]
        if missing:
            raise ValueError(f"violation {key!r} needs {missing} present")
    return out


def _value(violations: Mapping[str, Mapping[str, float]], key: str, neutral: float) -> float:
    """The one parameter of violation `key`, or its neutral value when the key is absent."""
    if key not in violations:
        return neutral
    return float(violations[key][VIOLATIONS[key][0]])


def check_duration(violations: Mapping[str, Mapping[str, float]], duration_s: float) -> None:
    """Refuse a drift that takes a stiffness to k·(1 + ρ·t) ≤ 0 within a trial of duration_s."""
    for key in DRIFTS:
        rho = _value(violations, key, 0.0)
        if 1.0 + rho * duration_s <= 0.0:
            raise ValueError(
                f"violation {key!r}: drift_per_s = {rho} makes the stiffness k·(1 + ρ·t) ≤ 0 "
                f"within a {duration_s:g} s trial"
            )


def real_leg(violations: Mapping[str, Mapping[str, float]]) -> Leg:
    """The real leg: segment values and both lengths s × the rig's, the ankle line o anterior."""
    length = _value(violations, "segment_lengths.value", 1.0)

    def scaled(key: str, nominal: float) -> float:
        return nominal * _value(violations, f"{key}.value", 1.0)

    return Leg(
        L_THIGH * length,
        L_SHANK * length,
        scaled("thigh_mass", M_THIGH),
        scaled("shank_mass", M_SHANK),
        scaled("thigh_com", COM_THIGH),
        scaled("shank_com", COM_SHANK),
        scaled("thigh_inertia", I_THIGH),
        scaled("shank_inertia", I_SHANK),
        _value(violations, "ankle_path.offset", 0.0) / 1000.0,
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
) -> tuple[np.ndarray, np.ndarray]:
    """Hexapod force (F_x, F_y) on the ankle (N), Newton–Euler: leg about hip, shank about knee.

    Whole leg about the fixed hip: x_A F_y − y_A F_x = Σ(I α + m r × a) + g Σ m x − M_hip, with
    M_hip = −(c φ̇1 + τ sign φ̇1) the hip's moment on the thigh; shank about the knee:
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
        _value(violations, "knee.elastic", 0.0) * motion.theta
        + _value(violations, "knee.viscous", 0.0) * motion.omega
        + _value(violations, "knee.coulomb", 0.0) * np.sign(motion.omega)
    )


# Layout of the parameter vector of the numba chain solver: two series elements (interface at
# E_INTERFACE, frame at E_FRAME: present, k, β, c, τ, ρ), the spring side, the play, the step.
E_INTERFACE, E_FRAME = 0, 6
(E_ON, E_K, E_BETA, E_C, E_TAU, E_RHO) = range(6)
(S_K, S_A, S_C, S_RHO, S_F0, S_R, S_N, S_KT, S_TAU, P_HAS_PLAY, P_PLAY, P_H, P_SIZE) = range(
    12, 25
)  # fmt: skip
_TOL = 1e-15


@numba.njit(cache=True)
def _element(m: float, x_prev: float, t: float, p: np.ndarray, b: int) -> tuple[float, float]:
    """Deflection x and dx/dM of k(t)(x + βx³) + c·ẋ + τ·sign ẋ = M (implicit Euler; 0 if rigid)."""
    if p[b + E_ON] == 0.0:
        return 0.0, 0.0
    k = p[b + E_K] * (1.0 + p[b + E_RHO] * t)
    beta, ch, tau = p[b + E_BETA], p[b + E_C] / p[P_H], p[b + E_TAU]
    excess = m - k * (x_prev + beta * x_prev**3)
    if abs(excess) <= tau:  # the friction holds: x sticks
        return x_prev, 0.0
    target = m - (tau if excess > 0.0 else -tau)  # k(x + βx³) + c(x − x_prev)/h = target
    if beta == 0.0:
        return (target + ch * x_prev) / (k + ch), 1.0 / (k + ch)
    # G(x) rises with slope ≥ k + c/h, so the root lies within |G(x_prev)|/(k + c/h) of x_prev.
    g0 = k * (x_prev + beta * x_prev**3) - target
    lo, hi = x_prev, x_prev - g0 / (k + ch)
    if lo > hi:
        lo, hi = hi, lo
    x = x_prev - g0 / (k * (1.0 + 3.0 * beta * x_prev * x_prev) + ch)
    for _ in range(200):
        if not lo <= x <= hi:
            x = 0.5 * (lo + hi)
        g = k * (x + beta * x**3) + ch * (x - x_prev) - target
        dg = k * (1.0 + 3.0 * beta * x * x) + ch
        if g == 0.0:
            break
        if g > 0.0:
            hi = x
        else:
            lo = x
        step = g / dg
        x -= step
        if abs(step) <= _TOL * (1.0 + abs(x)) or hi - lo <= _TOL * (1.0 + abs(x)):
            break
    x = min(max(x, lo), hi)
    return x, 1.0 / (k * (1.0 + 3.0 * beta * x * x) + ch)


@numba.njit(cache=True)
def _compliance(m: float, d_prev: float, e_prev: float, t: float, p: np.ndarray):
    """C(M) = δ(M) + ε(M), the interface's and frame's deflections under M, and C′(M)."""
    d, dd = _element(m, d_prev, t, p, E_INTERFACE)
    e, de = _element(m, e_prev, t, p, E_FRAME)
    return d + e, dd + de


@numba.njit(cache=True)
def _slack_stretch(k: float, a: float, f0: float) -> float:
    """Stretch x < 0 where F0 + k·x·(1 + a·|x|) = 0: −F0/k, or (1 − √(1 + 4aF0/k))/(2a)."""
    if a == 0.0:
        return -f0 / k
    return (1.0 - math.sqrt(1.0 + 4.0 * a * f0 / k)) / (2.0 * a)


@numba.njit(cache=True)
def _spring(s: float, s_prev: float, t: float, p: np.ndarray) -> tuple[float, float, float]:
    """M_s = n(rF − max(rF0 + k_t·n·s, 0)), F = F0 + k(t)·x(1 + a|x|) + c·ẋ ≥ 0 taut, x = r·n·s."""
    rn = p[S_R] * p[S_N]
    k = p[S_K] * (1.0 + p[S_RHO] * t)
    a, f0 = p[S_A], p[S_F0]
    x = rn * s
    # The spring and its damping pull through the cable while their force is positive (taut).
    f = f0 + k * x * (1.0 + a * abs(x)) + p[S_C] * rn * (s - s_prev) / p[P_H]
    df = k * (1.0 + 2.0 * a * abs(x)) + p[S_C] / p[P_H]
    if f <= 0.0:  # the cable cannot push
        f, df = 0.0, 0.0
    kt = p[S_KT] * p[S_N] ** 2
    if p[S_R] * f0 + p[S_KT] * p[S_N] * s <= 0.0:  # the tensioner, like the chain, only pulls
        return rn * f, rn * rn * df, f
    return rn * (f - f0) - kt * s, rn * rn * df - kt, f


@numba.njit(cache=True)
def _residual(kind: int, s: float, sign: float, target: float, st: np.ndarray, t: float, p):
    """Kind 0: R = s + C(M_s(s) + sign·τ) − u (taut chain); kind 1: R = M_s(s) + sign·τ − target."""
    ms, dms, _ = _spring(s, st[2], t, p)
    m = ms + sign * p[S_TAU]
    if kind == 1:
        return m - target, dms
    c, dc = _compliance(m, st[0], st[1], t, p)
    return s + c - target, 1.0 + dc * dms


@numba.njit(cache=True)
def _root(kind: int, sign: float, target: float, f0: float, df0: float, st: np.ndarray, t, p):
    """Nearest root of the residual from s_prev towards sign: doubling bracket, Newton–bisection."""
    s_prev = st[2]
    step = abs(f0 / df0) * 1.25 if df0 != 0.0 else 1e-6
    step = max(step, 1e-13)
    inner, outer, f_out = s_prev, s_prev, f0
    for _ in range(80):
        outer = s_prev + sign * step
        f_out, _ = _residual(kind, outer, sign, target, st, t, p)
        if f_out == 0.0:
            return outer
        if (f_out > 0.0) != (f0 > 0.0):
            break
        inner, f0, step = outer, f_out, 2.0 * step
    if (f_out > 0.0) == (f0 > 0.0):  # no root within reach: stop where the search ended
        return outer
    a, b, fa, fb = inner, outer, f0, f_out  # fa and fb have opposite signs
    x = b - fb * (b - a) / (fb - fa)
    for _ in range(200):
        lo, hi = min(a, b), max(a, b)
        if not lo < x < hi:
            x = 0.5 * (a + b)
        f, df = _residual(kind, x, sign, target, st, t, p)
        if f == 0.0:
            return x
        if (f > 0.0) == (fa > 0.0):
            a, fa = x, f
        else:
            b, fb = x, f
        nxt = x - f / df if df != 0.0 else 0.5 * (a + b)
        if not min(a, b) < nxt < max(a, b):
            nxt = 0.5 * (a + b)
        if abs(nxt - x) <= _TOL * (1.0 + abs(x)) or abs(b - a) <= 2 * _TOL * (1.0 + abs(x)):
            return nxt
        x = nxt
    return x


@numba.njit(cache=True)
def _moment_for(target: float, lo: float, hi: float, guess: float, st: np.ndarray, t, p) -> float:
    """M in [lo, hi] with C(M) = target (C nondecreasing), the nearest the guess if C is flat."""
    x = guess
    for _ in range(200):
        c, dc = _compliance(x, st[0], st[1], t, p)
        f = c - target
        if abs(f) <= 4.0 * _TOL * (1.0 + abs(target)):
            return x
        if f > 0.0:
            hi = x
        else:
            lo = x
        nxt = x - f / dc if dc > 0.0 else 0.5 * (lo + hi)
        if not lo < nxt < hi:
            nxt = 0.5 * (lo + hi)
        if abs(nxt - x) <= _TOL * (1.0 + abs(x)) or hi - lo <= _TOL * (1.0 + abs(x)):
            return nxt
        x = nxt
    return x


@numba.njit(cache=True)
def _taut(u: float, st: np.ndarray, m_prev: float, t: float, p: np.ndarray):
    """Taut chain s + δ(M) + ε(M) = u: the spring side sticks while |M − M_s(s_prev)| ≤ τ; s, M."""
    s_prev, tau = st[2], p[S_TAU]
    m0, _, _ = _spring(s_prev, s_prev, t, p)
    if p[E_INTERFACE + E_ON] == 0.0 and p[E_FRAME + E_ON] == 0.0:  # rigid: s = u
        if u == s_prev:
            return s_prev, min(max(m_prev, m0 - tau), m0 + tau)
        ms, _, _ = _spring(u, s_prev, t, p)
        return u, ms + (tau if u > s_prev else -tau)
    lo, hi = m0 - tau, m0 + tau
    c_lo, _ = _compliance(lo, st[0], st[1], t, p)
    r_lo = s_prev + c_lo - u
    r_hi = r_lo
    if tau > 0.0:
        c_hi, _ = _compliance(hi, st[0], st[1], t, p)
        r_hi = s_prev + c_hi - u
    if r_lo <= 0.0 <= r_hi:
        return s_prev, _moment_for(u - s_prev, lo, hi, min(max(m_prev, lo), hi), st, t, p)
    sign = 1.0 if r_hi < 0.0 else -1.0
    f0, df0 = _residual(0, s_prev, sign, u, st, t, p)
    s = _root(0, sign, u, f0, df0, st, t, p)
    ms, _, _ = _spring(s, s_prev, t, p)
    return s, ms + sign * tau


@numba.njit(cache=True)
def _free_side(st: np.ndarray, t: float, p: np.ndarray) -> float:
    """Spring side under no moment: sticks while |M_s(s_prev)| ≤ τ, else slides to M_s = ±τ."""
    s_prev = st[2]
    m0, _, _ = _spring(s_prev, s_prev, t, p)
    if abs(m0) <= p[S_TAU]:
        return s_prev
    sign = -1.0 if m0 > 0.0 else 1.0
    f0, df0 = _residual(1, s_prev, sign, 0.0, st, t, p)
    return _root(1, sign, 0.0, f0, df0, st, t, p)


@numba.njit(cache=True)
def _engaged(u_rel: float, st: np.ndarray, m_prev: float, t: float, p: np.ndarray):
    """Engaged step: taut chain after the play (M ≥ 0 with play) or slack (M = 0); s, M, δ, ε."""
    u = u_rel - (p[P_PLAY] if p[P_HAS_PLAY] > 0.0 else 0.0)
    s, m = _taut(u, st, m_prev, t, p)
    if p[P_HAS_PLAY] > 0.0 and m < 0.0:
        m = 0.0
        s = _free_side(st, t, p)
    d, _ = _element(m, st[0], t, p, E_INTERFACE)
    e, _ = _element(m, st[1], t, p, E_FRAME)
    if p[P_HAS_PLAY] > 0.0 and m == 0.0:
        s = max(s, u - d - e)
    return s, m, d, e


@numba.njit(cache=True)
def _chain(theta: np.ndarray, phase: np.ndarray, release: np.ndarray, p: np.ndarray):
    """March free (M = 0, s = 0), engaged (implicit series chain) and release (×(1 − w)) samples."""
    n = theta.size
    moment, delta, frame, side = np.zeros(n), np.zeros(n), np.zeros(n), np.zeros(n)
    tension, length = np.zeros(n), np.zeros(n)
    st = np.zeros(3)  # previous δ, ε, s
    m, s, d, e, th_e, u_e, m_r, s_r = 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0
    prev = 0
    for j in range(n):
        t = j * p[P_H]
        st[0], st[1], st[2] = d, e, s
        ph = phase[j]
        if ph == 1 and prev != 1:  # the clutch locks: the spring side starts at its pretension
            m, s = 0.0, 0.0
        elif ph == 1:
            s, m, d, e = _engaged(theta[j] - th_e + u_e, st, m, t, p)
        elif ph == 2:
            if prev == 1:
                m_r, s_r = m, s
            m, s = m_r * (1.0 - release[j]), s_r * (1.0 - release[j])
        else:
            m, s = 0.0, 0.0
        if ph != 1 or prev != 1:  # the interface and frame carry the moment M
            d, _ = _element(m, st[0], t, p, E_INTERFACE)
            e, _ = _element(m, st[1], t, p, E_FRAME)
        if ph == 1 and prev != 1:
            th_e, u_e = theta[j], d + e
        _, _, f = _spring(s, st[2], t, p)
        k = p[S_K] * (1.0 + p[S_RHO] * t)
        x = p[S_R] * p[S_N] * s
        moment[j], delta[j], frame[j], side[j], tension[j] = m, d, e, s, f
        length[j] = max(x, _slack_stretch(k, p[S_A], p[S_F0]))
        prev = ph
    return moment, delta, frame, side, tension, length


def clutch_schedule(
    n: int, fs_hz: float, delay_s: float, release_s: float
) -> tuple[np.ndarray, np.ndarray]:
    """Clutch phase per sample (0 free, 1 engaged delay…35 %, 2 releasing), release progress w."""
    per = round(STRIDE_S * fs_hz)
    k = np.arange(n) % per
    on = int(np.ceil(delay_s * fs_hz - 1e-9))
    off = round(CLUTCH_RELEASE_FRACTION * per)
    end = off + round(release_s * fs_hz)
    phase = np.zeros(n, dtype=np.int64)
    if on < off:
        phase[(k >= on) & (k < off)] = 1
        phase[(k >= off) & (k < end)] = 2
    w = smoothstep((k - off) / max(end - off, 1))[0]
    return phase, w


def chain_parameters(
    spring_N_per_m: float, violations: Mapping[str, Mapping[str, float]], fs_hz: float
) -> np.ndarray:
    """Parameter vector of the chain solver for the real rig: elements, spring side, play, step."""
    v = violations
    p = np.zeros(P_SIZE)
    for b, name, k_key, c_key in (
        (E_INTERFACE, "interface", "interface.elastic", "interface.viscous"),
        (E_FRAME, "frame", "frame.elastic", "frame.viscous"),
    ):
        if k_key in v:
            p[b + E_ON] = 1.0
            p[b + E_K] = _value(v, k_key, math.inf)
            p[b + E_BETA] = _value(v, f"{name}.stiffening", 0.0)
            p[b + E_C] = _value(v, c_key, 0.0)
            p[b + E_TAU] = _value(v, f"{name}.coulomb", 0.0)
            p[b + E_RHO] = _value(v, f"{name}.drifting", 0.0)
    p[S_K] = spring_N_per_m * _value(v, "spring.value", 1.0)
    p[S_A] = _value(v, "spring.stiffening", 0.0)
    p[S_C] = _value(v, "spring.viscous", 0.0)
    p[S_RHO] = _value(v, "spring.drifting", 0.0)
    p[S_F0] = F0_N
    p[S_R] = PULLEY_R * _value(v, "pulley_radius.value", 1.0)
    p[S_N] = CHAIN_RATIO * _value(v, "chain_ratio.value", 1.0)
    p[S_KT] = K_TENSIONER * _value(v, "tensioner.value", 1.0)
    p[S_TAU] = _value(v, "spring.coulomb", 0.0)
    if "transmission.play" in v:
        p[P_HAS_PLAY], p[P_PLAY] = 1.0, _value(v, "transmission.play", 0.0)
    p[P_H] = 1.0 / fs_hz
    return p


def exoskeleton_response(
    theta: np.ndarray,
    fs_hz: float,
    spring_N_per_m: float,
    violations: Mapping[str, Mapping[str, float]] | None = None,
    release_s: float = 0.1,
) -> ExoResponse:
    """Exoskeleton M, δ, ε, s, tension and spring length for θ sampled at fs_hz from a stride start.

    The drifts' t is the time since θ's first sample.
    """
    violations = checked_violations(violations)
    if not spring_N_per_m > 0:
        raise ValueError(f"the spring's rate must be > 0, got {spring_N_per_m}")
    check_duration(violations, (theta.size - 1) / fs_hz)
    p = chain_parameters(spring_N_per_m, violations, fs_hz)
    k_low = p[S_K] * min(1.0, 1.0 + p[S_RHO] * (theta.size - 1) / fs_hz)
    if k_low * p[S_R] ** 2 <= p[S_KT]:
        raise ValueError(
            "the tensioner overpowers the spring: k·r² ≤ k_tensioner gives a knee stiffness ≤ 0"
        )
    delay = _value(violations, "clutch.delay", 0.0)
    phase, w = clutch_schedule(theta.size, fs_hz, delay, release_s)
    moment, delta, frame, side, tension, stretch = _chain(
        np.ascontiguousarray(theta, float), phase, w, p
    )
    return ExoResponse(moment, delta, frame, side, tension, SPRING_LEN_M + stretch)


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


def sync_signal(n: int, delay_samples: float = 0.0) -> np.ndarray:
    """SYNC (V) stamped k: 5 V while 0 ≤ k − d < n and (k − d) mod stride < 20 ms, else 0."""
    pos = np.arange(n) - delay_samples
    on = (pos >= 0) & (pos < n) & (np.mod(pos, round(STRIDE_S * FS_ANALOG)) < SYNC_S * FS_ANALOG)
    return np.where(on, SYNC_V, 0.0)


def _lagged(signal: np.ndarray, substeps: int, delay_s: float) -> np.ndarray:
    """Analog samples k/fs of a signal sampled substeps× faster, read at k/fs − d (ends held)."""
    if delay_s == 0.0:
        return signal[::substeps]
    fine_fs = FS_ANALOG * substeps
    n = signal.size // substeps
    return np.interp(np.arange(n) * substeps - delay_s * fine_fs, np.arange(signal.size), signal)


def load_cell_signals(
    fx: np.ndarray,
    fy: np.ndarray,
    tension: np.ndarray,
    violations: Mapping[str, Mapping[str, float]],
    cell_shares: Sequence[float],
    substeps: int,
) -> np.ndarray:
    """Load cells' g·(true + s·other)(t − d − D) (4, n); ankle cells share F_y cos α + F_x sin α.

    The ankle cells' crosstalk is a share of the spring's true tension, the spring cell's a share
    of the true vertical ankle force F_y; D is the analog clock's delay.
    """
    tilt = _value(violations, "cell_direction.tilt", 0.0)
    along = fy * math.cos(tilt) + fx * math.sin(tilt) if tilt else fy
    sensed = [share * along for share in cell_shares] + [tension]
    others = [tension] * len(ANKLE_CELLS) + [fy]
    clock = _value(violations, "clocks.delay", 0.0)
    out = []
    for cell, own, other in zip(LOAD_CELLS, sensed, others, strict=True):
        share = _value(violations, f"{cell}.crosstalk", 0.0)
        signal = own + share * other if share else own
        delay = _value(violations, f"{cell}.delay", 0.0) + clock
        out.append(_value(violations, f"{cell}.gain", 1.0) * _lagged(signal, substeps, delay))
    return np.array(out)


def simulate_study(
    *,
    cycle_csv: Path,
    springs_N_per_m: Sequence[float],
    strides: int,
    ramp_strides: int,
    violations: Mapping[str, Mapping[str, float]],
    seed: int,
    marker_noise_mm: float = 0.15,
    cell_noise_N: float = 0.5,
    occlusions_per_marker: float = 0.0,
    cell_shares: Sequence[float] = (0.30, 0.33, 0.37),
    substeps: int = 4,
    release_s: float = 0.1,
) -> list[Trial]:
    """The trials write_study writes (one per spring, in test order), as arrays."""
    violations = checked_violations(violations)
    if strides <= 2 * ramp_strides or ramp_strides < 0:
        raise ValueError("strides must exceed twice ramp_strides (≥ 0)")
    if len(cell_shares) != 3 or not np.isclose(sum(cell_shares), 1.0):
        raise ValueError("cell_shares must be three shares summing to 1")
    if substeps < 1 or (FS_ANALOG * substeps) % FS_POINT:
        raise ValueError("substeps must be a whole number ≥ 1")
    names = [f"k{k:.0f}" for k in springs_N_per_m]
    if len(set(names)) != len(names):
        raise ValueError(f"springs give duplicate trial names: {names}")
    check_duration(violations, strides * STRIDE_S)
    rng = np.random.default_rng(seed)
    cycle = read_mean_cycle(cycle_csv)
    shifts = np.deg2rad(rng.normal(0.0, SHIFT_SD_DEG, (strides, cycle_extrema(cycle).size)))
    n = strides * round(STRIDE_S * FS_ANALOG)
    t = np.arange(n) / FS_ANALOG
    fine = knee_motion(
        cycle, shifts, ramp_strides, np.arange(n * substeps) / (FS_ANALOG * substeps)
    )
    leg = real_leg(violations)
    hinge = phantom_knee_moment(fine, violations)
    hip = (_value(violations, "hip.viscous", 0.0), _value(violations, "hip.coulomb", 0.0))
    sync = sync_signal(n, _value(violations, "clocks.delay", 0.0) * FS_ANALOG)
    frames = slice(None, None, substeps * FS_ANALOG // FS_POINT)
    trials = []
    for name, k in zip(names, springs_N_per_m, strict=True):
        exo = exoskeleton_response(fine.theta, FS_ANALOG * substeps, k, violations, release_s)
        fx, fy = ankle_forces(fine, exo.moment + hinge, leg, *hip)
        cells = load_cell_signals(fx, fy, exo.tension, violations, cell_shares, substeps)
        cells[:3] += rng.normal(0.0, cell_noise_N, (3, n))
        cells[3] += rng.normal(0.0, cell_noise_N, n)
        for i, cell in enumerate(LOAD_CELLS):
            cells[i] += _value(violations, f"{cell}.offset", 0.0)
            cells[i] += _value(violations, f"{cell}.drift", 0.0) * t
        points = marker_positions(
            fine.theta[frames],
            exo.interface[frames],
            exo.spring_length[frames],
            leg,
            _value(violations, "bars.offset", 0.0),
            _value(violations, "knee_markers.offset", 0.0),
        )
        points += rng.normal(0.0, marker_noise_mm, points.shape)
        _occlude(points, occlusions_per_marker, rng)
        trials.append(Trial(name, float(k), points, np.vstack([cells, sync])))
    return trials


def _occlude(points: np.ndarray, per_marker: float, rng: np.random.Generator) -> None:
    """Blank Poisson(per_marker) gaps of 3–15 frames per marker with NaN, in place."""
    n_frames = points.shape[2]
    counts = rng.poisson(per_marker, size=points.shape[1])
    starts = rng.integers(0, n_frames, size=counts.sum())
    lengths = rng.integers(3, 16, size=counts.sum())
    markers = np.repeat(np.arange(points.shape[1]), counts)
    frames = np.arange(n_frames)
    for mk, st, ln in zip(markers, starts, lengths, strict=True):
        points[:, mk, (frames >= st) & (frames < st + ln)] = np.nan


def write_c3d(path: Path, points_mm: np.ndarray, analogs: np.ndarray) -> None:
    """Write markers (3, 12, frames) at 100 Hz and analog channels (5, samples) at 1000 Hz."""
    c3d = ezc3d.c3d()
    c3d["parameters"]["POINT"]["RATE"]["value"] = np.array([float(FS_POINT)])
    c3d["parameters"]["POINT"]["LABELS"]["value"] = list(MARKERS)
    c3d["parameters"]["ANALOG"]["RATE"]["value"] = np.array([float(FS_ANALOG)])
    c3d["parameters"]["ANALOG"]["LABELS"]["value"] = list(CHANNELS)
    c3d["parameters"]["ANALOG"]["UNITS"]["value"] = list(CHANNEL_UNITS)
    c3d.add_parameter("POINT", "UNITS", ["mm"])
    data = np.ones((4, len(MARKERS), points_mm.shape[2]))
    data[:3] = points_mm
    c3d["data"]["points"] = data
    c3d["data"]["analogs"] = analogs[None, :, :]
    c3d.write(str(path))


def write_study(
    folder: Path,
    *,
    cycle_csv: Path,
    springs_N_per_m: Sequence[float],
    strides: int,
    ramp_strides: int,
    violations: Mapping[str, Mapping[str, float]],
    seed: int,
    marker_noise_mm: float = 0.15,
    cell_noise_N: float = 0.5,
    occlusions_per_marker: float = 0.0,
    cell_shares: Sequence[float] = (0.30, 0.33, 0.37),
    substeps: int = 4,
    release_s: float = 0.1,
) -> Path:
    """Write one C3D per spring and manifest.csv into folder; return the manifest's path."""
    trials = simulate_study(
        cycle_csv=cycle_csv,
        springs_N_per_m=springs_N_per_m,
        strides=strides,
        ramp_strides=ramp_strides,
        violations=violations,
        seed=seed,
        marker_noise_mm=marker_noise_mm,
        cell_noise_N=cell_noise_N,
        occlusions_per_marker=occlusions_per_marker,
        cell_shares=cell_shares,
        substeps=substeps,
        release_s=release_s,
    )
    folder = Path(folder)
    folder.mkdir(parents=True, exist_ok=True)
    rows = []
    for order, trial in enumerate(trials, start=1):
        write_c3d(folder / f"{trial.name}.c3d", trial.points_mm, trial.analogs)
        rows.append((trial.name, f"{trial.name}.c3d", trial.spring_N_per_m, order, ramp_strides))
    manifest = folder / "manifest.csv"
    pd.DataFrame(rows, columns=list(MANIFEST_COLUMNS)).to_csv(manifest, index=False)
    return manifest
