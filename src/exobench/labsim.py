"""Independent recording generator for the phantom + passive knee exoskeleton rig (docs/rig.md §1).

Writes the raw files a lab would write (one C3D per spring and ``manifest.csv``) from the rig
contract and the physics alone: the hexapod drives the knee kinematically along the measured
mean cycle with per-stride peak/valley shifts, the clutched exoskeleton transmits one moment
through interface → bars → frame → play → spring side, and the ankle load cells record the
vertical hexapod force from the two-link leg's equations of motion.

Sign conventions: X anterior, Y up, Z lateral; knee flexion θ positive; an extensor moment M
is positive (it acts counter-clockwise about +Z on the shank and clockwise on the thigh).
"""

from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import NamedTuple

import ezc3d
import numba
import numpy as np
import pandas as pd
from scipy.interpolate import PchipInterpolator

# Rig constants: the nominal rig of the contract (docs/rig.md §1; the spring's pretension and free
# length and the clutch release are the project's nominal values). The open-world validation
# analyses these recordings with the nominal rig.
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
CHANNELS = (*ANKLE_CELLS, "LC_SPRING", "SYNC")
CHANNEL_UNITS = ("N", "N", "N", "N", "V")
MANIFEST_COLUMNS = ("trial", "file", "spring_stiffness_N_per_m", "test_order", "ramp_strides")

EFFECT_PARAMETERS = {
    "interface_compliance": ("k_interface_Nm_per_rad",),
    "interface_stiffening": ("stiffening_per_rad2",),
    "interface_damping": ("c_interface_Nms_per_rad",),
    "frame_compliance": ("k_frame_Nm_per_rad",),
    "frame_friction": ("friction_Nm",),
    "transmission_play": ("play_rad",),
    "clutch_timing": ("delay_s",),
}
FAULT_PARAMETERS = {
    "ankle_cell_gain": ("gain", "channel"),
    "ankle_cell_offset": ("offset_N", "channel"),
    "ankle_cell_drift": ("rate_N_per_s", "channel"),
    "spring_cell_drift": ("rate_N_per_s",),
    "spring_mislabelled": ("factor",),
    "pulley_radius": ("factor",),
    "shank_mass": ("factor",),
    "phantom_knee_friction": ("friction_Nm",),
    "phantom_knee_damping": ("c_Nms_per_rad",),
    "progressive_spring": ("per_m",),
}

# Layout of the parameter vector of the numba chain solver.
(P_K, P_R, P_N, P_KT, P_F0, P_A, P_HAS_INT, P_KI, P_BETA, P_CI, P_COMPF, P_TAU, P_HAS_PLAY,
 P_PLAY, P_H, P_SIZE) = range(16)  # fmt: skip


class KneeMotion(NamedTuple):
    """Programmed phantom knee flexion and its time derivatives (rad, rad/s, rad/s²)."""

    theta: np.ndarray
    omega: np.ndarray
    alpha: np.ndarray


class ExoResponse(NamedTuple):
    """Exoskeleton state per sample: M (N·m), δ (rad), s (rad), tension (N), spring length (m)."""

    moment: np.ndarray
    interface: np.ndarray
    spring_side: np.ndarray
    tension: np.ndarray
    spring_length: np.ndarray


def _checked(table: Mapping[str, Mapping], allowed: Mapping[str, tuple], what: str) -> dict:
    """Validated copy of effects/faults: known names, exact parameters, dependencies, channels."""
    out = {}
    for name, params in table.items():
        if name not in allowed:
            raise ValueError(f"unknown {what} {name!r}; expected one of {sorted(allowed)}")
        if set(params) != set(allowed[name]):
            raise ValueError(f"{what} {name!r} needs exactly {allowed[name]}, got {sorted(params)}")
        out[name] = dict(params)
    for name in ("interface_stiffening", "interface_damping"):
        if name in out and "interface_compliance" not in out:
            raise ValueError(f"{name} needs interface_compliance")
    chan = [p["channel"] for p in out.values() if "channel" in p]
    if any(c not in ANKLE_CELLS for c in chan):
        raise ValueError(f"fault channel must be one of {ANKLE_CELLS}, got {chan}")
    return out


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
    motion: KneeMotion,
) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """φ1 = atan2(L2 sin θ, L1 + L2 cos θ), φ2 = φ1 − θ (CCW from −Y), rates, accelerations."""
    th, om, al = motion
    l1l2 = L_THIGH * L_SHANK
    d2 = L_THIGH**2 + L_SHANK**2 + 2 * l1l2 * np.cos(th)
    num = l1l2 * np.cos(th) + L_SHANK**2
    dphi = num / d2
    ddphi = l1l2 * np.sin(th) * (2 * num - d2) / d2**2
    phi1 = np.arctan2(L_SHANK * np.sin(th), L_THIGH + L_SHANK * np.cos(th))
    w1 = dphi * om
    a1 = ddphi * om**2 + dphi * al
    return phi1, phi1 - th, w1, w1 - om, a1, a1 - al


def ankle_vertical_force(
    motion: KneeMotion, knee_moment: np.ndarray, shank_mass_factor: float = 1.0
) -> np.ndarray:
    """Ankle F_y (N, up) by Newton–Euler: leg about the hip gives F_x, shank about the knee F_y."""
    m1, m2 = M_THIGH, M_SHANK * shank_mass_factor
    i1, i2 = I_THIGH, I_SHANK * shank_mass_factor
    p1, p2, w1, w2, a1, a2 = leg_angles(motion)
    e1 = np.stack([np.sin(p1), -np.cos(p1)])
    e2 = np.stack([np.sin(p2), -np.cos(p2)])
    n1 = np.stack([np.cos(p1), np.sin(p1)])
    n2 = np.stack([np.cos(p2), np.sin(p2)])
    unit_acc1 = a1 * n1 - w1**2 * e1
    unit_acc2 = a2 * n2 - w2**2 * e2
    r1, r2 = COM_THIGH * e1, L_THIGH * e1 + COM_SHANK * e2
    acc1 = COM_THIGH * unit_acc1
    acc2 = L_THIGH * unit_acc1 + COM_SHANK * unit_acc2

    def cross(a: np.ndarray, b: np.ndarray) -> np.ndarray:
        return a[0] * b[1] - a[1] * b[0]

    d = L_THIGH * np.cos(p1) + L_SHANK * np.cos(p2)
    fx = (
        i1 * a1 + m1 * cross(r1, acc1) + i2 * a2 + m2 * cross(r2, acc2)
        + G * (m1 * r1[0] + m2 * r2[0])
    ) / d  # fmt: skip
    rel = COM_SHANK * e2
    shank_rhs = i2 * a2 + m2 * cross(rel, acc2) + m2 * G * rel[0] - knee_moment
    return (shank_rhs + L_SHANK * e2[1] * fx) / (L_SHANK * e2[0])


@numba.njit(cache=True)
def _spring_side(s: float, p: np.ndarray) -> tuple[float, float]:
    """M_s(s) = n·r·(F − F0) − k_t·n²·s, F = max(F0 + k·x·(1 + a·x), 0), x = r·n·s; and M_s′(s)."""
    n, r = p[P_N], p[P_R]
    x = r * n * s
    f = p[P_F0] + p[P_K] * x * (1.0 + p[P_A] * x)
    kt = p[P_KT] * n * n
    if f <= 0.0:
        return -n * r * p[P_F0] - kt * s, -kt
    return n * r * (f - p[P_F0]) - kt * s, n * r * p[P_K] * r * n * (1.0 + 2.0 * p[P_A] * x) - kt


@numba.njit(cache=True)
def _knee_side(lam: float, d_prev: float, p: np.ndarray) -> tuple[float, float, float, float]:
    """M, M′, E = δ + M/k_f, E′ at λ: λ = δ, M = k_i(δ + βδ³) + c_i(δ − δ_prev)/h; else λ = M."""
    if p[P_HAS_INT] > 0.0:
        c = p[P_CI] / p[P_H]
        m = p[P_KI] * (lam + p[P_BETA] * lam**3) + c * (lam - d_prev)
        dm = p[P_KI] * (1.0 + 3.0 * p[P_BETA] * lam * lam) + c
        return m, dm, lam + p[P_COMPF] * m, 1.0 + p[P_COMPF] * dm
    return lam, 1.0, p[P_COMPF] * lam, p[P_COMPF]


@numba.njit(cache=True)
def _residual(kind: int, lam: float, target: float, sign: float, d_prev: float, p: np.ndarray):
    """Rising residual, slope: E − y | M − M_s(y − E) − sign·τ | M − y | M_s(λ) − y (kinds 0–3)."""
    if kind == 3:
        ms, dms = _spring_side(lam, p)
        return ms - target, dms
    m, dm, e, de = _knee_side(lam, d_prev, p)
    if kind == 0:
        return e - target, de
    if kind == 2:
        return m - target, dm
    ms, dms = _spring_side(target - e, p)
    return m - ms - sign * p[P_TAU], dm + dms * de


@numba.njit(cache=True)
def _solve(kind: int, target: float, sign: float, d_prev: float, lam0: float, p: np.ndarray):
    """Root of a rising residual: doubling bracket from λ0, then safeguarded Newton–bisection."""
    f0, _ = _residual(kind, lam0, target, sign, d_prev, p)
    if f0 == 0.0:
        return lam0
    direction = -1.0 if f0 > 0.0 else 1.0
    inner, outer, step = lam0, lam0, 1e-4
    for _ in range(200):
        outer = lam0 + direction * step
        fp, _ = _residual(kind, outer, target, sign, d_prev, p)
        if fp * f0 <= 0.0:
            break
        inner, step = outer, 2.0 * step
    lo, hi = (outer, inner) if f0 > 0.0 else (inner, outer)
    lam = 0.5 * (lo + hi)
    for _ in range(200):
        f, df = _residual(kind, lam, target, sign, d_prev, p)
        if f == 0.0:
            return lam
        if f > 0.0:
            hi = lam
        else:
            lo = lam
        nxt = lam - f / df if df > 0.0 else 0.5 * (lo + hi)
        if not lo < nxt < hi:
            nxt = 0.5 * (lo + hi)
        if abs(nxt - lam) <= 1e-15 * (1.0 + abs(lam)) or hi - lo <= 1e-15 * (1.0 + abs(lam)):
            return nxt
        lam = nxt
    return lam


@numba.njit(cache=True)
def _bilateral(u: float, s_prev: float, m_prev: float, d_prev: float, p: np.ndarray):
    """Taut chain: spring side sticks while |M − M_s(s_prev)| ≤ τ, else M = M_s(s) ± τ; s, M, λ."""
    tau = p[P_TAU]
    if p[P_HAS_INT] == 0.0 and p[P_COMPF] == 0.0:
        ms, _ = _spring_side(u, p)
        if u > s_prev:
            m = ms + tau
        elif u < s_prev:
            m = ms - tau
        else:
            m = min(max(m_prev, ms - tau), ms + tau)
        return u, m, 0.0
    lam0 = d_prev if p[P_HAS_INT] > 0.0 else m_prev
    lam = _solve(0, u - s_prev, 0.0, d_prev, lam0, p)
    m, _, _, _ = _knee_side(lam, d_prev, p)
    ms, _ = _spring_side(s_prev, p)
    if abs(m - ms) <= tau:
        return s_prev, m, lam
    sign = 1.0 if m > ms else -1.0
    lam = _solve(1, u, sign, d_prev, lam, p)
    m, _, e, _ = _knee_side(lam, d_prev, p)
    return u - e, m, lam


@numba.njit(cache=True)
def _engaged(u: float, s_prev: float, m_prev: float, d_prev: float, p: np.ndarray):
    """Engaged step at knee rotation u: taut chain (gap = play, M ≥ 0) or slack (M = 0); s, M, δ."""
    has_int = p[P_HAS_INT] > 0.0
    gap = p[P_PLAY] if p[P_HAS_PLAY] > 0.0 else 0.0
    s, m, lam = _bilateral(u - gap, s_prev, m_prev, d_prev, p)
    if p[P_HAS_PLAY] > 0.0 and m < 0.0:
        m = 0.0
        lam = _solve(2, 0.0, 0.0, d_prev, d_prev, p) if has_int else 0.0
        _, _, e, _ = _knee_side(lam, d_prev, p)
        ms, _ = _spring_side(s_prev, p)
        s = s_prev
        if abs(ms) > p[P_TAU]:
            s = _solve(3, np.sign(ms) * p[P_TAU], 0.0, 0.0, s_prev, p)
        s = max(s, u - e - gap)
    return s, m, lam if has_int else 0.0


@numba.njit(cache=True)
def _relaxed(m: float, d_prev: float, p: np.ndarray) -> float:
    """Interface deflection δ carrying moment m (solves M(δ) = m; 0 without an interface)."""
    if p[P_HAS_INT] > 0.0:
        return _solve(2, m, 0.0, d_prev, d_prev, p)
    return 0.0


@numba.njit(cache=True)
def _chain(theta: np.ndarray, phase: np.ndarray, release: np.ndarray, p: np.ndarray):
    """March free (M = 0, s = 0), engaged (implicit series chain) and release (×(1 − w)) samples."""
    n = theta.size
    moment, delta, side = np.zeros(n), np.zeros(n), np.zeros(n)
    m, s, d, th_e, d_e, m_r, s_r = 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0
    prev = 0
    for j in range(n):
        ph = phase[j]
        if ph == 1 and prev != 1:
            m, s, d = 0.0, 0.0, _relaxed(0.0, d, p)
            th_e, d_e = theta[j], d
        elif ph == 1:
            s, m, d = _engaged(theta[j] - th_e + d_e, s, m, d, p)
        elif ph == 2:
            if prev == 1:
                m_r, s_r = m, s
            m, s = m_r * (1.0 - release[j]), s_r * (1.0 - release[j])
            d = _relaxed(m, d, p)
        else:
            m, s, d = 0.0, 0.0, _relaxed(0.0, d, p)
        moment[j], delta[j], side[j] = m, d, s
        prev = ph
    return moment, delta, side


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


def exoskeleton_response(
    theta: np.ndarray,
    fs_hz: float,
    spring_N_per_m: float,
    effects: Mapping[str, Mapping[str, float]],
    faults: Mapping[str, Mapping] | None = None,
    release_s: float = 0.1,
) -> ExoResponse:
    """Exoskeleton M, δ, s, tension and spring length for θ sampled at fs_hz from a stride start."""
    effects = _checked(effects, EFFECT_PARAMETERS, "effect")
    faults = _checked(faults or {}, FAULT_PARAMETERS, "fault")
    k = spring_N_per_m * faults.get("spring_mislabelled", {}).get("factor", 1.0)
    r = PULLEY_R * faults.get("pulley_radius", {}).get("factor", 1.0)
    a = faults.get("progressive_spring", {}).get("per_m", 0.0)
    p = np.zeros(P_SIZE)
    p[[P_K, P_R, P_N, P_KT, P_F0, P_A]] = k, r, CHAIN_RATIO, K_TENSIONER, F0_N, a
    if "interface_compliance" in effects:
        p[P_HAS_INT] = 1.0
        p[P_KI] = effects["interface_compliance"]["k_interface_Nm_per_rad"]
        p[P_BETA] = effects.get("interface_stiffening", {}).get("stiffening_per_rad2", 0.0)
        p[P_CI] = effects.get("interface_damping", {}).get("c_interface_Nms_per_rad", 0.0)
    if "frame_compliance" in effects:
        p[P_COMPF] = 1.0 / effects["frame_compliance"]["k_frame_Nm_per_rad"]
    p[P_TAU] = effects.get("frame_friction", {}).get("friction_Nm", 0.0)
    if "transmission_play" in effects:
        p[P_HAS_PLAY], p[P_PLAY] = 1.0, effects["transmission_play"]["play_rad"]
    p[P_H] = 1.0 / fs_hz
    if min(k, r, p[P_KI] if p[P_HAS_INT] else 1.0) <= 0 or min(p[P_BETA], p[P_CI], p[P_TAU]) < 0:
        raise ValueError("stiffnesses, radius must be positive; stiffening, damping, friction ≥ 0")
    delay = effects.get("clutch_timing", {}).get("delay_s", 0.0)
    if delay < 0 or p[P_PLAY] < 0:
        raise ValueError("clutch delay and play must be ≥ 0")
    phase, w = clutch_schedule(theta.size, fs_hz, delay, release_s)
    moment, delta, side = _chain(np.ascontiguousarray(theta, float), phase, w, p)
    x = r * CHAIN_RATIO * side
    tension = np.maximum(F0_N + k * x * (1.0 + a * x), 0.0)
    slack_x = -F0_N / k if a == 0 else (-1.0 + np.sqrt(1.0 - 4.0 * a * F0_N / k)) / (2.0 * a)
    return ExoResponse(moment, delta, side, tension, SPRING_LEN_M + np.maximum(x, slack_x))


def marker_positions(theta: np.ndarray, delta: np.ndarray, spring_len_m: np.ndarray) -> np.ndarray:
    """Markers (3, 12, n) in mm: joints, bars at φ1 − δ/2 and φ2 + δ/2, spring on the thigh bar."""
    p1, p2, *_ = leg_angles(KneeMotion(theta, np.zeros_like(theta), np.zeros_like(theta)))

    def unit(phi: np.ndarray) -> np.ndarray:
        return np.stack([np.sin(phi), -np.cos(phi), np.zeros_like(phi)])

    hip = np.broadcast_to(HIP_MM[:, None], (3, theta.size))
    knee = hip + 1000 * L_THIGH * unit(p1)
    ankle = knee + 1000 * L_SHANK * unit(p2)
    zhat = np.array([0.0, 0.0, 1.0])[:, None]
    out = {}
    for name, centre in (("HIP", hip), ("KNEE", knee), ("ANK", ankle)):
        half = JOINT_HALF_WIDTH_MM[name]
        out[f"PH_{name}_MED"] = centre - half * zhat
        out[f"PH_{name}_LAT"] = centre + half * zhat
    hinge = knee + BAR_Z_MM * zhat
    thigh_dir, shank_dir = unit(p1 - delta / 2), unit(p2 + delta / 2)
    for name, dist in THIGH_BAR_MARKERS_M.items():
        out[name] = hinge - 1000 * dist * thigh_dir
    for name, dist in SHANK_BAR_MARKERS_M.items():
        out[name] = hinge + 1000 * dist * shank_dir
    anterior = np.stack([-thigh_dir[1], thigh_dir[0], np.zeros_like(theta)])
    fixed = (
        knee + SPRING_Z_MM * zhat
        - 1000 * SPRING_FIXED_FROM_HINGE_M * thigh_dir + 1000 * SPRING_ANTERIOR_M * anterior
    )  # fmt: skip
    out["EX_SPRING_A"] = fixed
    out["EX_SPRING_B"] = fixed + 1000 * spring_len_m * thigh_dir
    return np.stack([out[name] for name in MARKERS], axis=1)


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
    effects: Mapping[str, Mapping[str, float]],
    faults: Mapping[str, Mapping],
    seed: int,
    marker_noise_mm: float = 0.15,
    cell_noise_N: float = 0.5,
    occlusions_per_marker: float = 0.0,
    cell_shares: Sequence[float] = (0.30, 0.33, 0.37),
    substeps: int = 4,
    release_s: float = 0.1,
) -> Path:
    """Write one C3D per spring and manifest.csv into folder; return the manifest's path."""
    effects = _checked(effects, EFFECT_PARAMETERS, "effect")
    faults = _checked(faults, FAULT_PARAMETERS, "fault")
    if strides <= 2 * ramp_strides or ramp_strides < 0:
        raise ValueError("strides must exceed twice ramp_strides (≥ 0)")
    if not np.isclose(sum(cell_shares), 1.0) or len(cell_shares) != 3:
        raise ValueError("cell_shares must be three shares summing to 1")
    names = [f"k{k:.0f}" for k in springs_N_per_m]
    if len(set(names)) != len(names):
        raise ValueError(f"springs give duplicate trial names: {names}")
    folder = Path(folder)
    folder.mkdir(parents=True, exist_ok=True)
    rng = np.random.default_rng(seed)
    cycle = read_mean_cycle(cycle_csv)
    shifts = np.deg2rad(rng.normal(0.0, SHIFT_SD_DEG, (strides, cycle_extrema(cycle).size)))
    n = strides * round(STRIDE_S * FS_ANALOG)
    t = np.arange(n) / FS_ANALOG
    fine = knee_motion(
        cycle, shifts, ramp_strides, np.arange(n * substeps) / (FS_ANALOG * substeps)
    )
    motion = KneeMotion(*(v[::substeps] for v in fine))
    knee_friction = faults.get("phantom_knee_friction", {}).get("friction_Nm", 0.0)
    knee_damping = faults.get("phantom_knee_damping", {}).get("c_Nms_per_rad", 0.0)
    hinge = knee_friction * np.sign(motion.omega) + knee_damping * motion.omega
    shank = faults.get("shank_mass", {}).get("factor", 1.0)
    sync = np.zeros(n)
    sync[(np.arange(n) % round(STRIDE_S * FS_ANALOG)) < round(SYNC_S * FS_ANALOG)] = SYNC_V
    rows = []
    for order, (name, k) in enumerate(zip(names, springs_N_per_m, strict=True), start=1):
        exo = exoskeleton_response(fine.theta, FS_ANALOG * substeps, k, effects, faults, release_s)
        moment = exo.moment[::substeps]
        fy = ankle_vertical_force(motion, moment + hinge, shank)
        cells = np.asarray(cell_shares)[:, None] * fy[None, :]
        if "ankle_cell_gain" in faults:
            fault = faults["ankle_cell_gain"]
            cells[ANKLE_CELLS.index(fault["channel"])] *= fault["gain"]
        cells += rng.normal(0.0, cell_noise_N, cells.shape)
        if "ankle_cell_offset" in faults:
            fault = faults["ankle_cell_offset"]
            cells[ANKLE_CELLS.index(fault["channel"])] += fault["offset_N"]
        if "ankle_cell_drift" in faults:
            fault = faults["ankle_cell_drift"]
            cells[ANKLE_CELLS.index(fault["channel"])] += fault["rate_N_per_s"] * t
        spring = exo.tension[::substeps] + rng.normal(0.0, cell_noise_N, n)
        spring += faults.get("spring_cell_drift", {}).get("rate_N_per_s", 0.0) * t
        frames = slice(None, None, substeps * FS_ANALOG // FS_POINT)
        points = marker_positions(
            fine.theta[frames], exo.interface[frames], exo.spring_length[frames]
        )
        points += rng.normal(0.0, marker_noise_mm, points.shape)
        _occlude(points, occlusions_per_marker, rng)
        write_c3d(folder / f"{name}.c3d", points, np.vstack([cells, spring, sync]))
        rows.append((name, f"{name}.c3d", float(k), order, ramp_strides))
    manifest = folder / "manifest.csv"
    pd.DataFrame(rows, columns=list(MANIFEST_COLUMNS)).to_csv(manifest, index=False)
    return manifest
