"""The real-time controller at 1 kHz (Heer ch. 5–6) in closed loop with the rig: velocity from the
encoder, Table 5.1's gait events, Table 6.1's virtual clutch (or a lab's reading of it), the
spring law, the motor set point through the cable's calibration (eqs. 5.6–5.8), the motor's servo,
the cable and the cuffs, sample by sample."""

import math
from collections.abc import Mapping
from typing import NamedTuple

import numba
import numpy as np

from .cable import A_RATIO, SLACK, delivered_torque, flexing_weight, stretch_for
from .cuffs import cuff_step
from .reading import CENTRED_HALF_SPAN, Reading
from .rig import (
    ENGAGE_ABOVE_DEG,
    EQUILIBRIUM_DEG,
    FS,
    PEAK_EXTENSION_BELOW_DEG,
    PEAK_FLEXION_ABOVE_DEG,
    PULLEY_RATIO,
    value_of,
)
from .sensors import butterworth, encoder_reading

# Layout of the controller's vector: the spring's κ (N·m/rad), θ_eq (deg) and stiffening a
# (1/rad); the clutch's engage and release delays (samples), whether it releases at Table 5.1's
# heel strike (1) or where ω rises to −v_th (0), v_th (°/s), whether its arm latches (1); the
# velocity's difference span (samples) and filter b0, b1, b2, a1, a2, and the lag (samples) of
# the velocity its events are timed on; the servo's step factor 1 − exp(−h/T); the motor encoder's
# gain; the pulley ratio A it assumes.
(KAPPA, THETA_EQ, STIFFENING, ENGAGE_DELAY, RELEASE_DELAY, RELEASE_AT_HEEL, RELEASE_BELOW, LATCHED,
 SPAN, VB0, VB1, VB2, VA1, VA2, EVENT_LAG, SERVO, MOTOR_GAIN, RATIO,
 CONTROLLER_SIZE) = range(19)  # fmt: skip


# Table 5.1's events, as the loop marks them per sample.
NO_EVENT, PEAK_FLEXION, PEAK_EXTENSION, HEEL_STRIKE = range(4)


class Loop(NamedTuple):
    """Per sample: brace (deg), encoder (deg), velocity estimate (°/s), Table 5.1's event, clutch,
    desired τ (N·m), motor reading (deg), motor pulley (deg), delivered τ (N·m), whether the
    clutch's rule released it there."""

    brace: np.ndarray
    encoder: np.ndarray
    rate: np.ndarray
    events: np.ndarray
    engaged: np.ndarray
    desired: np.ndarray
    motor_reading: np.ndarray
    motor: np.ndarray
    torque: np.ndarray
    released: np.ndarray


def controller_vector(
    stiffness_Nm_per_rad: float,
    violations: Mapping[str, Mapping[str, float]],
    reading: Reading,
) -> np.ndarray:
    """The controller as it runs: the spring law's real κ·s, θ_eq + o and a, the clutch's delays
    (a late release's and the reading's, summed), rules (a release threshold's and the reading's,
    summed), velocity estimate (and the lag of the velocity its events are timed on) and motor
    lag."""
    p = np.zeros(CONTROLLER_SIZE)
    p[KAPPA] = stiffness_Nm_per_rad * value_of(violations, "spring.value", 1.0)
    p[THETA_EQ] = EQUILIBRIUM_DEG + value_of(violations, "spring.offset", 0.0)
    p[STIFFENING] = value_of(violations, "spring.stiffening", 0.0)
    p[ENGAGE_DELAY] = round(value_of(violations, "clutch_engage.delay", 0.0) * FS)
    release_delay = value_of(violations, "clutch_release.delay", 0.0) + reading.release_delay_s
    p[RELEASE_DELAY] = round(release_delay * FS)
    p[RELEASE_AT_HEEL] = reading.release_rule == "heel_strike"
    p[RELEASE_BELOW] = (reading.release_threshold_deg_per_s
                        + value_of(violations, "clutch_release.threshold", 0.0))  # fmt: skip
    p[LATCHED] = reading.engage_rule == "latched"
    if reading.velocity_estimate == "butterworth":
        p[SPAN] = 1
        b, a = butterworth(reading.velocity_cutoff_Hz, reading.velocity_order)
        p[VB0 : VB0 + b.size], p[VA1 : VA1 + a.size - 1] = b, a[1:] / a[0]
    else:  # the unfiltered centred difference about sample i − k
        p[SPAN], p[VB0] = 2 * CENTRED_HALF_SPAN, 1.0
    p[EVENT_LAG] = -round(value_of(violations, "velocity_estimate.delay", 0.0) * FS)  # a lead
    p[SERVO] = 1.0 - math.exp(-1.0 / (FS * reading.motor_time_constant_s))
    p[MOTOR_GAIN] = value_of(violations, "motor_encoder.gain", 1.0)
    p[RATIO] = PULLEY_RATIO
    return p


@numba.njit(cache=True)
def _spring_torque(angle_deg: float, p: np.ndarray) -> float:
    """τ = κ·x·(1 + a·x), x = max(0, θ_eq − θ) in rad (docs/rig.md §3, positive in flexion)."""
    x = math.radians(max(p[THETA_EQ] - angle_deg, 0.0))
    return p[KAPPA] * x * (1.0 + p[STIFFENING] * x)


@numba.njit(cache=True)
def _event(flags: np.ndarray, angle: float, w: float, w_prev: float) -> int:
    """Table 5.1 (knee) on flags FLX, EXT: peak flexion, peak extension, heel strike, or none."""
    if not flags[0] and angle > PEAK_FLEXION_ABOVE_DEG and w_prev >= 0.0 and w < 0.0:
        flags[0], flags[1] = True, False
        return PEAK_FLEXION
    if flags[0] and angle < PEAK_EXTENSION_BELOW_DEG and w_prev <= 0.0 and w > 0.0:
        flags[0], flags[1] = False, True
        return PEAK_EXTENSION
    if flags[1] and w < w_prev:  # the velocity's impact peak just after the heel strikes
        flags[1] = False
        return HEEL_STRIKE
    return NO_EVENT


@numba.njit(cache=True)
def _releases(event: int, w: float, w_prev: float, p: np.ndarray) -> bool:
    """The release's event: Table 5.1's heel strike, or ω_i−1 < −v_th ≤ ω_i (v_th 0: Table 6.1)."""
    if p[RELEASE_AT_HEEL] > 0.0:
        return event == HEEL_STRIKE
    return w_prev < -p[RELEASE_BELOW] and w >= -p[RELEASE_BELOW]


# numba keys _loop's cache on this file alone: a change to a jitted function it calls (cable.py,
# cuffs.py, sensors.py) must come with a change here, or a checkout's cache keeps the old one.
@numba.njit(cache=True)
def _loop(hinge, t, p, calibration, encoder, cable, cuffs, loading, later, early, ahead):
    """March the controller, servo, cable and cuffs through the hinge's angle, one sample a step
    (``ahead``: the velocity a lead times the events on, NaN where none is known yet)."""
    n = hinge.size
    h = 1.0 / FS
    span = int(p[SPAN])
    brace, reading, rate, desired = np.empty(n), np.empty(n), np.empty(n), np.empty(n)
    motor_reading, motor, torque = np.empty(n), np.empty(n), np.empty(n)
    engaged, released = np.zeros(n, dtype=np.bool_), np.zeros(n, dtype=np.bool_)
    events, flags = np.zeros(n, dtype=np.int8), np.zeros(2, dtype=np.bool_)
    delta, tau, z1, z2, w_prev, set_prev, taken = 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0
    lag = int(p[EVENT_LAG])
    flag, clutch, armed, on_at, off_at = False, False, False, -1, -1
    passed, peaks = False, 0  # the knee has passed 40° once; peaks below the arm met since
    for i in range(n):
        if i == 0:
            brace[i] = hinge[0]
        else:  # the cuffs turn the brace off the hinge under the last step's torque
            brace[i], delta = cuff_step(tau, hinge[i], brace[i - 1], delta, t[i], h, cuffs)
        reading[i] = encoder_reading(brace[i], t[i], encoder)
        # ω: the filter of (θ_e,i − θ_e,i−m)/(m·h) (transposed form II; the centred difference:
        # m = 2k and no filter)
        raw = (reading[i] - reading[i - span]) * (FS / span) if i >= span else 0.0
        w = p[VB0] * raw + z1
        z1 = p[VB1] * raw - p[VA1] * w + z2
        z2 = p[VB2] * raw - p[VA2] * w
        rate[i] = estimate = w
        # the velocity the events are timed on: the estimate m samples back (a lag d = m·h), or
        # m ahead as the last run of the loop left it (a lead), else the estimate itself
        if lag > 0:
            w = rate[i - lag] if i >= lag else 0.0
        elif lag < 0 and np.isfinite(ahead[i]):
            w = ahead[i]
        events[i] = _event(flags, reading[i], w, w_prev) if i > 0 else NO_EVENT
        # Table 6.1: engage at a peak flexion beyond 40° (latched: beyond 40° once; or a drawn
        # share of the peaks below, the knee past 40° before), release at the next peak
        # extension (or where ω rises to −v_th, or at Table 5.1's heel strike).
        armed = (armed and p[LATCHED] > 0.0) or reading[i] > ENGAGE_ABOVE_DEG
        passed = passed or reading[i] > ENGAGE_ABOVE_DEG
        peak = not flag and w_prev > 0.0 and w <= 0.0
        below = peak and not armed and passed
        if below:
            peaks += 1
        if peak and (armed or (below and loading[peaks - 1])):
            flag, on_at = True, i + int(p[ENGAGE_DELAY])
        elif flag and (early[i] or _releases(events[i], w, w_prev, p)):
            # a release moved (clutch_release.event): later by later[i] samples, or now
            rule = not early[i]
            flag, off_at = False, i + int(p[RELEASE_DELAY]) + (later[i] if rule else 0)
            released[i] = rule
            if on_at > off_at:  # released before its late engagement: it never engages
                on_at = -1
        if i == on_at:
            clutch = True
        if i == off_at:
            clutch = False
        engaged[i] = clutch
        desired[i] = _spring_torque(reading[i], p) if clutch else 0.0
        target = p[RATIO] * reading[i] + stretch_for(
            desired[i], flexing_weight(estimate), calibration
        )
        motor_reading[i] = (
            target
            if i == 0
            else motor_reading[i - 1] + p[SERVO] * (set_prev - motor_reading[i - 1])
        )
        motor[i] = motor_reading[i] / p[MOTOR_GAIN]
        brace_rate = (brace[i] - brace[i - 1]) * FS if i > 0 else 0.0
        if i == 0:  # the slack starts taken up
            taken = motor[0] - cable[A_RATIO] * (brace[0] + 0.5 * cable[SLACK])
        tau, taken = delivered_torque(motor[i], brace[i], brace_rate, t[i], taken, cable)
        torque[i] = tau
        w_prev, set_prev = w, target
    return brace, reading, rate, events, engaged, desired, motor_reading, motor, torque, released


def run_loop(
    hinge_deg: np.ndarray,
    t: np.ndarray,
    controller: np.ndarray,
    calibration: np.ndarray,
    encoder: np.ndarray,
    cable: np.ndarray,
    cuffs: np.ndarray,
    heel_strike_share: float,
    loading: np.ndarray,
) -> Loop:
    """The closed loop over the hinge's angle sampled at 1 kHz (t: time since the first record);
    with a ``heel_strike_share`` w ≠ 0 (clutch_release.event) each release of the clutch's rule
    moves w of the way to the heel strike that follows (Table 5.1's events,
    :func:`release_schedule`), the loop run again on its last run's events until the schedule
    repeats (at most :data:`RESCHEDULES` more runs); ``loading``: whether the k-th peak flexion
    at or below 40° engages too, the knee past 40° before (clutch_engage.event). A controller
    whose velocity leads by l (velocity_estimate.delay) times its events on the estimate l
    ahead as the loop's last run left it, run again until its runs repeat (the last run's, if
    they do not within :data:`RESCHEDULES`: its events then rest on an estimate that differs
    from its own by the cuffs' response to a moved edge)."""
    hinge = np.ascontiguousarray(hinge_deg, float)
    times = np.ascontiguousarray(t, float)
    later, early = np.zeros(hinge.size, dtype=np.int64), np.zeros(hinge.size, dtype=np.bool_)
    ahead = np.full(hinge.size, np.nan)
    args = (hinge, times, controller, calibration, encoder, cable, cuffs, loading)
    loop = Loop(*_loop(*args, later, early, ahead))
    rule = np.flatnonzero(loop.released)  # where the rule releases, before any is moved
    lead = controller[EVENT_LAG] < 0.0
    for _ in range(RESCHEDULES if heel_strike_share != 0.0 or lead else 0):
        moved = (release_schedule(rule, loop.events, heel_strike_share)
                 if heel_strike_share != 0.0 else (later, early))  # fmt: skip
        sooner = ahead_of(loop.rate, controller[EVENT_LAG]) if lead else ahead
        same = all(np.array_equal(m, s) for m, s in zip(moved, (later, early), strict=True))
        if same and np.array_equal(sooner, ahead, equal_nan=True):
            break
        (later, early), ahead = moved, sooner
        loop = Loop(*_loop(*args, later, early, ahead))
    return loop


def ahead_of(rate: np.ndarray, lag: float) -> np.ndarray:
    """The velocity estimate m = −lag samples ahead, ω_i+m (the last sample's at the end): the
    velocity a controller whose estimate leads by m samples times its events on."""
    m = int(-lag)
    return rate[np.minimum(np.arange(rate.size) + m, rate.size - 1)]


# clutch_release.event and a velocity that leads: the loop runs again on its last run's events
# at most this many times (events move by a sample or two once a release moves; they settle in
# one or two runs)
RESCHEDULES = 4


def release_schedule(released: np.ndarray, events: np.ndarray,
                     w: float) -> tuple[np.ndarray, np.ndarray]:  # fmt: skip
    """Each release r of the clutch's rule (samples ``released``) moved to r + round(w·(h − r)),
    h the heel strike after it and before the next peak flexion (Table 5.1's ``events``; a
    release without one stays): (later: samples a rule release at r waits, early: samples where
    a release comes first)."""
    strikes = np.flatnonzero(events == HEEL_STRIKE)
    flexions = np.flatnonzero(events == PEAK_FLEXION)
    later = np.zeros(events.size, dtype=np.int64)
    early = np.zeros(events.size, dtype=np.bool_)
    if not strikes.size:
        return later, early
    h = strikes[np.minimum(np.searchsorted(strikes, released, side="right"), strikes.size - 1)]
    f = np.searchsorted(flexions, released, side="right")
    before = np.where(f < flexions.size, flexions[np.minimum(f, flexions.size - 1)], np.inf)
    ok = (h > released) & (h < before)
    shift = np.round(w * (h - released)).astype(np.int64)
    later[released[ok & (shift > 0)]] = shift[ok & (shift > 0)]
    early[np.clip(released + shift, 0, None)[ok & (shift < 0)]] = True
    return later, early
