"""Effect registry of the emulator: series predictions of the brace torque, encoder and energy.

The baseline predicts what the rig really did, from the quantities the recording holds:
- brace torque: the Bowden cable delivers the calibrated torque b⁻¹ of its stretch, the recorded
  motor angle less A × the brace angle, in the direction the knee really moves (zero-phase rate),
  eqs. (5.6)–(5.7), computed at the brace's 1 kHz and recorded, as the real-time model records it,
  through its causal low-pass (20 Hz, Heer §5.2; without it the filter's ~11 ms lag is a misfit
  the engine would put down to an effect). The brace angle is the encoder reading plus half a
  count (an incremental encoder reports whole counts, on average half a count below the angle)
  plus the counts a drop lost. The controller's tracking of its set point (PID lag, the quantised
  encoder in the set point) is in the recorded motor angle, not modelled: a model of it left a
  1–2 % torque bias that the engine claimed as a motion-capture gain of 0.997 and a torque offset of
  0.012 N·m on clean twin data. The calibrated hysteresis of the two directions is the rig's
  design, not a fault: without it the model misses the delivered torque by ~0.17 N·m RMS around
  every reversal of the knee;
- encoder: the motion-capture (anatomical) angle, through the cuff under the predicted torque,
  half a count low and less the counts dropped;
- energy stored over the window, −∫ τ dθ_encoder while active as recorded (seed 002's
  definition), with the predicted torque over the recorded encoder angle;
- desired impulse: the controller's desired torque integrated along rows at the brace's 1 kHz
  that run past heel strike (a release departs from Table 6.1 there), read at the window's
  100 Hz, predicted as the spring law on the recorded encoder while Table 6.1 (rebuilt offline)
  has the spring active. The controller computes it without noise, so its scale is its
  resolution and any misfit is structure; integrated, a release delay moves it smoothly (the
  torque itself jumps at the release, and a fit of the delay would stall at whole samples).

Each entry only sets its own parameters in the state's model description; :func:`solve` then
computes the observables. Adding an effect is one entry here and one hidden-effect test case.
"""

from __future__ import annotations

from collections.abc import Mapping

import numpy as np

from exobench.emulator.chain import controller
from exobench.emulator.model import assumptions
from exobench.selection import Data, Effect, Parameter
from exobench.selection import assumptions as shared

OBSERVABLES = {"torque": "Nm", "encoder": "deg", "energy": "J", "desired_impulse": "Nm_s"}
DEG = np.pi / 180.0

# Sizes below which an effect is too small to name (``negligible``: the engine claims an effect
# only when its whole 95 % interval lies beyond it), from the rig's resolution, not from a test:
QUARTER_DEG = 0.25  # a quarter degree: a third of the motion capture's frame noise (0.8° SD)
SWING_RANGE_DEG = 60.0  # knee range of motion in swing: a gain error g moves its ends by g·60°
SWING_TORQUE_NM = 2.0  # typical peak brace torque in swing (κ ≤ 3.5 N·m/rad over ~35°)
BRACE_SAMPLE_S = 0.001  # one brace sample (1 kHz): no clock or settling time can be named below
ENCODER_COUNT_DEG = 0.072  # one count of the 1250-CPR quadrature encoder: no smaller drop exists
HALF_LOAD_CELL_NM = 0.01  # half the load cell's noise SD (0.02 N·m)

NEUTRAL = {
    "zero_deg": 0.0,
    "gain": 1.0,
    "clock_offset_s": 0.0,
    "compliance_deg_per_Nm": 0.0,
    "time_constant_s": 0.0,
    "drop_deg": 0.0,
    "friction_fraction": 0.0,
    "torque_offset_Nm": 0.0,
    "release_delay_s": 0.0,
}


def setter(*names: str):
    """Transformation of an effect: its parameters into the state's model description."""

    def transform(state, values, data):
        return {**state, "model": {**state["model"], **{n: values[n] for n in names}}}

    return transform


def hooked(state: dict, stage: str, law) -> dict:
    """A library term's law added to the model description at one stage of :func:`solve`
    (``law(value, data, context)`` returns the stage's value changed; laws of one stage apply
    in the order the terms were added)."""
    model = state["model"]
    hooks = model.get("hooks", {})
    return {**state, "model": {**model, "hooks": {**hooks, stage: (*hooks.get(stage, ()), law)}}}


def at_stage(model: Mapping, stage: str, value, data: Data, context: Mapping, reverse=False):
    """A stage's value through the laws the model's terms put there (none: unchanged)."""
    laws = model.get("hooks", {}).get(stage, ())
    for law in reversed(laws) if reverse else laws:
        value = law(value, data, context)
    return value


def shifted(line: np.ndarray, delay_samples, margin: int, width: int, stride: int = 1):
    """Samples margin + stride·k + delay of each row (linear interpolation), k = 0 … width − 1;
    the delay a number or one per row and sample."""
    position = margin + stride * np.arange(width) + np.asarray(delay_samples, float)
    position = np.clip(np.broadcast_to(position, (line.shape[0], width)), 0.0, line.shape[1] - 1.0)
    i = np.minimum(position.astype(int), line.shape[1] - 2)
    w = position - i
    rows = np.arange(line.shape[0])[:, None]
    return line[rows, i] * (1.0 - w) + line[rows, i + 1] * w


def cuff_lag(force: np.ndarray, time_constant_s: float, dt: float) -> np.ndarray:
    """First-order lag of the soft tissue along axis 1 from rest, exact for an input linear
    between samples (first-order hold: at 10 ms samples, taking each sample as held for the
    next interval advanced the lag by ~5 ms, and the fitted time constant came out ~5 ms long)."""
    if time_constant_s <= 0.0:
        return force
    from scipy.signal import lfilter  # here: the verdict's job imports this module

    a = np.exp(-dt / time_constant_s)
    ramp = time_constant_s / dt * (1.0 - a)
    return lfilter([1.0 - ramp, ramp - a], [1.0, -a], force, axis=1)


def spring_Nm(stiffness: np.ndarray, equilibrium_deg: float, angle_deg: np.ndarray,
              stiffening_per_rad: float = 0.0):  # fmt: skip
    """Spring law τ = κ·x·(1 + a·x), x = max(0, θ_eq − θ) in rad (docs/rig.md §3: a = 0), per
    step and sample."""
    x = np.maximum(0.0, equilibrium_deg - angle_deg) * DEG
    return np.asarray(stiffness)[:, None] * x * (1.0 + stiffening_per_rad * x)


def cable_Nm(stretch_deg: np.ndarray, weight: np.ndarray, transmission: Mapping) -> np.ndarray:
    """Torque the calibrated cable delivers at a cable stretch (motor angle − A·brace angle):
    the calibration b(τ) of the direction the knee really moves in (eqs. 5.6–5.7), ``weight``
    that of extension."""
    ext, flex = transmission["extension"], transmission["flexion"]
    return weight * controller.cable_torque_Nm(stretch_deg, ext) + (
        1.0 - weight
    ) * controller.cable_torque_Nm(stretch_deg, flex)


# 1 kHz rows of the torque's inputs, from the constants' ``lead`` samples before the window
FINE = ("motor_fine_deg", "encoder_fine_deg", "weight_fine", "count_deg")


def fine_torques(fine: Mapping, c: Mapping, dropped_deg=0.0, model: Mapping | None = None,
                 view: Data | None = None,
                 context: Mapping = {}) -> dict[str, np.ndarray]:  # fmt: skip
    """Delivered and recorded torque at the window samples: the cable's torque b⁻¹ of its stretch,
    motor − A·(encoder + half a count + ``dropped_deg``) at 1 kHz (the motor's tracking of its set
    point is recorded, not modelled), and the same through the real-time model's causal low-pass
    y = H·x. Without a ``model`` each is split as τ₀ + f·τ₁ by the friction fraction f (τ₁ =
    τ₀·(2w − 1), w the extension weight; H is linear, so H(τ₀ + f·τ₁) = H·τ₀ + f·H·τ₁); with
    one, its friction and the laws its terms put on the torque's path (:data:`TORQUE_STAGES`,
    on ``view``: the observations at 1 kHz) are in the torque."""
    t = c["transmission"]
    below = 0.5 * fine["count_deg"][:, None] + dropped_deg
    read = fine["encoder_fine_deg"] + below
    motor, ratio = fine["motor_fine_deg"], controller.pulley_ratio(t)
    if model is not None:
        x = {**context, "time_s": view.arrays["time_s"], "dt_s": c["brace_dt_s"]}
        read = at_stage(model, "brace_reading", read, view, x, reverse=True)
        motor = at_stage(model, "motor_reading", motor, view, x)
        ratio = at_stage(model, "ratio", ratio, view, x)
        t = at_stage(model, "calibration", t, view, x)
    stretch = motor - ratio * read
    if model is not None:
        stretch = at_stage(model, "stretch", stretch, view, x | {"ratio": ratio})
    cable = cable_Nm(stretch, fine["weight_fine"], t)
    friction = cable * (2.0 * fine["weight_fine"] - 1.0)
    parts = {"": cable, "_friction": friction}
    if model is not None:
        delivered = cable + model["friction_fraction"] * friction
        parts = {"": at_stage(model, "delivered", delivered, view, x)}
    window = np.s_[:, c["lead"] :: c["stride"]]
    out = {}
    for name, torque in parts.items():
        out[f"delivered{name}_Nm"] = torque[window]
        recorded = controller.recorded_torque_Nm(
            torque, c["torque_filter_Hz"], 1.0 / c["brace_dt_s"]
        )
        out[f"recorded{name}_Nm"] = recorded[window]
    return out


def delivered_torques(arrays: Mapping, constants: Mapping) -> dict[str, np.ndarray]:
    """:func:`fine_torques` without a drop, computed once for the observations, and the rows a
    count drop reaches (recomputed when one is fitted)."""
    return {**fine_torques({k: arrays[k] for k in FINE}, constants),
            "drop_rows": arrays["dropped_fine"].any(axis=1)}  # fmt: skip


# The stages of the torque's path, computed at the brace's 1 kHz before the recorded torque's
# low-pass (a term there changes the cable's torque, which the filter then lags)
TORQUE_STAGES = ("brace_reading", "motor_reading", "ratio", "stretch", "calibration", "delivered")


def torque_path(model: Mapping, data: Data, context: Mapping) -> tuple[np.ndarray, np.ndarray]:
    """Delivered and recorded torque at the window samples: computed once for the registry's
    model (:func:`delivered_torques`, linear in the friction fraction; the rows a fitted drop
    reaches again), or, where a term acts on the torque's path, at 1 kHz through its laws
    (:func:`fine_torques`)."""
    a, c = data.arrays, data.constants
    f = model["friction_fraction"]
    if set(model.get("hooks", {})) & set(TORQUE_STAGES):
        fine = fine_torques({k: a[k] for k in FINE}, c, model["drop_deg"] * a["dropped_fine"],
                            model, fine_view(data), context)  # fmt: skip
        return fine["delivered_Nm"], fine["recorded_Nm"]
    delivered = a["delivered_Nm"] + f * a["delivered_friction_Nm"]
    recorded = a["recorded_Nm"] + f * a["recorded_friction_Nm"]
    if model["drop_deg"] != 0.0 and a["drop_rows"].any():  # the rows a drop reaches, at 1 kHz
        rows, drop = a["drop_rows"], model["drop_deg"]
        fine = memo(data, ("drop", drop),
                    lambda: fine_torques({k: a[k][rows] for k in FINE}, c,
                                         drop * a["dropped_fine"][rows]))  # fmt: skip
        delivered, recorded = delivered.copy(), recorded.copy()
        delivered[rows] = fine["delivered_Nm"] + f * fine["delivered_friction_Nm"]
        recorded[rows] = fine["recorded_Nm"] + f * fine["recorded_friction_Nm"]
    return delivered, recorded


def fine_view(data: Data) -> Data:
    """The observations as the torque's path sees them at 1 kHz: the brace's rate and the time
    along each row from its first sample (``lead`` before the window) at the brace's rate."""
    a, c = data.arrays, data.constants
    rate = a["rate_fine_deg_per_s"]
    start = a["time_s"][:, :1] - c["lead"] * c["brace_dt_s"]
    time = start + np.arange(rate.shape[1])[None, :] * c["brace_dt_s"]
    return Data({**a, "rate_deg_per_s": rate, "time_s": time}, data.trial, data.order,
                {**c, "dt_s": c["brace_dt_s"]})  # fmt: skip


# Per observations, the last few results of the stages whose inputs are the observations and one
# or two scalars (a fit's Jacobian changes one parameter at a time: the stages before the first
# that reads it are the same as for the fit's point). Keyed by the scalars, held with the
# observations they belong to (compared by identity, never by a recycled id).
MEMO_SIZE = 8
_MEMO: dict[tuple, tuple[Data, object]] = {}


def memo(data: Data, key: tuple, compute):
    """``compute()`` for the observations ``data`` and the scalars ``key``, kept for the next
    call with the same (the last :data:`MEMO_SIZE` kept)."""
    hit = _MEMO.get(key)
    if hit is not None and hit[0] is data:
        return hit[1]
    if len(_MEMO) >= MEMO_SIZE:
        del _MEMO[next(iter(_MEMO))]
    value = compute()
    _MEMO[key] = (data, value)
    return value


def solve(state: dict, data: Data) -> dict:
    """Brace torque, encoder angle, energy and desired impulse per window of the state's model
    description: the registry's parameters, and the laws library terms put at the stages
    (:func:`hooked`): ``knee`` (the knee angle motion capture shows), ``clock`` (its delay, s,
    per sample), ``hinge`` (the brace angle the knee turns), ``brace_reading`` (the recorded
    encoder + half a count + the drops → the brace angle, inverted laws of the encoder's
    ``encoder_reading``), ``motor_reading``, ``ratio``, ``calibration``, ``stretch``,
    ``delivered``, ``deflection`` (the cuff's load c·τ), ``brace`` (the brace angle with the
    cuff's deflection), ``encoder_reading``, ``torque_reading``, ``spring``, ``clutch``,
    ``timed`` (the sample Table 6.1's release falls on as the controller times its events),
    ``release`` (the sample each row's release falls on, :func:`desired_impulse`) and
    ``arming`` (the share of the steps whose arm stays latched once the knee passed 40°)."""
    p = state["model"]
    a, c = data.arrays, data.constants
    dt, margin = c["dt_s"], c["margin"]
    width = a["encoder_deg"].shape[1]
    context = {"time_s": a["time_s"], "knee_phase": a["phase"], "dt_s": dt}

    def mocap_seen():
        delay_s = at_stage(p, "clock", p["clock_offset_s"], data, context)
        return shifted(a["mocap_deg"], np.asarray(delay_s) / c["mocap_dt_s"], margin, width,
                       c["stride"])  # fmt: skip

    # kept unless a term puts a law on the clock (then it is more than the offset)
    seen = (mocap_seen() if "clock" in p.get("hooks", {})
            else memo(data, ("seen", p["clock_offset_s"]), mocap_seen))  # fmt: skip
    knee = at_stage(p, "knee", (seen - p["zero_deg"]) / p["gain"], data, context)
    context["knee_deg"] = knee
    # the encoder counts whole steps: it reads half a count below the brace on average, and the
    # counts lost in a drop less from the drop on
    below = 0.5 * a["count_deg"][:, None] + p["drop_deg"] * a["dropped"]
    delivered, recorded = torque_path(p, data, context)
    context |= {"delivered_Nm": delivered, "compliance": p["compliance_deg_per_Nm"]}
    load = at_stage(p, "deflection", p["compliance_deg_per_Nm"] * delivered, data, context)
    lag = cuff_lag(load, p["time_constant_s"], dt)
    brace = at_stage(p, "brace", at_stage(p, "hinge", knee, data, context) + lag, data, context)
    encoder = at_stage(p, "encoder_reading", brace, data, context) - below
    torque = at_stage(p, "torque_reading", recorded, data, context) + p["torque_offset_Nm"]
    # seed 002's energy over the recorded encoder angle: the torque is the model's, the angle
    # the recording's (the model's encoder carries the motion capture's noise and filter)
    stored = window_energy_J(torque, a["encoder_deg"], a["active"])
    return {**state, "torque": torque, "encoder": encoder, "energy": stored,
            "desired_impulse": desired_impulse(p, data, context)}  # fmt: skip


def desired_impulse(model: Mapping, data: Data, context: Mapping) -> np.ndarray:
    """The controller's desired torque integrated along each row (:func:`impulse_Nm_s`): the
    spring law on the recorded encoder while the clutch is engaged as Table 6.1 (rebuilt
    offline) says, released at Table 6.1's release as the controller times it (stage "timed")
    moved where the model's terms move it (stage "release") and ``release_delay_s`` late, plus
    a share w (stage "arming") of what a latched arm's runs add (:func:`loading_runs`),
    a + w·max(0, l − a); Table 6.1's own impulse when nothing changes it (computed once)."""
    a, c = data.arrays, data.constants
    hooks = model.get("hooks", {})
    if not ({"spring", "clutch", "timed", "release", "arming"} & set(hooks)):  # Table 6.1's
        delay = model["release_delay_s"]
        if delay == 0.0:
            return a["table61_impulse_Nm_s"]

        def late():
            held = held_clutch(a["table61_rows"], a["release_at"], delay / c["brace_dt_s"],
                               table61_runs(data))  # fmt: skip
            return impulse_Nm_s(a["spring_rows_Nm"] * held, c["brace_dt_s"], c["stride"])

        return memo(data, ("release", delay), late)
    if {"spring", "clutch"} & set(hooks):
        law = at_stage(model, "spring", {"stiffness": a["stiffness_Nm_per_rad"],
                                         "equilibrium_deg": c["equilibrium_deg"],
                                         "stiffening_per_rad": 0.0}, data, context)  # fmt: skip
        spring = spring_Nm(law["stiffness"], law["equilibrium_deg"], a["encoder_rows_deg"],
                           law["stiffening_per_rad"])  # fmt: skip
        engaged = at_stage(model, "clutch", a["engaged_rows"], data, context)
        table61 = engaged * (spring > 0.0)
    else:  # Table 6.1's spring and engagement as the observations hold them (computed once)
        spring, table61 = a["spring_rows_Nm"], a["table61_rows"]
    timed = at_stage(model, "timed", a["release_at"], data, context)
    release = at_stage(model, "release", timed, data, context)
    delay = release - timed + model["release_delay_s"] / c["brace_dt_s"]
    if np.any(delay != 0.0):
        began = (table61_runs(data) if table61 is a["table61_rows"]
                 else last_runs(table61, timed))  # fmt: skip
        table61 = held_clutch(table61, timed, delay, began)
    share = at_stage(model, "arming", 0.0, data, context)
    if share != 0.0:  # the runs an arm latched once the knee passed 40° adds, a share w of them
        extra = np.clip(loading_runs(model, data, context, spring) - table61, 0.0, None)
        table61 = table61 + share * extra
    return impulse_Nm_s(spring * table61, c["brace_dt_s"], c["stride"])


def moved_release(model: Mapping, data: Data, context: Mapping, release_at: np.ndarray):
    """A run's release (row samples) as the controller times it and the model's terms and delay
    move it: (timed t, moved r')."""
    timed = at_stage(model, "timed", release_at, data, context)
    moved = at_stage(model, "release", timed, data, context)
    return timed, moved + model["release_delay_s"] / data.constants["brace_dt_s"]


def loading_runs(model: Mapping, data: Data, context: Mapping, spring: np.ndarray):
    """Spring activity of the runs only an arm latched once the knee passed 40° engages (each
    loading peak's, rebuilt offline), each released as the model moves Table 6.1's release:
    the row's own (through the clutch's laws, its release at ``loading_release_at`` where the
    row holds one, its heel strike the next step's) and the one engaged before the row began
    (:func:`carried_in`)."""
    a = data.arrays
    own = {**context, "impact_at": a["loading_impact_at"],
           "run": ("loading", a["loading_began"], a["loading_release_at"])}  # fmt: skip
    engaged = at_stage(model, "clutch", a["loading_rows"], data, context)
    active = engaged * (spring > 0.0)
    timed, moved = moved_release(model, data, own, a["loading_release_at"])
    # a run still on at the row's end has no release the row sees: nothing to move
    moved = np.where(a["loading_release_at"] < active.shape[1], moved, timed)
    if np.any(moved != timed):
        active = held_clutch(active, timed, moved - timed, last_runs(active, timed))
    return np.maximum(active, carried_in(model, data, context) * (spring > 0.0))


def carried_in(model: Mapping, data: Data, context: Mapping) -> np.ndarray:
    """Activity of the run a latched arm engaged before each row began, from the row's start to
    its release as the model moves it (``carried_at``, that run's release, ≤ 0; none where
    NaN): min(1, max(0, r' − k)) at row sample k."""
    a = data.arrays
    _, moved = moved_release(model, data, context, a["carried_at"])
    k = np.arange(a["table61_rows"].shape[1])[None, :]
    return np.nan_to_num(np.clip(moved[:, None] - k, 0.0, 1.0))


def impulse_Nm_s(torque_Nm: np.ndarray, dt: float, every: int) -> np.ndarray:
    """Torque integrated along each row from its start, Σ τ·Δt, at the end of every ``every``
    samples (the window's sample rate: the 1 kHz integral is smooth between them)."""
    blocks = torque_Nm.shape[1] // every
    whole = torque_Nm[:, : blocks * every].reshape(torque_Nm.shape[0], blocks, every)
    return np.cumsum(whole.sum(axis=2), axis=1) * dt


def last_runs(table61: np.ndarray, release_at: np.ndarray) -> np.ndarray:
    """The sample where each row's last run of activity before Table 6.1's release (sample
    ``release_at``) began, 0 without one."""
    k = np.arange(table61.shape[1])[None, :]
    rising = (table61 > 0.0) & (np.pad(table61, ((0, 0), (1, 0)))[:, :-1] <= 0.0)
    return np.max(np.where(rising & (k < release_at[:, None]), k, 0), axis=1)


def table61_runs(data: Data) -> np.ndarray:
    """:func:`last_runs` of Table 6.1's activity as the observations hold it (computed once)."""
    a = data.arrays
    return memo(data, ("last_runs",), lambda: last_runs(a["table61_rows"], a["release_at"]))


def held_clutch(table61: np.ndarray, release_at: np.ndarray, delay_samples,
                began: np.ndarray) -> np.ndarray:  # fmt: skip
    """Spring activity of a clutch released ``delay_samples`` (one for all rows, or one per row;
    below 0: early, no sooner than the last run of activity began, at ``began``,
    :func:`last_runs`) after Table 6.1 releases it (at sample ``release_at`` of each row),
    linear in the delay between whole samples; a later engagement in the row stays."""
    delay = np.broadcast_to(np.asarray(delay_samples, float), release_at.shape)
    # an early release ends the last run no sooner than it began
    delay = np.maximum(delay, began - release_at)
    # only the samples between each release and the moved one change
    span = int(np.ceil(np.max(np.abs(delay), initial=0.0))) + 1
    start = release_at + np.minimum(delay, 0.0)
    k = np.floor(start).astype(int)[:, None] + np.arange(span + 1)[None, :]
    rows = np.broadcast_to(np.arange(table61.shape[0])[:, None], k.shape)
    inside = (k >= 0) & (k < table61.shape[1])
    rows, k = rows[inside], k[inside]
    out = table61.copy()
    share = np.clip(release_at[rows] + delay[rows] - k, 0.0, 1.0)
    later = k >= release_at[rows]
    out[rows, k] = np.where(later, np.maximum(share, table61[rows, k]),
                            np.minimum(share, table61[rows, k]))  # fmt: skip
    return out


def window_energy_J(torque_Nm: np.ndarray, angle_deg: np.ndarray, active: np.ndarray):
    """Energy stored over each window, −Σ ½(τ_i + τ_i+1)(θ_i+1 − θ_i) over active intervals."""
    dtheta = np.diff(angle_deg, axis=1) * DEG
    return -np.sum(0.5 * (torque_Nm[:, 1:] + torque_Nm[:, :-1]) * dtheta * active[:, :-1], axis=1)


def baseline(data: Data) -> dict:
    """Calibrated cable on the recorded motor and encoder angles, the encoder as the motion
    capture sees the knee: every sensor and the transmission as calibrated."""
    return {"model": dict(NEUTRAL)}


def recorded(state: dict, data: Data) -> dict:
    """The observables of the state's model (solved once, after every transformation)."""
    solved = solve(state, data)
    return {o: solved[o] for o in OBSERVABLES}


def registry_effect(name: str, parameters: tuple[Parameter, ...], transform) -> Effect:
    """A registry entry: the assumption table's relaxation that is this effect (its description,
    the observables its row touches) with the engine's parameters and transformation."""
    return shared.registry_effect(assumptions.TABLE, name, parameters, transform)


# Each entry: the effect, its parameters (name, unit, fit bounds, meaning, start value, the value
# at which the effect vanishes, the documented detectable range) and its forward transformation;
# its name and observables come from the assumption table.
REGISTRY: dict[str, Effect] = {
    "mocap_zero": registry_effect(
        "mocap_zero",
        (Parameter("zero_deg", "deg", -20.0, 20.0, "motion capture reads zero + gain·θ",
                   log=False, start=0.0, detectable=(1.0, 5.0), negligible=QUARTER_DEG),),
        setter("zero_deg"),
    ),
    "mocap_gain": registry_effect(
        "mocap_gain",
        (Parameter("gain", "1", 0.7, 1.3, "motion-capture degrees per knee degree", log=False,
                   start=1.0, neutral=1.0, detectable=(0.03, 0.10),
                   negligible=1.0 + QUARTER_DEG / SWING_RANGE_DEG),),
        setter("gain"),
    ),
    "mocap_clock": registry_effect(
        "mocap_clock",
        (Parameter("clock_offset_s", "s", -0.09, 0.09,
                   "the motion-capture frame stamped s shows the knee at s − offset", log=False,
                   start=0.0, detectable=(0.01, 0.04), negligible=BRACE_SAMPLE_S),),
        setter("clock_offset_s"),
    ),
    "cuff_compliance": registry_effect(
        "cuff_compliance",
        (Parameter("compliance_deg_per_Nm", "deg/(N·m)", 0.01, 10.0,
                   "brace minus limb angle per N·m of brace torque, settled", start=0.5,
                   detectable=(0.5, 2.0), negligible=QUARTER_DEG / SWING_TORQUE_NM),
         Parameter("time_constant_s", "s", 0.001, 0.3, "settling time constant of the cuffs",
                   start=0.02, detectable=(0.01, 0.05), shape=True)),
        setter("compliance_deg_per_Nm", "time_constant_s"),
    ),
    "encoder_count_drop": registry_effect(
        "encoder_count_drop",
        (Parameter("drop_deg", "deg", -30.0, 30.0,
                   "counts lost at the drop the session QC located (before the trial: a "
                   "constant offset of that trial)", log=False, start=0.0,
                   detectable=assumptions.DROP_DETECTABLE_DEG, negligible=ENCODER_COUNT_DEG,
                   resolution=ENCODER_COUNT_DEG),),
        setter("drop_deg"),
    ),
    "transmission_friction": registry_effect(
        "transmission_friction",
        (Parameter("friction_fraction", "1", -0.5, 0.5,
                   "delivered/desired torque − 1 while extending (Heer §5.3)", log=False,
                   start=0.0, detectable=(0.05, 0.20),
                   negligible=HALF_LOAD_CELL_NM / SWING_TORQUE_NM),),
        setter("friction_fraction"),
    ),
    "torque_offset": registry_effect(
        "torque_offset",
        (Parameter("torque_offset_Nm", "N·m", -2.0, 2.0, "recorded minus true brace torque",
                   log=False, start=0.0, detectable=(0.05, 0.3), negligible=HALF_LOAD_CELL_NM),),
        setter("torque_offset_Nm"),
    ),
    "clutch_late_release": registry_effect(
        "clutch_late_release",
        (Parameter("release_delay_s", "s", 1e-4, 0.3,
                   "time the controller held its clutch past Table 6.1's release", start=0.02,
                   detectable=(0.003, 0.1), negligible=BRACE_SAMPLE_S,
                   resolution=BRACE_SAMPLE_S),),
        setter("release_delay_s"),
    ),
}  # fmt: skip
