"""The phantom's library of correction terms, generated from the assumption table: every
relaxation of docs/assumptions.md that is not a registry effect (and not seen only by a direct
check) becomes a term the engine may add when its registry leaves structure unexplained.

How a term acts follows from where its row lives:
- an element of the series chain (interface, frame, spring, transmission constants): its
  parameter enters the chain, which is solved again (:mod:`exobench.phantom.model.effects`);
- the phantom's knee: a moment of its own, law(θ, θ̇), added to the exoskeleton's before the
  chain's filter, in the engaged window and in the swing;
- the phantom's hip and the segments' values: the inverse dynamics' error, through the
  moment's sensitivity to a hip moment or to each value (columns of the kinetics table);
- a channel: its fault on the recorded channel (a gain, offset, drift, lag or crosstalk of one
  load cell passes to the moment through ∂M/∂F_y; LC_SPRING's to the force);
- the ankle cells' axis: the tilt's share of the horizontal force, through ∂M/∂F_y.
"""

from __future__ import annotations

import numpy as np

from exobench.phantom.model import assumptions
from exobench.phantom.model.effects import (
    CELLS,
    MOMENT_WINDOWS,
    NEUTRAL_CHAIN,
    ankle_lag,
    mechanical,
    shifted,
    solved,
    with_recorded,
)
from exobench.selection import Effect, Parameter

# What a term's parameter measures, by family (its name and unit come from the table).
MEANINGS = {
    "elastic": "stiffness", "stiffening": "stiffening coefficient", "viscous": "damping",
    "coulomb": "friction moment", "drifting": "relative change of the stiffness per second",
    "value": "real over rated", "gain": "recorded over true", "offset": "offset",
    "drift": "drift rate", "delay": "lag", "crosstalk": "share of the other channel",
    "tilt": "tilt anterior of vertical",
}  # fmt: skip
# The analog channels of the observations, by contract label.
CELL_ARRAYS = {f"LC_ANKLE_{i}": cell for i, cell in enumerate(CELLS, start=1)}


def _on_moments(contribution) -> dict[str, object]:
    """``contribution(prefix)`` for each knee-moment window, keyed by its observable."""
    return {obs: contribution(prefix) for obs, prefix in MOMENT_WINDOWS.items()}


def parameter(row: assumptions.Assumption, r: assumptions.Relaxation) -> Parameter:
    """A term's parameter from its relaxation: named row.parameter, its fit bounds a few times
    beyond the visible sizes (either side of neutral for a signed one, a factor above a tenth),
    negligible below a quarter of the smallest visible size."""
    low, high = r.visible
    name, meaning = f"{row.key}.{r.parameter}", MEANINGS[r.family]
    if r.signed:  # a factor stays positive
        floor = 0.1 * r.neutral if r.neutral else -4.0 * high
        return Parameter(name, r.unit, max(r.neutral - 4.0 * high, floor), r.neutral + 4.0 * high,
                         meaning,
                         log=False, start=r.neutral, neutral=r.neutral,
                         detectable=(r.neutral + low, r.neutral + high),
                         negligible=r.neutral + low / 4.0)  # fmt: skip
    if r.neutral == 1.0:  # a factor that only grows (not far beyond what a recording sees)
        return Parameter(name, r.unit, 0.05, 1.5 * high, meaning, start=1.0, neutral=1.0,
                         detectable=(low, high), negligible=1.0 + (low - 1.0) / 4.0)  # fmt: skip
    return Parameter(name, r.unit, low / 100.0, 10.0 * high, meaning, start=low / 2.0,
                     detectable=(low, high), negligible=low / 4.0)  # fmt: skip


def chain_term(name: str):
    """A constant of the series chain (the chain then solved again)."""
    return mechanical(**{name: NEUTRAL_CHAIN[name]})


def knee_law(family: str, name: str):
    """A moment of the phantom's own knee added to the exoskeleton's, in every window (before
    the chain's filter, like any physical moment): k·θ, c·θ̇ or τ·sign(θ̇), extensor +."""

    def law(theta, dt):
        if family == "elastic":
            return theta
        rate = np.gradient(theta, dt, axis=1)
        return rate if family == "viscous" else np.sign(rate)

    def transform(state, values, data):
        state = solved(state, data)
        dt = data.constants["dt_s"]
        out = dict(state)
        for obs, theta in (("moment", state["theta"]), ("swing", data.arrays["swing_phantom_rad"])):
            out[obs] = state[obs] + values[name] * law(theta, dt)
        return out

    return transform


def hip_law(family: str, name: str):
    """The inverse dynamics' error from a hip moment on the thigh against its rotation,
    −c·φ̇ or −τ·sign(φ̇): M_rec = M + (∂M/∂M_hip)·M_hip."""

    def transform(state, values, data):
        def error(w):
            rate = data.arrays[f"{w}thigh_rate_rad_per_s"]
            law = rate if family == "viscous" else np.sign(rate)
            return -values[name] * law * data.arrays[f"{w}moment_per_hip_moment"]

        return with_recorded(state, _on_moments(error))

    return transform


def segment_value(key: str, name: str):
    """A segment value s × the rig's: the inverse dynamics, which uses the rig's, then misses
    M_rec − M = −(s − 1)·P·∂M/∂P − (s − 1)²·C·P² (C·P² the part quadratic in a centre-of-mass
    distance; masses and inertias enter linearly)."""

    def transform(state, values, data):
        excess = values[name] - 1.0

        def error(w):
            out = -excess * data.arrays[f"{w}moment_per_{key}_scale_Nm"]
            curvature = data.arrays.get(f"{w}moment_per_{key}_scale2_Nm")
            return out if curvature is None else out - excess**2 * curvature

        return with_recorded(state, _on_moments(error))

    return transform


def tilt(name: str):
    """Ankle cells measuring along an axis tilted α anterior: F_rec = F_y·cos α + F_x·sin α, so
    the analysis takes F_rec − F_y = F_rec·(1 − 1/cos α) + F_x·tan α too much vertical force."""

    def transform(state, values, data):
        alpha = values[name]

        def error(w):
            excess = data.arrays[f"{w}ankle_force_N"] * (1.0 - 1.0 / np.cos(alpha)) + data.arrays[
                f"{w}ankle_force_x_N"] * np.tan(alpha)  # fmt: skip
            return excess * data.arrays[f"{w}moment_per_ankle_force_m"]

        return with_recorded(state, _on_moments(error))

    return transform


def cell_fault(cell: str, family: str, name: str):
    """A fault of one ankle load cell, passed to the moment through ∂M/∂F_y: gain g
    ((1 − 1/g)·F_cell,rec), offset o, drift ḃ·t, lag d (F_cell,rec(t) − F_cell,rec(t + d)),
    crosstalk s × LC_SPRING's force."""
    array = CELL_ARRAYS[cell]

    def excess(values, data, w):
        value = values[name]
        if family == "gain":
            return (1.0 - 1.0 / value) * data.arrays[f"{w}{array}"]
        if family == "offset":
            return value
        if family == "drift":
            return value * data.arrays[f"{w}time_s"]
        if family == "crosstalk":
            return value * data.arrays[f"{w}spring_force_N"]
        return 0.0

    def transform(state, values, data):
        if family == "delay":
            return with_recorded(state, _on_moments(
                lambda w: ankle_lag(values[name], data, w, array)))  # fmt: skip
        return with_recorded(
            state,
            _on_moments(
                lambda w: excess(values, data, w) * data.arrays[f"{w}moment_per_ankle_force_m"]
            ),
        )

    return transform


def spring_cell_fault(family: str, name: str):
    """A fault of LC_SPRING beyond the registry's gain and offset, engaged and with the clutch
    open: drift ḃ·t, lag d (the predicted tension shifted), crosstalk s × the vertical ankle
    force."""

    def transform(state, values, data):
        value = values[name]
        if family == "delay":
            state = solved(state, data)
            return {**state, "force": shifted(state["force"], value, data)}
        extra = "time_s" if family == "drift" else "ankle_force_N"
        return with_recorded(
            state,
            {
                "force": value * data.arrays[extra],
                "swing_force": value * data.arrays[f"swing_{extra}"],
            },
        )

    return transform


def transform_of(row: assumptions.Assumption, r: assumptions.Relaxation):
    """The forward transformation of a relaxation, by where its row lives."""
    name = f"{row.key}.{r.parameter}"
    if name in NEUTRAL_CHAIN:
        return chain_term(name)
    if row.key == "knee":
        return knee_law(r.family, name)
    if row.key == "hip":
        return hip_law(r.family, name)
    if row.key in CELL_ARRAYS:
        return cell_fault(row.key, r.family, name)
    if row.key == "LC_SPRING":
        return spring_cell_fault(r.family, name)
    if row.key == "cell_direction":
        return tilt(name)
    return segment_value(row.key, name)


def library() -> dict[str, Effect]:
    """Every relaxation of the table that no registry effect and no direct check covers, as a
    term keyed row.family; a term that needs another relaxation requires that effect."""
    registry = assumptions.registry_terms()
    out = {}
    for key, (row, r) in assumptions.relaxations().items():
        if r.registry or r.checked:
            continue
        out[key] = Effect(
            key, row.description(r), (parameter(row, r),), row.observables, transform_of(row, r),
            requires=tuple(registry.get(q, q) for q in r.requires),
            early=f"{row.key}.{r.parameter}" in NEUTRAL_CHAIN,
        )  # fmt: skip
    return out


LIBRARY: dict[str, Effect] = library()
