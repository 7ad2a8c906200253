"""Effect registry of the phantom rig: series predictions of the engaged window of each stride.

The baseline is seed 000's rigid theory (eqs. 2.1–2.2): from the engagement instant the knee
rotation u = θ_phantom − θ_phantom(engagement) passes unchanged to the spring side, M = k_θ·u.
Every model is driven by the measured phantom angle and predicts four observables of each
stride's window: knee moment (inverse dynamics, analog clock), exoskeleton-angle change and
spring-length change (markers) and spring force (LC_SPRING, analog clock).

The mechanical effects add elements in series between limb and spring. A chain of elastic
elements is solved in closed form (a dead zone for the play; a play operator for Coulomb
friction on the spring side, exact for linear compliances in series); an interface with damping
or strain-stiffening has a memory, so that chain is stepped through time (vectorised over
strides), exactly for a moment linear between samples. The sensor
effects transform the predicted recordings. Each entry is self-contained: adding an effect is
one entry here and one hidden-effect test case.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import replace

import numba
import numpy as np

from exobench.phantom.rig import Rig
from exobench.selection import Data, Effect, Parameter

SECANT_ITERATIONS = 50
SECANT_TOLERANCE_RAD = 1e-12
SPRING_ITERATIONS = 30
SPRING_TOLERANCE_RAD = 1e-9
# parts of the damped chain's first step (engagement instant to first sample; numerical method)
FIRST_SUBSTEPS = 10
OBSERVABLES = {"moment": "Nm", "exo": "rad", "spring": "m", "force": "N", "swing": "Nm"}
# the window of each knee-moment observable: the prefix of its arrays in the observations
MOMENT_WINDOWS = {"moment": "", "swing": "swing_"}
# the three ankle load cells' filtered forces in the observations
CELLS = tuple(f"ankle_cell_{i}_N" for i in (1, 2, 3))


def play_operator(x: np.ndarray, half_width: np.ndarray) -> np.ndarray:
    """Backlash (play) operator along axis 1 from y = 0: y_n = clip(y_{n−1}, x_n − r, x_n + r).

    Composition of clamps is a clamp, so the recursion is an associative scan, done here by
    doubling (log2(samples) vectorised steps).
    """
    low, high = x - half_width, x + half_width
    n, shift = x.shape[1], 1
    while shift < n:
        lo_prev, hi_prev = low[:, :-shift], high[:, :-shift]
        lo_cur, hi_cur = low[:, shift:], high[:, shift:]
        low = np.concatenate([low[:, :shift], np.clip(lo_prev, lo_cur, hi_cur)], axis=1)
        high = np.concatenate([high[:, :shift], np.clip(hi_prev, lo_cur, hi_cur)], axis=1)
        shift *= 2
    return np.clip(0.0, low, high)


def chain(values: Mapping[str, float], state: dict) -> dict:
    """Mechanical parameters of a candidate, merged into the state's chain description."""
    return {**state["chain"], **values}


def engagement_rotation(theta: np.ndarray, t: np.ndarray, delay_s: float):
    """Knee rotation since the clutch engaged (0 before) and the engaged mask, per sample; the
    angle at the engagement instant between samples by cubic (four-point Lagrange)
    interpolation, exact to O(h⁴) where the knee turns near its extremum (linear at the
    window's ends and outside it, where a cubic would extrapolate)."""
    engaged = np.broadcast_to(t >= delay_s, theta.shape)
    i = int(np.clip(np.searchsorted(t, delay_s) - 1, 0, t.size - 2))
    w = (delay_s - t[i]) / (t[i + 1] - t[i])
    if 1 <= i <= t.size - 3 and 0.0 <= w <= 1.0:
        weights = np.array([-w * (w - 1) * (w - 2) / 6, (w + 1) * (w - 1) * (w - 2) / 2,
                            -(w + 1) * w * (w - 2) / 2, (w + 1) * w * (w - 1) / 6])  # fmt: skip
        at_engagement = theta[:, i - 1 : i + 3] @ weights
    else:
        at_engagement = (1.0 - w) * theta[:, i] + w * theta[:, i + 1]
    return np.where(engaged, theta - at_engagement[:, None], 0.0), engaged


def spring_side(c: Mapping, data: Data) -> tuple[Rig, np.ndarray]:
    """The rig as a chain describes it (the nominal rig with its spring-pulley radius and
    tensioner scaled by the chain's ``arm_scale`` and ``tensioner_scale``) and every unit's
    spring rate (the manifest's times ``spring_scale``), (units, 1)."""
    rig = data.constants["rig"]
    scaled = replace(
        rig,
        pulley_radius_m=rig.pulley_radius_m * c["arm_scale"],
        tensioner_stiffness_Nm_per_rad=rig.tensioner_stiffness_Nm_per_rad * c["tensioner_scale"],
    )
    return scaled, data.arrays["k_spring_N_per_m"][:, None] * c["spring_scale"]


def branches(c: Mapping, data: Data, side=None) -> tuple[tuple, tuple, np.ndarray]:
    """The spring side's two branches M_s = K·s + M₀ (taut: K = k_θ, seed 000 eq. 2.2; slack,
    below the rotation where the spring's tension reaches 0: the tensioner alone, (T/t)²·k_t)
    and that rotation. A progressive spring, F = F₀ + k·x·(1 + a·x) with x = r·(T/t)·s, adds
    k·a·(r·T/t)³·s to K at the spring-side rotation ``side`` (its secant stiffness)."""
    rig, k_spring = spring_side(c, data)
    travel = rig.spring_travel_m_per_rad
    k_theta = rig.joint_stiffness(k_spring)
    if side is not None and c["spring_quadratic_per_m"]:
        k_theta = k_theta + k_spring * c["spring_quadratic_per_m"] * travel**3 * side
    kink = -data.arrays["pretension_N"][:, None] / (k_spring * travel)
    k_slack = rig.chain_ratio**2 * rig.tensioner_stiffness_Nm_per_rad
    return (k_theta, 0.0 * kink), (k_slack + 0.0 * kink, (k_theta - k_slack) * kink), kink


def static_chain(drive, data: Data, c: Mapping, side=None):
    """Moment and spring-side rotation of elastic compliances in series with a spring that has
    Coulomb friction: the spring side is a play operator of the drive (closed form, taut
    spring); where the spring would go slack, the tensioner alone holds (no friction); the
    spring's secant stiffness taken at ``side`` (:func:`branches`)."""
    compliance = 1.0 / c["k_interface_Nm_per_rad"] + 1.0 / c["k_frame_Nm_per_rad"]
    tau = c["friction_Nm"]
    taut, slack, kink = branches(c, data, side)
    k_theta = taut[0]
    if tau > 0:
        scale = 1.0 + k_theta * compliance
        side = play_operator(drive / scale, tau * compliance / scale)
        if compliance > 0:
            moment = (drive - side) / compliance
        else:
            moment, side = k_theta * drive + tau * np.sign(np.gradient(drive, axis=1)), drive
    else:
        moment = drive / (compliance + 1.0 / k_theta)
        side = moment / k_theta
    stiffness, offset = slack
    loose = (drive + offset / stiffness) / (compliance + 1.0 / stiffness)
    is_slack = side < kink
    return np.where(is_slack, loose, moment), np.where(is_slack, (loose - offset) / stiffness, side)


@numba.njit(cache=True)
def _relaxation(stiffness: float, damping: float, dt: float) -> tuple[float, float]:
    """(a, q) of the exact Kelvin–Voigt step for a moment linear over the step (a = e^(−h/T))."""
    if damping <= 0.0:
        return 0.0, 1.0
    T = damping / stiffness
    a = np.exp(-dt / T)
    return a, 1.0 - T * (1.0 - a) / dt


@numba.njit(cache=True)
def _series_step(r, offset, gain, frame, s_prev, kt, ks, ms, kk, tau):
    """Moment and spring-side rotation of one step: interface δ = offset + gain·M and the frame
    in series with the spring side, which sticks while |M − M_s(s)| ≤ τ, else slides."""
    held = kt * s_prev if s_prev >= kk else ks * s_prev + ms
    stick = (r - s_prev - offset) / (gain + frame)
    if abs(stick - held) <= tau:
        return stick, s_prev
    sign = 1.0 if stick > held else -1.0
    moment = (r - offset + tau * sign / kt) / (gain + frame + 1.0 / kt)
    turned = (moment - tau * sign) / kt
    if turned < kk:
        moment = (r - offset + (ms + tau * sign) / ks) / (gain + frame + 1.0 / ks)
        turned = (moment - ms - tau * sign) / ks
    return moment, turned


@numba.njit(cache=True)
def _kelvin_voigt_step(r, h, m_prev, d_prev, s_prev, kt, ks, ms, kk, k_i, frame, tau, beta,
                       damping):  # fmt: skip
    """(M, δ, s) after one step of length h to the drive r: the interface's exact Kelvin–Voigt
    step for a moment linear over the step, the frame and spring side solved at its end; a
    stiffening interface takes its secant stiffness at the step's own end deflection (averaged
    fixed-point iteration: the secant map's slope lies in (−2, 0))."""
    k, guess = k_i, d_prev
    a, q = _relaxation(k_i, damping, h)
    m_new = s_new = d_new = 0.0
    for _ in range(SECANT_ITERATIONS):
        if beta > 0.0:
            k = k_i * (1.0 + beta * guess * guess)
            a, q = _relaxation(k, damping, h)
        offset = a * d_prev + (1.0 - a - q) * m_prev / k  # δ = offset + gain·M
        m_new, s_new = _series_step(r, offset, q / k, frame, s_prev, kt, ks, ms, kk, tau)
        d_new = offset + q / k * m_new
        if beta == 0.0 or abs(d_new - guess) < SECANT_TOLERANCE_RAD:
            break
        guess = 0.5 * (guess + d_new)  # averaged: the plain map overshoots when βδ² > 1
    return m_new, d_new, s_new


@numba.njit(cache=True)
def _chain_step(r, h, m_prev, d_prev, s_prev, kt0, kq, ks, kk, k_i, frame, tau, beta, damping):
    """:func:`_kelvin_voigt_step` with a progressive spring: its secant stiffness kt0 + kq·s
    taken at the step's own end rotation (averaged fixed-point iteration, at most
    ``SPRING_ITERATIONS``, to ``SPRING_TOLERANCE_RAD``)."""
    guess = s_prev
    m = d = s = 0.0
    for _ in range(SPRING_ITERATIONS):
        kt = kt0 + kq * guess
        m, d, s = _kelvin_voigt_step(r, h, m_prev, d_prev, s_prev, kt, ks, (kt - ks) * kk, kk,
                                     k_i, frame, tau, beta, damping)  # fmt: skip
        if kq == 0.0 or abs(s - guess) < SPRING_TOLERANCE_RAD:
            break
        guess = 0.5 * (guess + s)
    return m, d, s


@numba.njit(cache=True)
def _damped_steps(rest, steps, k_theta, k_quadratic, k_slack, kink, k_i, k_f, tau, beta,
                  damping, dt, first_dt):  # fmt: skip
    """The per-sample recursion of :func:`damped_chain`, compiled (every stride, every step).
    The first step spans ``first_dt``, from the engagement instant (drive 0) to the first
    engaged sample, in ``FIRST_SUBSTEPS`` parts: the moment rises from nothing there, far from
    linear over the step."""
    units, samples = rest.shape
    moment = np.zeros((units, samples))
    delta = np.zeros((units, samples))
    side = np.zeros((units, samples))
    frame = 1.0 / k_f
    for j in range(units):
        m = d = s = 0.0
        kt, kq, ks, kk = k_theta[j], k_quadratic[j], k_slack[j], kink[j]
        for i, n in enumerate(steps):
            if i > 0:
                m, d, s = _chain_step(rest[j, n], dt, m, d, s, kt, kq, ks, kk, k_i, frame, tau,
                                      beta, damping)  # fmt: skip
            elif first_dt > 0.0:  # (at the engagement instant itself nothing is loaded yet)
                for part in range(1, FIRST_SUBSTEPS + 1):
                    m, d, s = _chain_step(
                        rest[j, n] * part / FIRST_SUBSTEPS, first_dt / FIRST_SUBSTEPS, m, d, s,
                        kt, kq, ks, kk, k_i, frame, tau, beta, damping,
                    )  # fmt: skip
            moment[j, n], delta[j, n], side[j, n] = m, d, s
    return moment, delta, side


def damped_chain(u, engaged, data: Data, c: Mapping, dt: float):
    """Moment, interface deflection and spring-side rotation with a Kelvin–Voigt (optionally
    strain-stiffening) interface: a time-stepping solution (compiled loop over strides and steps).

    Per step the interface obeys c·δ̇ + k·δ = M with M linear over the step (exact:
    δₙ = a·δₙ₋₁ + ((1 − a − q)·Mₙ₋₁ + q·Mₙ)/k, a = e^(−h/T), q = 1 − T(1 − a)/h, T = c/k, k the
    secant stiffness k_i(1 + β·δ²)); the first step runs from the engagement instant (between
    samples when the clutch is late) to the first engaged sample, so that the load starts where
    the clutch locks; the spring side sticks while |M − M_s(s)| ≤ τ, else slides; a progressive
    spring's secant stiffness (:func:`branches`) is solved within each step.
    """
    (k_theta, _), (k_slack, _), kink = branches(c, data)
    rig, k_spring = spring_side(c, data)
    quadratic = k_spring * c["spring_quadratic_per_m"] * rig.spring_travel_m_per_rad**3
    per_unit = (np.ascontiguousarray(np.broadcast_to(x, kink.shape)[:, 0], dtype=float)
                for x in (k_theta, quadratic, k_slack, kink))  # fmt: skip
    rest = np.ascontiguousarray(np.maximum(u - c["play_rad"], np.minimum(u, 0.0)), dtype=float)
    steps = np.flatnonzero(engaged[0])
    first = data.constants["t_s"][steps[0]] - c["delay_s"] if steps.size else dt
    return _damped_steps(
        rest, steps, *per_unit,
        *(float(c[k]) for k in ("k_interface_Nm_per_rad", "k_frame_Nm_per_rad", "friction_Nm",
                                "stiffening_per_rad2", "c_interface_Nms_per_rad")),
        float(dt), float(min(first, dt)),
    )  # fmt: skip


def chain_solution(u, engaged, data: Data, c: Mapping) -> tuple[np.ndarray, ...]:
    """Moment, interface deflection and spring-side rotation of the series chain: time-stepped
    with a damped or stiffening interface (:func:`damped_chain`), else in closed form, a
    progressive spring then by fixed-point iteration on its secant stiffness (at most
    ``SPRING_ITERATIONS``, to ``SPRING_TOLERANCE_RAD``)."""
    k_i = c["k_interface_Nm_per_rad"]
    if np.isfinite(k_i) and (c["c_interface_Nms_per_rad"] > 0 or c["stiffening_per_rad2"] > 0):
        return damped_chain(u, engaged, data, c, data.constants["dt_s"])
    drive = np.maximum(u - c["play_rad"], np.minimum(u, 0.0))
    side = None
    for _ in range(SPRING_ITERATIONS if c["spring_quadratic_per_m"] else 1):
        moment, turned = static_chain(drive, data, c, side)
        done = side is not None and np.max(np.abs(turned - side)) < SPRING_TOLERANCE_RAD
        side = turned if side is None else 0.5 * (side + turned)
        if done:
            break
    return moment, moment / k_i, side


def solve(state: dict, data: Data) -> dict:
    """Moment and deflections of the series chain for the state's chain, and its recordings."""
    c = state["chain"]
    theta = state["theta"]
    u, engaged = engagement_rotation(theta, data.constants["t_s"], c["delay_s"])
    moment, delta, side = chain_solution(u, engaged, data, c)
    moment, delta, side = (np.where(engaged, x, 0.0) for x in (moment, delta, side))
    rig, k_spring = spring_side(c, data)
    travel = rig.spring_travel_m_per_rad
    kink = branches(c, data)[2]
    stretch = travel * side
    return {
        **state,
        "moment": moment,
        "exo": theta - delta,
        "spring": travel * np.maximum(side, kink),
        "force": np.maximum(
            data.arrays["pretension_N"][:, None]
            + k_spring * stretch * (1.0 + c["spring_quadratic_per_m"] * stretch),
            0.0,
        ),
    }


def mechanical(**defaults):
    """Transformation of a mechanical effect: its parameters into the chain (solved lazily)."""

    def transform(state, values, data):
        chain_values = {k: values[k] for k in defaults}
        return {**state, "chain": chain(chain_values, state), "solved": False}

    return transform


def solved(state: dict, data: Data) -> dict:
    """The state with its chain solved (once, however many effects changed it)."""
    return state if state.get("solved") else {**solve(state, data), "solved": True}


def shifted(values: np.ndarray, delay_s: float, data: Data) -> np.ndarray:
    """A recorded signal whose sample stamped t holds the value at t − delay (linear interp)."""
    size = values.shape[1]
    position = np.clip(np.arange(size) - delay_s / data.constants["dt_s"], 0.0, size - 1.0)
    i = np.minimum(position.astype(int), size - 2)
    w = position - i
    return values[:, i] * (1.0 - w) + values[:, i + 1] * w


def with_recorded(state: dict, extra: Mapping[str, np.ndarray]) -> dict:
    """The state with terms added to its observables as recorded (after the chain's filter:
    terms built from recorded, already filtered channels)."""
    total = dict(state.get("recorded_extra", {}))
    for name, value in extra.items():
        total[name] = total[name] + value if name in total else value
    return {**state, "recorded_extra": total}


def ankle_lag(delay_s: float, data: Data, prefix: str) -> np.ndarray:
    """The inverse-dynamics moment's error when the vertical ankle force lags the marker
    geometry by delay_s: (∂M/∂F_y)·(F_y,rec(t) − F_y,rec(t + d)), on a window's own arrays."""
    ankle = data.arrays[f"{prefix}ankle_force_N"]
    arm = data.arrays[f"{prefix}moment_per_ankle_force_m"]
    return arm * (ankle - shifted(ankle, -delay_s, data))


def clock(state, values, data):
    """Analog channels lag the marker clock by analog_delay_s (d). SYNC is analog too, so the
    strides it marks start d late: on the window's (marker) time line the clutch engages d
    early. LC_SPRING's sample t holds the tension at t − d: the chain driven by θ(t − d) with
    the engagement on time. The inverse-dynamics moment combines the late vertical ankle force
    with on-time marker geometry (:func:`ankle_lag`), in the engaged window and in the swing."""
    delay = values["analog_delay_s"]
    chain_values = {**state["chain"], "delay_s": state["chain"]["delay_s"] - delay}
    early = solved({**state, "chain": chain_values, "solved": False}, data)
    late = solve({**state, "theta": shifted(state["theta"], delay, data)}, data)
    lag = {"moment": ankle_lag(delay, data, ""), "swing": ankle_lag(delay, data, "swing_")}
    return with_recorded({**early, "force": late["force"]}, lag)


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
    """The measured phantom angle is biased by knee markers placed anterior of the joint: the
    true angle is recovered by inverting the geometric bias, then the chain re-solved."""
    grid = np.linspace(-0.2, 1.6, 721)
    thigh, shank = data.constants["thigh_m"], data.constants["shank_m"]
    seen = knee_marker_angle(grid, values["offset_mm"] / 1000.0, thigh, shank)
    true = np.interp(data.arrays["phantom_rad"], seen, grid)
    return {**state, "theta": true, "solved": False}


def load_cell_gain(state, values, data):
    """LC_SPRING reads gain × the true tension."""
    state = solved(state, data)
    return {**state, "force": state["force"] * values["gain"]}


def load_cell_offset(state, values, data):
    """LC_SPRING reads the true tension plus a constant offset."""
    state = solved(state, data)
    return {**state, "force": state["force"] + values["offset_N"]}


INF = np.inf
# Each entry: the effect, its parameters (name, unit, fit bounds, meaning, start value, the value
# at which the effect vanishes, the documented detectable range, and the size below which it is
# too small to name: a tenth of a degree, a millisecond or two, a percent of a gain, a newton),
# the observables it shows in and its forward transformation.
REGISTRY: dict[str, Effect] = {
    "interface_compliance": Effect(
        "interface_compliance",
        "interface compliance (soft tissue and straps in series between limb and bars)",
        (Parameter("k_interface_Nm_per_rad", "N·m/rad", 2.0, 1e5,
                   "knee-equivalent interface stiffness", start=100.0, neutral=INF,
                   detectable=(40.0, 150.0), negligible=3000.0),),
        ("moment", "exo"),
        mechanical(k_interface_Nm_per_rad=INF),
    ),
    "interface_stiffening": Effect(
        "interface_stiffening",
        "strain-stiffening of the soft tissue (interface stiffness rising with deflection)",
        (Parameter("stiffening_per_rad2", "1/rad²", 1.0, 5e3, "β in k_i·(δ + β·δ³)",
                   start=50.0, detectable=(100.0, 1000.0), negligible=10.0),),
        ("moment", "exo"),
        mechanical(stiffening_per_rad2=0.0),
        requires=("interface_compliance",),
    ),
    "interface_damping": Effect(
        "interface_damping",
        "interface damping (viscous loss in the soft tissue and straps)",
        (Parameter("c_interface_Nms_per_rad", "N·m·s/rad", 1e-3, 50.0,
                   "Kelvin–Voigt damping of the interface", start=0.5,
                   detectable=(0.8, 2.5), negligible=0.1),),
        ("moment", "exo"),
        mechanical(c_interface_Nms_per_rad=0.0),
        requires=("interface_compliance",),
    ),
    "frame_compliance": Effect(
        "frame_compliance",
        "frame compliance (bars, chain and clutch in series between bars and spring)",
        (Parameter("k_frame_Nm_per_rad", "N·m/rad", 10.0, 1e6, "knee-equivalent frame stiffness",
                   start=1000.0, neutral=INF, detectable=(300.0, 1500.0),
                   negligible=1e4),),
        ("moment", "exo", "spring"),
        mechanical(k_frame_Nm_per_rad=INF),
    ),
    "frame_friction": Effect(
        "frame_friction",
        "friction (Coulomb loss in the chain and clutch on the spring side)",
        (Parameter("friction_Nm", "N·m", 1e-3, 10.0, "knee-equivalent Coulomb friction moment",
                   start=0.2, detectable=(0.3, 1.5), negligible=0.05),),
        ("moment", "spring", "force"),
        mechanical(friction_Nm=0.0),
    ),
    "transmission_play": Effect(
        "transmission_play",
        "play in the transmission (chain slack taken up after engagement)",
        (Parameter("play_rad", "rad", 1e-4, 0.3, "knee rotation before the spring is loaded",
                   start=0.01, detectable=(0.01, 0.05), negligible=0.002),),
        ("moment", "spring", "force"),
        mechanical(play_rad=0.0),
    ),
    "clutch_timing": Effect(
        "clutch_timing",
        "late clutch engagement (the clutch locks after the programmed instant)",
        (Parameter("delay_s", "s", 1e-3, 0.3, "engagement delay after the programmed instant",
                   start=0.02, detectable=(0.02, 0.08), negligible=0.005),),
        ("moment", "exo", "spring", "force"),
        mechanical(delay_s=0.0),
    ),
    "knee_marker_offset": Effect(
        "knee_marker_offset",
        "knee markers placed off the joint centre (biased phantom knee angle)",
        (Parameter("offset_mm", "mm", -60.0, 60.0, "anterior offset of the knee markers",
                   log=False, start=0.0, detectable=(10.0, 30.0), negligible=3.0),),
        ("moment", "exo", "spring", "force"),
        knee_marker,
    ),
    "clock_offset": Effect(
        "clock_offset",
        "misaligned clocks (the analog channels lag the markers)",
        (Parameter("analog_delay_s", "s", -0.1, 0.1, "analog lag behind the marker clock",
                   log=False, start=0.0, detectable=(0.01, 0.04), negligible=0.002),),
        ("moment", "force"),
        clock,
    ),
    "load_cell_gain": Effect(
        "load_cell_gain",
        "spring load-cell gain error",
        (Parameter("gain", "1", 0.5, 2.0, "recorded over true spring tension", start=1.0,
                   neutral=1.0, detectable=(1.05, 1.15), negligible=1.01),),
        ("force",),
        load_cell_gain,
    ),
    "load_cell_offset": Effect(
        "load_cell_offset",
        "spring load-cell offset (or a pretension other than the rig's nominal)",
        (Parameter("offset_N", "N", -50.0, 50.0, "recorded minus true spring tension",
                   log=False, start=0.0, detectable=(3.0, 15.0), negligible=1.0),),
        ("force",),
        load_cell_offset,
    ),
}  # fmt: skip


def baseline(data: Data) -> dict:
    """Rigid theory: every compliance rigid, no loss, no play, engagement on the programme."""
    chain0 = {
        "k_interface_Nm_per_rad": np.inf,
        "stiffening_per_rad2": 0.0,
        "c_interface_Nms_per_rad": 0.0,
        "k_frame_Nm_per_rad": np.inf,
        "friction_Nm": 0.0,
        "play_rad": 0.0,
        "delay_s": 0.0,
        "spring_scale": 1.0,
        "arm_scale": 1.0,
        "tensioner_scale": 1.0,
        "spring_quadratic_per_m": 0.0,
    }
    return {
        "chain": chain0,
        "theta": data.arrays["phantom_rad"],
        "swing": np.zeros_like(data.arrays["swing_phantom_rad"]),
        "solved": False,
    }
