"""The exoskeleton's series chain (interface → bars → frame → play → spring side) solved sample
by sample, implicit Euler in a compiled loop."""

import math
from collections.abc import Mapping
from typing import NamedTuple

import numba
import numpy as np

from .leg import smoothstep
from .rig import (
    CHAIN_RATIO,
    CLUTCH_RELEASE_FRACTION,
    F0_N,
    K_TENSIONER,
    PULLEY_R,
    SPRING_LEN_M,
    STRIDE_S,
    check_duration,
    checked_violations,
    value_of,
)


class ExoResponse(NamedTuple):
    """Per sample: M (N·m), δ (straps' play in it), ε, s (rad), tension (N), spring length (m)."""

    moment: np.ndarray
    interface: np.ndarray
    frame: np.ndarray
    spring_side: np.ndarray
    tension: np.ndarray
    spring_length: np.ndarray


# Layout of the parameter vector of the numba chain solver: two series elements (interface at
# E_INTERFACE, frame at E_FRAME: present, k, β, c, τ, ρ), the spring side, the transmission's
# play, the step, the straps' play.
E_INTERFACE, E_FRAME = 0, 6
(E_ON, E_K, E_BETA, E_C, E_TAU, E_RHO) = range(6)
(S_K, S_A, S_C, S_RHO, S_F0, S_R, S_N, S_KT, S_TAU, P_HAS_PLAY, P_PLAY, P_H, I_HAS_PLAY, I_PLAY,
 P_SIZE) = range(12, 27)  # fmt: skip
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
def _strap_slack(u: float, st: np.ndarray, t: float, p: np.ndarray) -> tuple[float, bool]:
    """Straps' dead band b ∈ [−p/2, p/2]: b_z = u − (s + δ + ε at M = 0); loaded at an end."""
    half = 0.5 * p[I_PLAY]
    d, _ = _element(0.0, st[0], t, p, E_INTERFACE)
    e, _ = _element(0.0, st[1], t, p, E_FRAME)
    b_z = u - _free_side(st, t, p) - d - e  # the slack that leaves the chain unloaded
    if b_z > half:
        return half, True
    if p[P_HAS_PLAY] > 0.0:  # a chain that only pulls stays unloaded for every b ≥ b_z
        return min(max(st[3], b_z, -half), half), False
    if b_z < -half:
        return -half, True
    return b_z, False


@numba.njit(cache=True)
def _engaged(u_rel: float, st: np.ndarray, m_prev: float, t: float, p: np.ndarray):
    """Engaged: taut chain after the plays (M ≥ 0 with play) or slack (M = 0); s, M, δ, ε, b."""
    u = u_rel - (p[P_PLAY] if p[P_HAS_PLAY] > 0.0 else 0.0)
    b = st[3]
    if p[I_HAS_PLAY] > 0.0:
        b, loaded = _strap_slack(u, st, t, p)
        if not loaded:  # the bars turn freely in the straps: no moment
            d, _ = _element(0.0, st[0], t, p, E_INTERFACE)
            e, _ = _element(0.0, st[1], t, p, E_FRAME)
            return _free_side(st, t, p), 0.0, d, e, b
        u -= b
    s, m = _taut(u, st, m_prev, t, p)
    if p[P_HAS_PLAY] > 0.0 and m < 0.0:
        m = 0.0
        s = _free_side(st, t, p)
    d, _ = _element(m, st[0], t, p, E_INTERFACE)
    e, _ = _element(m, st[1], t, p, E_FRAME)
    if p[P_HAS_PLAY] > 0.0 and m == 0.0:
        s = max(s, u - d - e)
    return s, m, d, e, b


@numba.njit(cache=True)
def _chain(theta: np.ndarray, phase: np.ndarray, release: np.ndarray, p: np.ndarray):
    """March free (M = 0, s = 0), engaged (implicit series chain) and release (×(1 − w)) samples.

    The straps' play b (the bars' slack in the straps) stays put while nothing loads it.
    """
    n = theta.size
    moment, delta, frame, side = np.zeros(n), np.zeros(n), np.zeros(n), np.zeros(n)
    tension, length = np.zeros(n), np.zeros(n)
    st = np.zeros(4)  # previous δ (elastic), ε, s, b
    m, s, d, e, b, th_e, u_e, m_r, s_r = 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0
    prev = 0
    for j in range(n):
        t = j * p[P_H]
        st[0], st[1], st[2], st[3] = d, e, s, b
        ph = phase[j]
        if ph == 1 and prev != 1:  # the clutch locks: the spring side starts at its pretension
            m, s = 0.0, 0.0
        elif ph == 1:
            s, m, d, e, b = _engaged(theta[j] - th_e + u_e, st, m, t, p)
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
            th_e, u_e = theta[j], d + e + b
        _, _, f = _spring(s, st[2], t, p)
        k = p[S_K] * (1.0 + p[S_RHO] * t)
        x = p[S_R] * p[S_N] * s
        moment[j], delta[j], frame[j], side[j], tension[j] = m, d + b, e, s, f
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
            p[b + E_K] = value_of(v, k_key, math.inf)
            p[b + E_BETA] = value_of(v, f"{name}.stiffening", 0.0)
            p[b + E_C] = value_of(v, c_key, 0.0)
            p[b + E_TAU] = value_of(v, f"{name}.coulomb", 0.0)
            p[b + E_RHO] = value_of(v, f"{name}.drifting", 0.0)
    p[S_K] = spring_N_per_m * value_of(v, "spring.value", 1.0)
    p[S_A] = value_of(v, "spring.stiffening", 0.0)
    p[S_C] = value_of(v, "spring.viscous", 0.0)
    p[S_RHO] = value_of(v, "spring.drifting", 0.0)
    p[S_F0] = F0_N
    p[S_R] = PULLEY_R * value_of(v, "pulley_radius.value", 1.0)
    p[S_N] = CHAIN_RATIO * value_of(v, "chain_ratio.value", 1.0)
    p[S_KT] = K_TENSIONER * value_of(v, "tensioner.value", 1.0)
    p[S_TAU] = value_of(v, "spring.coulomb", 0.0)
    if "transmission.play" in v:
        p[P_HAS_PLAY], p[P_PLAY] = 1.0, value_of(v, "transmission.play", 0.0)
    if "interface.play" in v:
        p[I_HAS_PLAY], p[I_PLAY] = 1.0, value_of(v, "interface.play", 0.0)
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
    delay = value_of(violations, "clutch.delay", 0.0)
    phase, w = clutch_schedule(theta.size, fs_hz, delay, release_s)
    moment, delta, frame, side, tension, stretch = _chain(
        np.ascontiguousarray(theta, float), phase, w, p
    )
    return ExoResponse(moment, delta, frame, side, tension, SPRING_LEN_M + stretch)
