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
- the load cells' datasheets: every cell's nonlinearity, the ankle cells' through ∂M/∂F_y,
  LC_SPRING's on the predicted tension;
- the ankle cells' axis: the tilt's share of the horizontal force, through ∂M/∂F_y;
- the analog clock's rate: a lag of every analog channel that grows over the trial, each unit
  lagged as the registry's clock lag (:func:`exobench.phantom.model.effects.lagged`).
"""

from __future__ import annotations

import numpy as np

from exobench.phantom.model import assumptions
from exobench.phantom.model.effects import (
    CELLS,
    MOMENT_WINDOWS,
    NEUTRAL_CHAIN,
    ankle_lag,
    lagged,
    mechanical,
    shifted,
    solved,
    unit_time,
    with_recorded,
)
from exobench.selection import Effect
from exobench.selection.assumptions import term_library
from exobench.selection.families import UnknownFamily, transform

# The analog channels of the observations, by contract label.
CELL_ARRAYS = {f"LC_ANKLE_{i}": cell for i, cell in enumerate(CELLS, start=1)}


def _on_moments(contribution) -> dict[str, object]:
    """``contribution(prefix)`` for each knee-moment window, keyed by its observable."""
    return {obs: contribution(prefix) for obs, prefix in MOMENT_WINDOWS.items()}


def chain_term(name: str):
    """A constant of the series chain (the chain then solved again)."""
    return mechanical(**{name: NEUTRAL_CHAIN[name]})


# The phantom knee's own moment per unit of its parameter, by family: θ, θ̇ or sign(θ̇).
KNEE_LAWS = {
    "elastic": lambda theta, dt: theta,
    "viscous": lambda theta, dt: np.gradient(theta, dt, axis=1),
    "coulomb": lambda theta, dt: np.sign(np.gradient(theta, dt, axis=1)),
}


def knee_law(family: str, name: str):
    """A moment of the phantom's own knee added to the exoskeleton's, in every window (before
    the chain's filter, like any physical moment): k·θ, c·θ̇ or τ·sign(θ̇), extensor +."""
    law = transform(KNEE_LAWS, family, "the phantom's knee")

    def transform_state(state, values, data):
        state = solved(state, data)
        dt = data.constants["dt_s"]
        out = dict(state)
        for obs, theta in (("moment", state["theta"]), ("swing", data.arrays["swing_phantom_rad"])):
            out[obs] = state[obs] + values[name] * law(theta, dt)
        return out

    return transform_state


# The hip's moment on the thigh per unit of its parameter, by family, from a window's arrays
# (prefix w): φ, φ̇ or sign(φ̇), φ the thigh's angle from the vertical (against it).
HIP_LAWS = {
    "elastic": lambda arrays, w: arrays[f"{w}thigh_angle_rad"],
    "viscous": lambda arrays, w: arrays[f"{w}thigh_rate_rad_per_s"],
    "coulomb": lambda arrays, w: np.sign(arrays[f"{w}thigh_rate_rad_per_s"]),
}


def hip_law(family: str, name: str):
    """The inverse dynamics' error from a hip moment on the thigh against its rotation, −k·φ,
    −c·φ̇ or −τ·sign(φ̇): M_rec = M + (∂M/∂M_hip)·M_hip."""
    law = transform(HIP_LAWS, family, "the phantom's hip")

    def transform_state(state, values, data):
        def error(w):
            return -values[name] * law(data.arrays, w) * data.arrays[f"{w}moment_per_hip_moment"]

        return with_recorded(state, _on_moments(error))

    return transform_state


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


# An ankle cell's excess recorded force per fault, by family (the lag is a shift instead):
# gain g: (1 − 1/g)·F_cell,rec; offset o; drift ḃ·t; crosstalk s × LC_SPRING's force.
ANKLE_CELL_FAULTS = {
    "gain": lambda value, arrays, w, cell: (1.0 - 1.0 / value) * arrays[f"{w}{cell}"],
    "offset": lambda value, arrays, w, cell: value,
    "drift": lambda value, arrays, w, cell: value * arrays[f"{w}time_s"],
    "crosstalk": lambda value, arrays, w, cell: value * arrays[f"{w}spring_force_N"],
    "delay": None,
}
# LC_SPRING's faults beyond the registry's gain and offset, by family: the array its excess is a
# multiple of (drift: time, crosstalk: the vertical ankle force); the lag is a shift instead.
SPRING_CELL_FAULTS = {"drift": "time_s", "crosstalk": "ankle_force_N", "delay": None}


def cell_fault(cell: str, family: str, name: str):
    """A fault of one ankle load cell, passed to the moment through ∂M/∂F_y: its excess
    recorded force (:data:`ANKLE_CELL_FAULTS`), or a lag d (F_cell,rec(t) − F_cell,rec(t + d))."""
    array = CELL_ARRAYS[cell]
    excess = transform(ANKLE_CELL_FAULTS, family, f"load cell {cell}")

    def transform_state(state, values, data):
        if excess is None:  # the lag
            return with_recorded(state, _on_moments(
                lambda w: ankle_lag(values[name], data, w, array)))  # fmt: skip
        return with_recorded(
            state,
            _on_moments(
                lambda w: (
                    excess(values[name], data.arrays, w, array)
                    * data.arrays[f"{w}moment_per_ankle_force_m"]
                )
            ),
        )

    return transform_state


def spring_cell_fault(family: str, name: str):
    """A fault of LC_SPRING beyond the registry's gain and offset, engaged and with the clutch
    open: drift ḃ·t, crosstalk s × the vertical ankle force (:data:`SPRING_CELL_FAULTS`), lag d
    (the predicted tension shifted)."""
    extra = transform(SPRING_CELL_FAULTS, family, "load cell LC_SPRING")

    def transform_state(state, values, data):
        value = values[name]
        if extra is None:  # the lag
            state = solved(state, data)
            return {**state, "force": shifted(state["force"], value, data)}
        return with_recorded(
            state,
            {
                "force": value * data.arrays[extra],
                "swing_force": value * data.arrays[f"swing_{extra}"],
            },
        )

    return transform_state


def recorded_by_nonlinear_cell(true_N: np.ndarray, quadratic_per_kN: float) -> np.ndarray:
    """What a load cell records of a true force F: F·(1 + q·|F|), F in kN."""
    return true_N * (1.0 + quadratic_per_kN * np.abs(true_N) / 1000.0)


def true_of_nonlinear_cell(recorded_N: np.ndarray, quadratic_per_kN: float) -> np.ndarray:
    """The true force of a recording R = F·(1 + q·|F|) (kN): F = 2R / (1 + √(1 + 4q|R|)), NaN
    where no force records R."""
    with np.errstate(invalid="ignore"):
        root = np.sqrt(1.0 + 4.0 * quadratic_per_kN * np.abs(recorded_N) / 1000.0)
    return 2.0 * recorded_N / (1.0 + root)


def cells_nonlinear(name: str):
    """Every load cell records F·(1 + q·|F|): the ankle cells' excess recorded force, summed,
    passes to the moment through ∂M/∂F_y (each cell's true force from its recording);
    LC_SPRING records the predicted tension so, before the chain's filter."""

    def transform_state(state, values, data):
        q = values[name]
        state = solved(state, data)
        out = {**state, **{obs: recorded_by_nonlinear_cell(state[obs], q)
                           for obs in ("force", "swing_force")}}  # fmt: skip

        def error(w):
            cells = [data.arrays[f"{w}{cell}"] for cell in CELLS]
            excess = sum(cell - true_of_nonlinear_cell(cell, q) for cell in cells)
            return excess * data.arrays[f"{w}moment_per_ankle_force_m"]

        return with_recorded(out, _on_moments(error))

    return transform_state


def clock_rate(name: str):
    """The analog clock runs (1 + ε) × the markers': the analog sample stamped t holds its value
    at t·(1 − ε), a lag ε·t that grows over the trial; each unit lagged by ε × its time in the
    trial (the change within a window, ε × its length, is a fraction of a millisecond)."""

    def transform_state(state, values, data):
        return lagged(state, values[name] * unit_time(data), data)

    return transform_state


# The rows whose value's error passes to the moment through its sensitivity column.
SEGMENT_VALUES = tuple(
    f"{seg}_{what}" for seg in ("thigh", "shank") for what in ("mass", "com", "inertia")
)


def transform_of(row: assumptions.Assumption, r: assumptions.Relaxation):
    """The forward transformation of a relaxation, by where its row lives and its family (a row
    or family without one raises)."""
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
        return transform({"tilt": tilt}, r.family, row.where)(name)
    if row.key == "cell_linearity":
        return transform({"nonlinearity": cells_nonlinear}, r.family, row.where)(name)
    if row.key == "clocks":
        return transform({"drift": clock_rate}, r.family, row.where)(name)
    if row.key in SEGMENT_VALUES:
        return transform({"value": segment_value}, r.family, row.where)(row.key, name)
    raise UnknownFamily(f"no term transform for {row.term(r.family)} ({row.where})")


def library() -> dict[str, Effect]:
    """Every relaxation of the table that no registry effect and no direct check covers, as a
    term keyed row.family (:func:`exobench.selection.assumptions.term_library`); a constant of
    the series chain changes the model's constants (early)."""
    return term_library(assumptions.TABLE, transform_of, early=in_chain)


def in_chain(row: assumptions.Assumption, r: assumptions.Relaxation) -> bool:
    """Whether a relaxation's parameter is a constant of the series chain."""
    return f"{row.key}.{r.parameter}" in NEUTRAL_CHAIN


LIBRARY: dict[str, Effect] = library()
