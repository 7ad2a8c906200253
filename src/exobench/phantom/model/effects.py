"""Effect registry of the phantom rig: series predictions of the engaged window of each stride.

The baseline is seed 000's rigid theory (eqs. 2.1–2.2): from the engagement instant the knee
rotation u = θ_phantom − θ_phantom(engagement) passes unchanged to the spring side, M = k_θ·u.
Every model is driven by the measured phantom angle and predicts four observables of each
stride's window: knee moment (inverse dynamics, analog clock), exoskeleton-angle change and
spring-length change (markers) and spring force (LC_SPRING, analog clock).

The mechanical effects and terms add elements in series between limb and spring: the interface,
the frame and the spring side, each with its elastic law (linear or cubic; the spring side's
taut and slack branches), Kelvin–Voigt damping and Coulomb friction in parallel, as
docs/assumptions.md states them. One compiled solver steps that chain through each window
(:func:`chain_steps`), exactly for linear elements and a moment linear between samples. The
sensor effects transform the predicted recordings. The registry's entries are rows of the
assumption table (:mod:`exobench.phantom.model.assumptions`), which names them.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import replace

import numba
import numpy as np

from exobench.phantom.model import assumptions
from exobench.phantom.rig import Rig
from exobench.selection import Data, Effect, Parameter
from exobench.selection import assumptions as shared

NEWTON_ITERATIONS = 30
NEWTON_TOLERANCE_RAD = 1e-12
# parts of the chain's first step (engagement instant to first sample; numerical method)
FIRST_SUBSTEPS = 10
# steps per sample of a chain whose interface sticks and slips (numerical method)
STICK_SLIP_SUBSTEPS = 5
OBSERVABLES = {"moment": "Nm", "exo": "rad", "spring": "m", "force": "N", "swing": "Nm",
               "swing_force": "N"}  # fmt: skip
# the window of each knee-moment observable: the prefix of its arrays in the observations
MOMENT_WINDOWS = {"moment": "", "swing": "swing_"}
# the three ankle load cells' filtered forces in the observations
CELLS = tuple(f"ankle_cell_{i}_N" for i in (1, 2, 3))
# Every constant of the series chain at its neutral value: the registry's parameters and the
# terms' (keyed row.parameter, as docs/assumptions.md names them).
NEUTRAL_CHAIN = {
    "k_interface_Nm_per_rad": np.inf,
    "stiffening_per_rad2": 0.0,
    "c_interface_Nms_per_rad": 0.0,
    "interface.friction_Nm": 0.0,
    "interface.drift_per_s": 0.0,
    "k_frame_Nm_per_rad": np.inf,
    "frame.stiffening_per_rad2": 0.0,
    "frame.c_frame_Nms_per_rad": 0.0,
    "frame.drift_per_s": 0.0,
    "friction_Nm": 0.0,
    "spring.scale": 1.0,
    "spring.quadratic_per_m": 0.0,
    "spring.c_spring_Ns_per_m": 0.0,
    "spring.drift_per_s": 0.0,
    "pulley_radius.scale": 1.0,
    "chain_ratio.scale": 1.0,
    "tensioner.scale": 1.0,
    "interface.play_rad": 0.0,
    "play_rad": 0.0,
    "delay_s": 0.0,
}


def engagement_rotation(theta: np.ndarray, t: np.ndarray, delay_s):
    """Knee rotation since the clutch engaged (0 before) and the engaged mask, per sample, for
    an engagement ``delay_s`` after the programmed instant (one for all units, or one per unit);
    the angle at the engagement instant between samples by cubic (four-point Lagrange)
    interpolation, exact to O(h⁴) where the knee turns near its extremum (linear at the
    window's ends and outside it, where a cubic would extrapolate)."""
    delay = np.broadcast_to(np.asarray(delay_s, float), theta.shape[:1])
    engaged = t[None, :] >= delay[:, None]
    i = np.clip(np.searchsorted(t, delay) - 1, 0, t.size - 2)
    w = (delay - t[i]) / (t[i + 1] - t[i])
    weights = np.stack([-w * (w - 1) * (w - 2) / 6, (w + 1) * (w - 1) * (w - 2) / 2,
                        -(w + 1) * w * (w - 2) / 2, (w + 1) * w * (w - 1) / 6], axis=1)  # fmt: skip
    rows = np.arange(theta.shape[0])
    near = theta[rows[:, None], np.clip(i[:, None] + np.arange(-1, 3), 0, t.size - 1)]
    cubic = (i >= 1) & (i <= t.size - 3) & (w >= 0.0) & (w <= 1.0)
    at_engagement = np.where(cubic, np.sum(near * weights, axis=1),
                             (1.0 - w) * theta[rows, i] + w * theta[rows, i + 1])  # fmt: skip
    return np.where(engaged, theta - at_engagement[:, None], 0.0), engaged


def unit_time(data: Data) -> np.ndarray:
    """Each unit's time since its trial's first sample at the programmed engagement (s)."""
    return data.arrays["time_s"][:, data.constants["zero"]]


def drifting(value, rate_per_s: float, data: Data) -> np.ndarray:
    """A stiffness that changes over the trial, k·(1 + ρ·t), at each unit's time (units,); never
    below a tenth of k (a stiffness does not drift through zero)."""
    factor = np.maximum(1.0 + rate_per_s * unit_time(data), 0.1)
    return np.broadcast_to(value, (data.units,)) * factor


def spring_side(c: Mapping, data: Data) -> tuple[Rig, np.ndarray]:
    """The rig as a chain describes it (pulley radius, chain ratio and tensioner scaled) and
    every unit's spring rate (the manifest's, scaled, drifting over the trial), (units, 1)."""
    rig = data.constants["rig"]
    scaled = replace(
        rig,
        pulley_radius_m=rig.pulley_radius_m * c["pulley_radius.scale"],
        chain_ratio=rig.chain_ratio * c["chain_ratio.scale"],
        tensioner_stiffness_Nm_per_rad=rig.tensioner_stiffness_Nm_per_rad * c["tensioner.scale"],
    )
    rate = data.arrays["k_spring_N_per_m"] * c["spring.scale"]
    return scaled, drifting(rate, c["spring.drift_per_s"], data)[:, None]


def branches(c: Mapping, data: Data) -> tuple[Rig, np.ndarray, np.ndarray, np.ndarray, float,
                                               np.ndarray]:  # fmt: skip
    """The spring side's elastic moment per unit: K·s + kq·s² while taut (K = k_θ, seed 000
    eq. 2.2; kq = k·a·(r·T/t)³ for a spring F = F₀ + k·x·(1 + a·x), x = r·(T/t)·s), the
    tensioner alone, (T/t)²·k_t, below the rotation where the spring's tension reaches 0 (the
    kink); returns the rig and spring rate of :func:`spring_side`, then K, kq, that slack
    stiffness and the kink, (units, 1) but the slack's."""
    rig, k_spring = spring_side(c, data)
    travel = rig.spring_travel_m_per_rad
    k_theta = rig.joint_stiffness(k_spring)
    quadratic = k_spring * c["spring.quadratic_per_m"] * travel**3
    kink = -data.arrays["pretension_N"][:, None] / (k_spring * travel)
    slack = rig.chain_ratio**2 * rig.tensioner_stiffness_Nm_per_rad
    return rig, k_spring, k_theta, quadratic, slack, kink


@numba.njit(cache=True)
def _element(d0, m0, kt, b, c, h):
    """End deflection base + slope·m of an element whose elastic law is linearised as
    k_t·d + b, damped by c, when the moment driving it rises linearly from m0 (at deflection
    d0) to m over a step of h (exact Kelvin–Voigt: z = d + b/k_t obeys c·ż + k_t·z = m;
    a = e^(−h/T), q = 1 − T(1 − a)/h, T = c/k_t); a rigid element: 0, 0."""
    if not np.isfinite(kt):
        return 0.0, 0.0
    a, q = 0.0, 1.0
    if c > 0.0:
        T = c / kt
        a = np.exp(-h / T)
        q = 1.0 - T * (1.0 - a) / h
    return a * (d0 + b / kt) + (1.0 - a - q) * m0 / kt - b / kt, q / kt


@numba.njit(cache=True)
def _deflection(M, d0, base, slope, tau):
    """An element's end deflection at the moment M and its slope, with a friction moment tau in
    parallel: stuck at d0 while the sliding solution (driven by M ∓ tau) would not move it."""
    if slope == 0.0:
        return 0.0, 0.0
    if tau <= 0.0:
        return base + slope * M, slope
    hi = (d0 - base) / slope + tau
    if M > hi:
        return base + slope * (M - tau), slope
    if M < hi - 2.0 * tau:
        return base + slope * (M + tau), slope
    return d0, 0.0


@numba.njit(cache=True)
def _total(M, d0i, bi, si, ti, bf, sf, d0s, bs, ss, ts):
    """The sum of the three elements' end deflections at the moment M, and its slope."""
    x, dx = _deflection(M, d0i, bi, si, ti)
    y, dy = _deflection(M, 0.0, bf, sf, 0.0)
    z, dz = _deflection(M, d0s, bs, ss, ts)
    return x + y + z, dx + dy + dz


@numba.njit(cache=True)
def _moment(r, d0i, bi, si, ti, bf, sf, d0s, bs, ss, ts):
    """The moment at which the elements' end deflections add up to the drive r, exactly: the
    sum is piecewise affine and non-decreasing in M, with breakpoints where a friction element
    starts or stops sliding (bracketed between them, then solved on its piece)."""
    points = (
        (d0i - bi) / si - ti if ti > 0.0 and si > 0.0 else np.nan,
        (d0i - bi) / si + ti if ti > 0.0 and si > 0.0 else np.nan,
        (d0s - bs) / ss - ts if ts > 0.0 and ss > 0.0 else np.nan,
        (d0s - bs) / ss + ts if ts > 0.0 and ss > 0.0 else np.nan,
    )
    below, above = -np.inf, np.inf
    for point in points:
        if np.isnan(point) or point <= below or point >= above:
            continue
        value, _ = _total(point, d0i, bi, si, ti, bf, sf, d0s, bs, ss, ts)
        if value < r:
            below = point
        else:
            above = point
    if np.isfinite(below) and np.isfinite(above):
        inside = 0.5 * (below + above)
    elif np.isfinite(above):
        inside = above - 1.0
    elif np.isfinite(below):
        inside = below + 1.0
    else:
        inside = 0.0
    value, derivative = _total(inside, d0i, bi, si, ti, bf, sf, d0s, bs, ss, ts)
    if derivative <= 0.0:
        return above if np.isfinite(above) else below
    return inside + (r - value) / derivative


@numba.njit(cache=True)
def _cubic(k, beta, d):
    """Tangent and offset of k·(d + β·d³) linearised at d (infinite k: rigid)."""
    if not np.isfinite(k):
        return np.inf, 0.0
    tangent = k * (1.0 + 3.0 * beta * d * d)
    return tangent, k * (d + beta * d * d * d) - tangent * d


@numba.njit(cache=True)
def _side(K, kq, kink, k_slack, s):
    """Tangent and offset of the spring side's elastic moment linearised at s, K·s + kq·s²
    while taut, k_slack·s + (K − k_slack)·kink below the kink; and whether it is taut."""
    if s >= kink:
        tangent = K + 2.0 * kq * s
        return tangent, -kq * s * s, True
    return k_slack, (K - k_slack) * kink, False


@numba.njit(cache=True)
def _driving(M, d0, base, slope, tau, kt0, b0):
    """The moment driving an element's elastic and viscous part: M ∓ tau while it slides, its
    elastic moment at d0 while it sticks (no rate; the friction carries the rest)."""
    if tau <= 0.0 or slope == 0.0:
        return M
    hi = (d0 - base) / slope + tau
    if M > hi:
        return M - tau
    if M < hi - 2.0 * tau:
        return M + tau
    return kt0 * d0 + b0


@numba.njit(cache=True)
def chain_steps(rest, start, k_i, k_f, K, kq, kink, scalars, dt, first_dt, substeps):
    """The series chain interface → frame → spring side of every unit over its engaged
    samples, from its first engaged sample ``start`` on (compiled): moment, interface, frame
    and spring-side deflections and the spring side's driving moment per sample. Per step,
    Newton on the elements' elastic laws (linearised at the guessed end deflections, the
    linear chain then solved exactly, to NEWTON_TOLERANCE_RAD); the first step runs from the
    engagement instant (drive 0) to the first engaged sample, ``first_dt`` later, in
    FIRST_SUBSTEPS parts, where the moment rises from nothing."""
    beta_i, beta_f, c_i, c_f, c_s, k_slack, tau_i, tau_s = scalars
    units, samples = rest.shape
    out = np.zeros((5, units, samples))
    linear = beta_i == 0.0 and beta_f == 0.0
    for j in range(units):
        # an interface with friction left the last stride stuck where unloading stopped it,
        # k·δ = τ (the friction holding the rest): it starts the stride there
        di = tau_i / k_i[j] if np.isfinite(k_i[j]) else 0.0
        df = ds = 0.0  # deflections: interface, frame, spring side
        mi, mf, ms = k_i[j] * di if di else 0.0, 0.0, 0.0  # moments driving elastic + viscous
        out[1, j, :] = di
        for n in range(start[j], samples):
            i = n - start[j]
            parts, h = (substeps, dt / substeps) if i > 0 else (
                FIRST_SUBSTEPS, first_dt[j] / FIRST_SUBSTEPS)  # fmt: skip
            if i == 0 and first_dt[j] <= 0.0:
                parts = 0  # engaged on the sample itself: nothing is loaded yet
            M = 0.0
            before = rest[j, n - 1] if i > 0 else 0.0
            for part in range(parts):
                r = before + (rest[j, n] - before) * (part + 1) / parts
                gi, gf, gs = di, df, ds
                bi = si = bf = sf = bs = ss = 0.0
                for _ in range(NEWTON_ITERATIONS):
                    ki, oi = _cubic(k_i[j], beta_i, gi)
                    kf, of = _cubic(k_f[j], beta_f, gf)
                    ks, os, taut = _side(K[j], kq[j], kink[j], k_slack, gs)
                    bi, si = _element(di, mi, ki, oi, c_i, h)
                    bf, sf = _element(df, mf, kf, of, c_f, h)
                    bs, ss = _element(ds, ms, ks, os, c_s if taut else 0.0, h)
                    M = _moment(r, di, bi, si, tau_i, bf, sf, ds, bs, ss, tau_s)
                    ni, _ = _deflection(M, di, bi, si, tau_i)
                    nf, _ = _deflection(M, 0.0, bf, sf, 0.0)
                    ns, _ = _deflection(M, ds, bs, ss, tau_s)
                    change = max(abs(ni - gi), abs(nf - gf), abs(ns - gs))
                    still_taut = ns >= kink[j]
                    gi, gf, gs = ni, nf, ns
                    if change < NEWTON_TOLERANCE_RAD or (
                        linear and kq[j] == 0.0 and still_taut == taut
                    ):
                        break
                k0, b0 = _cubic(k_i[j], beta_i, di)
                mi = _driving(M, di, bi, si, tau_i, k0, b0)
                mf = M
                k0, b0, _ = _side(K[j], kq[j], kink[j], k_slack, ds)
                ms = _driving(M, ds, bs, ss, tau_s, k0, b0)
                di, df, ds = gi, gf, gs
            out[0, j, n] = M
            out[1, j, n] = di
            out[2, j, n] = df
            out[3, j, n] = ds
            out[4, j, n] = ms
    return out


def dead_band(drive: np.ndarray, below: float, above: float) -> np.ndarray:
    """What passes a slack element of ``below`` + ``above`` about its unloaded position: the
    drive less ``above`` beyond it, plus ``below`` short of it, 0 between (a dead zone)."""
    return np.maximum(drive - above, np.minimum(drive + below, 0.0))


def chain_solution(
    u, engaged, data: Data, c: Mapping, sides: tuple | None = None
) -> tuple[np.ndarray, ...]:
    """Moment, interface, frame and spring-side deflections and the spring side's driving
    moment (elastic and viscous: the moment less its friction) of the chain a state describes,
    every unit, every sample (0 before the engagement, but the interface's, which holds where
    it starts), each unit engaged the chain's ``delay_s`` after the programmed instant (one for
    all units, or one each). The drive is the knee rotation less two slacks in series, each a
    dead zone (:func:`dead_band`): the transmission's play p (the spring side turns only after
    the knee has turned p; the bars turn with the phantom meanwhile) and the interface's play
    p_i (the bars stand while the phantom turns ±p_i/2 about them from where the engagement
    found them, which counts in the interface's deflection); ``sides``: the chain's
    :func:`branches`, when the caller has them."""
    rig, _, k_theta, quadratic, k_slack, kink = sides or branches(c, data)
    per_unit = [np.ascontiguousarray(np.broadcast_to(x, kink.shape)[:, 0], dtype=float)
                for x in (k_theta, quadratic, kink)]  # fmt: skip
    stiffness = [
        np.ascontiguousarray(drifting(c[k], c[drift], data), dtype=float)
        for k, drift in (("k_interface_Nm_per_rad", "interface.drift_per_s"),
                         ("k_frame_Nm_per_rad", "frame.drift_per_s"))
    ]  # fmt: skip
    scalars = np.array([
        c["stiffening_per_rad2"], c["frame.stiffening_per_rad2"], c["c_interface_Nms_per_rad"],
        c["frame.c_frame_Nms_per_rad"],
        c["spring.c_spring_Ns_per_m"] * rig.spring_travel_m_per_rad**2,
        k_slack, c["interface.friction_Nm"], c["friction_Nm"],
    ], dtype=float)  # fmt: skip
    passed = dead_band(u, 0.0, c["play_rad"])
    half = 0.5 * c["interface.play_rad"]
    rest = np.ascontiguousarray(dead_band(passed, half, half), dtype=float)
    t = data.constants["t_s"]
    dt = float(data.constants["dt_s"])
    delay = np.broadcast_to(np.asarray(c["delay_s"], float), u.shape[:1])
    start = np.where(engaged.any(axis=1), np.argmax(engaged, axis=1), t.size)
    first = np.minimum(t[np.minimum(start, t.size - 1)] - delay, dt)
    # an interface that sticks and slips changes state within a step: finer steps there
    substeps = STICK_SLIP_SUBSTEPS if c["interface.friction_Nm"] > 0 else 1
    out = chain_steps(rest, start, *stiffness, *per_unit, scalars, dt,
                      np.ascontiguousarray(first, dtype=float), substeps)  # fmt: skip
    moment, delta, frame, side, driving = out
    delta = delta + np.where(engaged, passed - rest, 0.0)
    return (*(np.where(engaged, x, 0.0) for x in (moment,)), delta,
            *(np.where(engaged, x, 0.0) for x in (frame, side, driving)))  # fmt: skip


def solve(state: dict, data: Data) -> dict:
    """Moment and deflections of the series chain for the state's chain, and its recordings:
    the exoskeleton angle θ − δ, the spring's length change r·(T/t)·max(s, kink) and its
    tension F₀ + k·x·(1 + a·x) + c·ẋ (the viscous part while taut), never below 0."""
    c = state["chain"]
    theta = state["theta"]
    u, engaged = engagement_rotation(theta, data.constants["t_s"], c["delay_s"])
    sides = branches(c, data)
    moment, delta, _, side, driving = chain_solution(u, engaged, data, c, sides)
    rig, k_spring, k_theta, quadratic, _, kink = sides
    travel = rig.spring_travel_m_per_rad
    stretch = travel * side
    viscous = np.where(side >= kink, driving - k_theta * side - quadratic * side**2, 0.0)
    return {
        **state,
        "moment": moment,
        "exo": theta - delta,
        "spring": travel * np.maximum(side, kink),
        "force": np.maximum(
            data.arrays["pretension_N"][:, None]
            + k_spring * stretch * (1.0 + c["spring.quadratic_per_m"] * stretch)
            + viscous / travel,
            0.0,
        ),
    }


def mechanical(**defaults):
    """Transformation of a mechanical effect: its parameters into the chain (solved lazily)."""

    def transform(state, values, data):
        chain_values = {k: values[k] for k in defaults}
        return {**state, "chain": {**state["chain"], **chain_values}, "solved": False}

    return transform


def solved(state: dict, data: Data) -> dict:
    """The state with its chain solved (once, however many effects changed it)."""
    return state if state.get("solved") else {**solve(state, data), "solved": True}


def shifted(values: np.ndarray, delay_s, data: Data) -> np.ndarray:
    """A recorded signal whose sample stamped t holds the value at t − delay (linear interp;
    one delay for every unit, or one per unit)."""
    size = values.shape[1]
    delay = np.asarray(delay_s, float).reshape(-1, 1)
    position = np.clip(np.arange(size)[None, :] - delay / data.constants["dt_s"], 0.0, size - 1.0)
    i = np.minimum(position.astype(int), size - 2)
    w = position - i
    rows = np.arange(values.shape[0])[:, None]
    return values[rows, i] * (1.0 - w) + values[rows, i + 1] * w


def with_recorded(state: dict, extra: Mapping[str, np.ndarray]) -> dict:
    """The state with terms added to its observables as recorded (after the chain's filter:
    terms built from recorded, already filtered channels)."""
    total = dict(state.get("recorded_extra", {}))
    for name, value in extra.items():
        total[name] = total[name] + value if name in total else value
    return {**state, "recorded_extra": total}


def ankle_lag(delay_s, data: Data, prefix: str, force: str = "ankle_force_N"):
    """The inverse-dynamics moment's error when a vertical ankle force (the cells' sum, or one
    cell's) lags the marker geometry by delay_s: (∂M/∂F_y)·(F_rec(t) − F_rec(t + d)), on a
    window's own arrays."""
    ankle = data.arrays[f"{prefix}{force}"]
    arm = data.arrays[f"{prefix}moment_per_ankle_force_m"]
    return arm * (ankle - shifted(ankle, -delay_s, data))


def clock(state, values, data):
    """Analog channels lag the marker clock by analog_delay_s (:func:`lagged`)."""
    return lagged(state, values["analog_delay_s"], data)


def lagged(state: dict, delay, data: Data) -> dict:
    """Analog channels lag the marker clock by d more (one lag, or one per unit; lags add up).
    SYNC is analog too, so the strides it marks start d late: on the window's (marker) time
    line the clutch engages d early. LC_SPRING's sample t holds the tension at t − D (D the
    whole lag): the chain driven by θ(t − D) with the engagement on time. The inverse-dynamics
    moment combines the late vertical ankle force with on-time marker geometry
    (:func:`ankle_lag`), in the engaged window and in the swing."""
    before = state.get("analog_lag_s", 0.0)
    lag = before + delay
    chain = state["chain"]
    early = solved({**state, "chain": {**chain, "delay_s": chain["delay_s"] - delay},
                    "solved": False}, data)  # fmt: skip
    late = solve({**state, "theta": shifted(state["theta"], lag, data),
                  "chain": {**chain, "delay_s": chain["delay_s"] + before}}, data)  # fmt: skip
    more = {obs: ankle_lag(lag, data, w) - ankle_lag(before, data, w)
            for obs, w in MOMENT_WINDOWS.items()}  # fmt: skip
    return with_recorded({**early, "force": late["force"], "analog_lag_s": lag}, more)


def knee_marker_angle(theta_true: np.ndarray, offset_m: float, thigh_m: float, shank_m: float):
    """Knee flexion seen with the knee markers offset_m anterior of the joint (hip fixed, ankle
    below it): angle between hip→knee′ and knee′→ankle."""
    hip_to_ankle = np.sqrt(thigh_m**2 + shank_m**2 + 2 * thigh_m * shank_m * np.cos(theta_true))
    # thigh angle from the downward vertical (knee anterior), law of cosines at the hip
    cos_hip = (thigh_m**2 + hip_to_ankle**2 - shank_m**2) / (2 * thigh_m * hip_to_ankle)
    phi = np.arccos(np.clip(cos_hip, -1.0, 1.0))
    knee = np.stack([thigh_m * np.sin(phi), -thigh_m * np.cos(phi)])
    normal = np.stack([np.cos(phi), np.sin(phi)])  # anterior normal of the thigh
    seen = knee + offset_m * normal
    ankle = np.stack([np.zeros_like(phi), -hip_to_ankle])
    a, b = seen, ankle - seen
    cross = a[0] * b[1] - a[1] * b[0]
    return np.arctan2(-cross, a[0] * b[0] + a[1] * b[1])


def knee_marker(state, values, data):
    """Knee markers placed anterior of the joint: the measured phantom angle is biased (the true
    angle recovered by inverting the geometric bias, then the chain re-solved), and the inverse
    dynamics takes its knee centre o off the axis, M_rec = M + o·∂M/∂o, in every window."""
    grid = np.linspace(-0.2, 1.6, 721)
    thigh, shank = data.constants["thigh_m"], data.constants["shank_m"]
    offset = values["offset_mm"] / 1000.0
    seen = knee_marker_angle(grid, offset, thigh, shank)
    true = np.interp(data.arrays["phantom_rad"], seen, grid)
    shifted_centre = {obs: offset * data.arrays[f"{w}moment_per_knee_shift_Nm_per_m"]
                      for obs, w in MOMENT_WINDOWS.items()}  # fmt: skip
    return with_recorded({**state, "theta": true, "solved": False}, shifted_centre)


def load_cell_gain(state, values, data):
    """LC_SPRING reads gain × the true tension (engaged and disengaged)."""
    state = solved(state, data)
    gain = values["gain"]
    return {**state, "force": state["force"] * gain, "swing_force": state["swing_force"] * gain}


def load_cell_offset(state, values, data):
    """LC_SPRING reads the true tension plus a constant offset (engaged and disengaged)."""
    state = solved(state, data)
    offset = values["offset_N"]
    return {**state, "force": state["force"] + offset,
            "swing_force": state["swing_force"] + offset}  # fmt: skip


def registry_effect(name: str, parameter: Parameter, transform, **options) -> Effect:
    """A registry entry: the table's relaxation that is this effect (its description, the
    observables its row touches) with the engine's parameter and transformation."""
    return shared.registry_effect(assumptions.TABLE, name, (parameter,), transform, **options)


INF = np.inf
# Each entry: the effect, its parameter (name, unit, fit bounds, meaning, start value, the value
# at which the effect vanishes, the documented detectable range, and the size below which it is
# too small to name: a tenth of a degree, a millisecond or two, a percent of a gain, a newton)
# and its forward transformation; its name and observables come from the assumption table.
REGISTRY: dict[str, Effect] = {
    "interface_compliance": registry_effect(
        "interface_compliance",
        Parameter("k_interface_Nm_per_rad", "N·m/rad", 2.0, 1e5,
                  "knee-equivalent interface stiffness", start=100.0, neutral=INF,
                  detectable=(40.0, 150.0), negligible=3000.0),
        mechanical(k_interface_Nm_per_rad=INF),
    ),
    "interface_stiffening": registry_effect(
        "interface_stiffening",
        Parameter("stiffening_per_rad2", "1/rad²", 1.0, 5e3, "β in k_i·(δ + β·δ³)",
                  start=50.0, detectable=(100.0, 1000.0), negligible=10.0),
        mechanical(stiffening_per_rad2=0.0),
        requires=("interface_compliance",),
    ),
    "interface_damping": registry_effect(
        "interface_damping",
        Parameter("c_interface_Nms_per_rad", "N·m·s/rad", 1e-3, 50.0,
                  "Kelvin–Voigt damping of the interface", start=0.5,
                  detectable=(0.8, 2.5), negligible=0.1),
        mechanical(c_interface_Nms_per_rad=0.0),
        requires=("interface_compliance",),
    ),
    "frame_compliance": registry_effect(
        "frame_compliance",
        Parameter("k_frame_Nm_per_rad", "N·m/rad", 10.0, 1e6, "knee-equivalent frame stiffness",
                  start=1000.0, neutral=INF, detectable=(300.0, 1500.0), negligible=1e4),
        mechanical(k_frame_Nm_per_rad=INF),
    ),
    "frame_friction": registry_effect(
        "frame_friction",
        Parameter("friction_Nm", "N·m", 1e-3, 10.0, "knee-equivalent Coulomb friction moment",
                  start=0.2, detectable=(0.3, 1.5), negligible=0.05),
        mechanical(friction_Nm=0.0),
    ),
    "transmission_play": registry_effect(
        "transmission_play",
        Parameter("play_rad", "rad", 1e-4, 0.3, "knee rotation before the spring is loaded",
                  start=0.01, detectable=(0.01, 0.05), negligible=0.002),
        mechanical(play_rad=0.0),
    ),
    "clutch_timing": registry_effect(
        "clutch_timing",
        Parameter("delay_s", "s", 1e-3, 0.3, "engagement delay after the programmed instant",
                  start=0.02, detectable=(0.02, 0.08), negligible=0.005),
        mechanical(delay_s=0.0),
    ),
    "knee_marker_offset": registry_effect(
        "knee_marker_offset",
        Parameter("offset_mm", "mm", -60.0, 60.0, "anterior offset of the knee markers",
                  log=False, start=0.0, detectable=(10.0, 30.0), negligible=3.0),
        knee_marker,
    ),
    "clock_offset": registry_effect(
        "clock_offset",
        Parameter("analog_delay_s", "s", -0.1, 0.1, "analog lag behind the marker clock",
                  log=False, start=0.0, detectable=(0.01, 0.04), negligible=0.002),
        clock,
    ),
    "load_cell_gain": registry_effect(
        "load_cell_gain",
        Parameter("gain", "1", 0.5, 2.0, "recorded over true spring tension", start=1.0,
                  neutral=1.0, detectable=(1.05, 1.15), negligible=1.01),
        load_cell_gain,
    ),
    "load_cell_offset": registry_effect(
        "load_cell_offset",
        Parameter("offset_N", "N", -50.0, 50.0, "recorded minus true spring tension",
                  log=False, start=0.0, detectable=(3.0, 15.0), negligible=1.0),
        load_cell_offset,
    ),
}  # fmt: skip


def baseline(data: Data) -> dict:
    """Rigid theory: every compliance rigid, no loss, no play, engagement on the programme."""
    return {
        "chain": dict(NEUTRAL_CHAIN),
        "theta": data.arrays["phantom_rad"],
        "swing": np.zeros_like(data.arrays["swing_phantom_rad"]),
        # with the clutch open the spring holds its pretension
        "swing_force": data.arrays["pretension_N"][:, None]
        + np.zeros_like(data.arrays["swing_phantom_rad"]),
        "solved": False,
    }
