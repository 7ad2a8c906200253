"""The emulator's library of correction terms, generated from its assumption table: every
relaxation of docs/emulator_assumptions.md that is not a registry effect (and not seen only by a
direct check) becomes a term the engine may add when its registry leaves structure unexplained.

Each term puts its law at one stage of the forward model (:func:`effects.solve`, through
:func:`effects.hooked`), chosen by where its row lives and found through a registry per element
keyed by family (a family an element's registry lacks raises):
- motion capture and the clocks: the knee angle motion capture shows (an artefact locked to the
  gait), the delay of its frames (a clock running at another rate);
- the brace on the knee: the hinge's offset from the knee's axis, the cuffs' law (stiffening,
  friction in parallel, a compliance drifting over the trial, play);
- the load path: the cable's law (damping, creep, slack), its calibration's slope and zero, the
  pulleys' ratio; the motor encoder's gain;
- the channels: the brace encoder's gain and slip (on its reading and, inverted, on the brace
  angle the cable's stretch takes from it), the torque sensor's gain, drift, lag and nonlinearity;
- the controller: its spring's rate, equilibrium and law, a late engagement of its clutch, an
  engagement at the loading response's peak flexion too (an arm latched once met), a release
  moved towards the impact peak after the peak extension, a release at a velocity threshold
  before it, and a velocity estimate ahead of the chain's (the clutch's activity sooner), on
  the desired-torque impulse.
"""

from __future__ import annotations

from collections.abc import Callable

import numpy as np

from exobench.emulator.model import assumptions
from exobench.emulator.model.effects import DEG, hooked, last_runs, memo
from exobench.selection import Effect, Parameter
from exobench.selection.assumptions import term_library, term_parameter
from exobench.selection.families import UnknownFamily, transform

# A law: (value, data, context) -> value, at one stage of effects.solve.
Law = Callable[[object, object, dict], object]


def backlash(line: np.ndarray, width) -> np.ndarray:
    """A play of ``width`` along axis 1 (per row, or one for all): the output stays put until
    the input pulls it along by the play's edge, y_k = clip(y_k−1, x_k − w/2, x_k + w/2), from
    y_0 = x_0 (the play's middle)."""
    half = 0.5 * np.broadcast_to(np.asarray(width, float), line.shape)
    out = np.empty_like(line)
    out[:, 0] = line[:, 0]
    for k in range(1, line.shape[1]):
        out[:, k] = np.clip(out[:, k - 1], line[:, k] - half[:, k], line[:, k] + half[:, k])
    return out


def lagged(line: np.ndarray, samples: float) -> np.ndarray:
    """Each row delayed by ``samples`` (linear interpolation; before its first sample, the
    first): y(k) = x(k − d)."""
    position = np.clip(np.arange(line.shape[1]) - samples, 0.0, line.shape[1] - 1.0)
    i = np.minimum(position.astype(int), line.shape[1] - 2)
    w = position - i
    return line[:, i] * (1.0 - w) + line[:, i + 1] * w


def _calibration(scale: float = 1.0, offset: float = 0.0) -> Law:
    """The cable's calibration b(τ) = s·(B·τ² + C·τ) + D + o in both directions."""

    def law(transmission, data, context):
        out = dict(transmission)
        for side in ("extension", "flexion"):
            coeffs = transmission[side]
            out[side] = {**coeffs, "B": scale * coeffs["B"], "C": scale * coeffs["C"],
                         "D": coeffs["D"] + offset}  # fmt: skip
        return out

    return law


def cable_damping(c: float) -> Law:
    """max(0, τ − c·ω) while the cable pulls (τ > 0), ω the brace's rate (rad/s, flexion +): a
    torque against the motion that a cable, pulling only, cannot turn negative."""

    def law(tau, data, x):
        damped = np.maximum(tau - c * data.arrays["rate_deg_per_s"] * DEG, 0.0)
        return np.where(tau > 0.0, damped, tau)

    return law


def friction_bias(bias: float) -> Law:
    """max(0, τ − τ_f) while the cable pulls (τ > 0): a friction the calibration does not hold."""
    return lambda tau, data, x: np.where(tau > 0.0, np.maximum(tau - bias, 0.0), tau)


def creep(rho: float) -> Law:
    """τ·(1 + ρ·t), t the time since the trial's first sample."""
    return lambda value, data, x: value * (1.0 + rho * x["time_s"])


def cable_slack(p: float) -> Law:
    """The stretch through a play of A·p motor degrees (p in brace degrees)."""
    return lambda stretch, data, x: backlash(stretch, x["ratio"] * p)


def cuff_stiffening(beta: float) -> Law:
    """The cuff's deflection c·τ / (1 + β·|τ|)."""
    return lambda load, data, x: load / (1.0 + beta * np.abs(x["delivered_Nm"]))


def cuff_friction(friction: float) -> Law:
    """A friction τ_s in parallel with the cuff's spring: the deflection c·τ through a play of
    ±c·τ_s (it sticks while |τ − δ/c| ≤ τ_s)."""
    return lambda load, data, x: backlash(load, 2.0 * friction * x["compliance"])


def cuff_play(p: float) -> Law:
    """The brace stays put within ±p/2 of the knee until the knee takes it along: brace +
    play(knee) − knee."""
    return lambda brace, data, x: brace + backlash(x["knee_deg"], p) - x["knee_deg"]


def hinge_offset(a: float) -> Law:
    """The brace turns θ + a·sin θ (rad) when the knee turns θ."""
    return lambda knee, data, x: knee + a * np.sin(knee * DEG) / DEG


def spring_rate(s: float) -> Law:
    """The controller's rate s·κ."""
    return lambda law, data, x: {**law, "stiffness": s * law["stiffness"]}


def spring_equilibrium(o: float) -> Law:
    """The controller's equilibrium θ_eq + o."""
    return lambda law, data, x: {**law, "equilibrium_deg": law["equilibrium_deg"] + o}


def spring_stiffening(a: float) -> Law:
    """The controller's law κ·x·(1 + a·x)."""
    return lambda law, data, x: {**law, "stiffening_per_rad": law["stiffening_per_rad"] + a}


def gain(g: float) -> Law:
    """A reading g × the true value."""
    return lambda value, data, x: g * value


def ungained(g: float) -> Law:
    """The true value of a reading with gain g: reading / g."""
    return lambda value, data, x: value / g


def drift(rate: float) -> Law:
    """A reading + ḃ·t, t the time since the trial's first sample."""
    return lambda value, data, x: value + rate * x["time_s"]


def slip(rate: float) -> Law:
    """An encoder that slips: it reads the angle − ḃ·t."""
    return drift(-rate)


def torque_lag(d: float) -> Law:
    """The sample stamped t holds the torque at t − d."""
    return lambda tau, data, x: lagged(tau, d / x["dt_s"])


def quadratic(q: float) -> Law:
    """A reading τ·(1 + q·|τ|)."""
    return lambda tau, data, x: tau * (1.0 + q * np.abs(tau))


def clock_rate(e: float) -> Law:
    """Motion capture's clock runs (1 + ε) × the brace's: a frame shows the knee ε·t earlier
    than its stamp says, the delay d + ε·t."""
    return lambda delay, data, x: delay + e * x["time_s"]


def engaging_late(d: float) -> Law:
    """The clutch engages d after Table 6.1's engagement (:func:`late_engagement`)."""
    return lambda engaged, data, x: late_engagement(engaged, d / data.constants["brace_dt_s"])


def loading_share(w: float) -> Law:
    """The share of the steps whose arm stays latched once the knee passed 40°: s + w."""
    return lambda share, data, x: share + w


def towards_heel_strike(w: float) -> Law:
    """The clutch's release a share w of the way from Table 6.1's (the peak extension, row
    sample r) to the impact peak after it (:func:`discrepancy.impact_samples`, h; the run's own,
    ``impact_at`` in the context, for another run): r + w·(h − r)."""

    def law(release_at, data, x):
        return release_at + w * (x.get("impact_at", data.arrays["impact_at"]) - release_at)

    return law


def rising_through(velocity: np.ndarray, level: float, first: np.ndarray,
                   last: np.ndarray) -> np.ndarray:  # fmt: skip
    """Where each row's velocity first rises through ``level`` after sample ``first``, at or
    before ``last`` (ω_k−1 < level ≤ ω_k, first < k ≤ last), linear between the samples:
    k − 1 + (level − ω_k−1)/(ω_k − ω_k−1); NaN where it does not."""
    k = np.arange(1, velocity.shape[1])[None, :]
    inside = (k > first[:, None]) & (k <= last[:, None])
    rises = (velocity[:, :-1] < level) & (velocity[:, 1:] >= level) & inside
    at = np.argmax(rises, axis=1)
    rows = np.arange(velocity.shape[0])
    below, above = velocity[rows, at], velocity[rows, at + 1]
    with np.errstate(invalid="ignore", divide="ignore"):
        return np.where(rises.any(axis=1), at + (level - below) / (above - below), np.nan)


def clutch_run(data) -> tuple[np.ndarray, np.ndarray]:
    """The clutch's run (rebuilt offline) that Table 6.1's release r ends, per row: the sample
    it began, s (:func:`last_runs`), and its first sample off at or after r, f = min{k ≥ r:
    e_k ≤ 0} (the spring's end may come first; the row's width where it never is off)."""

    def compute():
        engaged, release_at = data.arrays["engaged_rows"], data.arrays["release_at"]
        k = np.arange(engaged.shape[1])[None, :]
        off = (engaged <= 0.0) & (k >= release_at[:, None])
        end = np.where(off.any(axis=1), np.argmax(off, axis=1), engaged.shape[1]).astype(float)
        return last_runs(engaged, end), end

    return memo(data, ("clutch_run",), compute)


def at_velocity_threshold(v: float) -> Law:
    """The clutch released where the controller's velocity first rises through −v in its run
    rather than through 0: its release f (:func:`clutch_run`; another run's, ``run`` in the
    context: its name, start and release) moved by c(−v) − c(0) samples (:func:`rising_through`,
    s < k ≤ f), the release min(r, f + c(−v) − c(0)), r the one the stage holds (Table 6.1's,
    or as a law before this one moved it); unmoved where either crossing is missing or the
    clutch stays on to the row's end."""

    def law(release_at, data, x):
        velocity = data.arrays["velocity_rows_deg_per_s"]
        name, began, off = x.get("run") or ("table61", *clutch_run(data))
        zero = memo(data, ("rises", name), lambda: rising_through(velocity, 0.0, began, off))
        lead_samples = rising_through(velocity, -v, began, off) - zero
        moved = np.isfinite(lead_samples) & (off < velocity.shape[1])
        return np.where(moved, np.minimum(release_at, off + lead_samples), release_at)

    return law


def activity_sooner(lead: float) -> Law:
    """The clutch's activity l sooner: y(k) = x(k + l/h) (:func:`lagged`, h the brace's sample
    time), its engagement and its release alike."""
    return lambda engaged, data, x: lagged(engaged, -lead / data.constants["brace_dt_s"])


def timed_sooner(lead: float) -> Law:
    """Table 6.1's release as the controller times it, l sooner: r − l/h samples (the release's
    other moves then count from it)."""
    return lambda release_at, data, x: release_at - lead / data.constants["brace_dt_s"]


# Per element, by family: the stage of effects.solve a relaxation acts at and its law, of the
# term's values (one; an artefact locked to the gait has its phase too). A channel fault reads
# y = F(true); the encoder's also gives the brace angle back from its reading for the cable's
# stretch (F⁻¹ at ``brace_reading``).
CABLE = {"viscous": ("delivered", cable_damping), "drifting": ("delivered", creep),
         "play": ("stretch", cable_slack), "bias": ("delivered", friction_bias)}  # fmt: skip
CALIBRATION = {"value": ("calibration", lambda s: _calibration(scale=s)),
               "offset": ("calibration", lambda o: _calibration(offset=o))}  # fmt: skip
PULLEYS = {"value": ("ratio", gain)}
CUFF = {"stiffening": ("deflection", cuff_stiffening), "coulomb": ("deflection", cuff_friction),
        "drifting": ("deflection", creep), "play": ("brace", cuff_play)}  # fmt: skip
HINGE = {"offset": ("hinge", hinge_offset)}
SPRING = {"value": ("spring", spring_rate), "offset": ("spring", spring_equilibrium),
          "stiffening": ("spring", spring_stiffening)}  # fmt: skip
ENCODER = {"gain": (("encoder_reading", gain), ("brace_reading", ungained)),
           "drift": (("encoder_reading", slip), ("brace_reading", drift))}  # fmt: skip
MOTOR_ENCODER = {"gain": ("motor_reading", ungained)}
TORQUE_SENSOR = {"gain": ("torque_reading", gain), "drift": ("torque_reading", drift),
                 "delay": ("torque_reading", torque_lag),
                 "nonlinearity": ("torque_reading", quadratic)}  # fmt: skip
CLOCKS = {"drift": ("clock", clock_rate)}
CLUTCH = {"delay": ("clutch", engaging_late), "event": ("arming", loading_share)}
CLUTCH_RELEASE = {"event": ("release", towards_heel_strike),
                  "threshold": ("release", at_velocity_threshold)}  # fmt: skip
VELOCITY = {"delay": (("clutch", activity_sooner), ("timed", timed_sooner))}


def late_engagement(engaged: np.ndarray, delay_samples: float) -> np.ndarray:
    """Clutch activity engaged ``delay_samples`` after each row's first engagement (the
    engaging sample's share linear in the delay's fraction); a later run in the row stays."""
    k = np.arange(engaged.shape[1])[None, :]
    rising = np.diff(np.concatenate([np.zeros((engaged.shape[0], 1)), engaged], axis=1), axis=1)
    start = np.argmax(rising > 0.0, axis=1)[:, None]
    ends = np.cumsum(rising < 0.0, axis=1) == 0  # the first run
    share = np.clip(k + 1.0 - start - delay_samples, 0.0, 1.0)
    return np.where(ends & (k >= start), engaged * share, engaged)


def artefact(a: float, psi: float) -> Law:
    """Motion capture's soft-tissue artefact: the knee it shows, less a·sin(2πkφ + ψ₀ + ψ),
    k and ψ₀ where the data place it (the harmonic the encoder against motion capture shows
    most while the spring is inactive, ``constants["artefact"]``), φ each sample's gait phase."""

    def law(knee, data, context):
        placed = data.constants["artefact"]
        turn = 2.0 * np.pi * placed["harmonic"] * context["knee_phase"]
        return knee - a * np.sin(turn + placed["phase_rad"] + psi)

    return law


MOCAP = {"harmonic": ("knee", artefact)}

# Where each row lives: its element's registry.
ELEMENTS = {
    "cable": CABLE, "cable_calibration": CALIBRATION, "pulley_ratio": PULLEYS, "cuff": CUFF,
    "hinge": HINGE, "spring": SPRING, "encoder": ENCODER, "motor_encoder": MOTOR_ENCODER,
    "mocap": MOCAP, "torque_sensor": TORQUE_SENSOR, "torque_linearity": TORQUE_SENSOR,
    "clocks": CLOCKS, "clutch_engage": CLUTCH, "clutch_release": CLUTCH_RELEASE,
    "velocity_estimate": VELOCITY,
}  # fmt: skip


def phase_parameter(row: assumptions.Assumption) -> Parameter:
    """The artefact's phase ψ beside its amplitude: a shape (it sizes nothing), from the data's
    ψ₀, a quarter turn either way (with the amplitude of either sign, every phase)."""
    return Parameter(f"{row.key}.phase_rad", "rad", -0.5 * np.pi, 0.5 * np.pi,
                     "phase of the artefact beyond the data's own", log=False, start=0.0,
                     shape=True)  # fmt: skip


def parameters_of(row: assumptions.Assumption, r: assumptions.Relaxation) -> tuple:
    """A term's parameters: the one its relaxation sizes (:func:`term_parameter`), and for an
    artefact locked to the gait its phase."""
    sized = term_parameter(row, r)
    return (sized, phase_parameter(row)) if r.family == "harmonic" else (sized,)


def transform_of(row: assumptions.Assumption, r: assumptions.Relaxation):
    """The forward transformation of a relaxation, by where its row lives and its family (a row
    or family without one raises): its laws, of the term's values, at their stages."""
    element = ELEMENTS.get(row.key)
    if element is None:
        raise UnknownFamily(f"no term transform for {row.term(r.family)} ({row.where})")
    entry = transform(element, r.family, row.where)
    stages = entry if isinstance(entry[0], tuple) else (entry,)
    names = [p.name for p in parameters_of(row, r)]

    def transform_state(state, values, data):
        for stage, law in stages:
            state = hooked(state, stage, law(*(values[n] for n in names)))
        return state

    return transform_state


def library() -> dict[str, Effect]:
    """Every relaxation of the table that no registry effect and no direct check covers, as a
    term keyed row.family (:func:`exobench.selection.assumptions.term_library`)."""
    return term_library(assumptions.TABLE, transform_of, parameters_of)


LIBRARY: dict[str, Effect] = library()
