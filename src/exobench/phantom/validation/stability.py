"""Validation of the parameter stability on the phantom's twin: a rig constant changed in one
trial, or in none.

The twin records each trial on its own (its own settings and noise stream): every trial with the
session's rig, and the changed trial, if any, with one constant of the assumption table's
``between`` rows moved (the interface stiffness by a share of itself, LC_SPRING's zero by some
newtons). The analysis chain reads the files back as a lab's; the registry effects the twin
holds are fitted to all the data, as a right selection leaves them, and the parameter stability
(:func:`exobench.selection.stability.stability`) compares the trials. The rows say, per
constant, whether it flagged and which trials it named.
"""

from __future__ import annotations

import copy
import tempfile
from collections.abc import Mapping
from pathlib import Path

import numpy as np

from exobench import phantom, selection
from exobench.phantom.model import assumptions, discrepancy
from exobench.phantom.rig import Rig
from exobench.phantom.twin import twin
from exobench.phantom.validation import recordings
from exobench.selection import validation
from exobench.selection.assumptions import between_spreads

# The rig every trial shares: the registry effects a real rig has, at its sizes.
RIG = {
    "interface_compliance": {"k_interface_Nm_per_rad": 65.0},
    "interface_damping": {"c_interface_Nms_per_rad": 1.0},
    "frame_compliance": {"k_frame_Nm_per_rad": 1000.0},
    "frame_friction": {"friction_Nm": 0.8},
}
# How each constant of a between row changes in a trial, as the twin's settings: the effect and
# its parameter, and whether the change is a share of the session's value (else added to it).
CHANGES = {
    "straps_between": ("interface_compliance", "k_interface_Nm_per_rad", True),
    "cells_zero_between": ("load_cell_offset", "offset_N", False),
}
# The visible spread between trials of each constant (the table's between rows).
SPREADS = {row: spread for row, spread in between_spreads(assumptions.TABLE).items()
           if row in CHANGES}  # fmt: skip


def changed_rig(constant: str | None, size: float, rig: Mapping = RIG) -> dict:
    """The twin's effects (``rig``) with a constant moved by ``size`` (a share, or in its
    unit)."""
    hidden = copy.deepcopy(dict(rig))
    if constant is None:
        return hidden
    effect, parameter, relative = CHANGES[constant]
    value = hidden.get(effect, {}).get(parameter, 0.0)
    hidden[effect] = {parameter: value * (1.0 + size) if relative else value + size}
    return hidden


def write(folder: Path, base: Mapping, strides: int, seed: int, mean_cycle_deg, rig: Rig,
          changed: Mapping[int, dict] = {}, effects: Mapping = RIG) -> Path:  # fmt: skip
    """The twin's recordings of every spring of the validation protocol, trial i with the
    effects ``changed[i]`` where given (and its own noise stream), else the session's rig
    (``effects``)."""
    config = recordings.twin_config(base, effects, strides, seed)
    trials = list(twin.simulate_trials(mean_cycle_deg, rig, phantom.settings(config), {}))
    for index, hidden in changed.items():
        spring = float(recordings.SPRINGS_N_PER_M[index])
        own = recordings.twin_config(base, hidden, strides, seed + 7919 * (index + 1))
        own["phantom"]["protocol"].update(springs_N_per_m=[spring], test_order_N_per_m=[spring])
        trials[index] = next(twin.simulate_trials(mean_cycle_deg, rig, phantom.settings(own), {}))
    twin.write_recordings(trials, folder, {"rule": "validation"}, 1)
    return folder / "manifest.csv"


def observations(base: Mapping, strides: int, seed: int, mean_cycle_deg, swing_fraction: float,
                 changed: Mapping[int, dict] = {}, effects: Mapping = RIG):  # fmt: skip
    """The engine's observations and noise scales of :func:`write`'s recordings."""
    rig = Rig()
    config = recordings.twin_config(base, effects, strides, seed)
    with tempfile.TemporaryDirectory() as tmp:
        manifest = write(Path(tmp), base, strides, seed, mean_cycle_deg, rig, changed, effects)
        parts = recordings.engine_parts(
            recordings.chain_tables(manifest, config, swing_fraction, rig)
        )
    block = phantom.settings(config)
    settings = {**block["discrepancy"], "engine": config["discrepancy"], "seed": seed}
    return discrepancy.observations(parts, settings, rig, block["chain"])


def run_case(index: int, base: Mapping, mean_cycle_deg, swing_fraction: float,
             strides_choices) -> list[dict]:  # fmt: skip
    """One case: no change, or one constant changed in one trial
    (:func:`exobench.selection.drawn_change`); a row per constant tested."""
    seed = int(base["seed"]) * 100_003 + index
    rng = np.random.default_rng([seed, 31])
    strides = int(rng.choice(strides_choices))
    constant, trial, size = selection.drawn_change(rng, SPREADS, len(recordings.SPRINGS_N_PER_M))
    changed = {} if constant is None else {trial: changed_rig(constant, size)}
    data, scales = observations(base, strides, seed, mean_cycle_deg, swing_fraction, changed)
    engine = selection.Settings.from_config(base["discrepancy"], seed)
    return validation.stability_case(
        "phantom",
        index,
        seed,
        discrepancy.problem(),
        data,
        scales,
        engine,
        RIG,
        data.trial,
        (constant, trial, size),
    )
