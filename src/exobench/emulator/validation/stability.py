"""Validation of the parameter stability on the emulator's twin: a rig constant changed in one
trial, or in none.

The twin records each condition on its own: every condition with the session's rig (the
registry effects a real rig has: cuff compliance, transmission friction, motion capture's zero,
gain and clock), and the changed one, if any, with one constant of the assumption table's
``between`` rows moved (the cuffs' compliance by a share of itself, motion capture's zero by
some degrees, the torque sensor's zero by some N·m, added to its file as a re-zeroed sensor
records it). The analysis chain reads the files back as a lab's; the registry effects the twin
holds are fitted to all the data, as a right selection leaves them, and the parameter stability
compares the trials (:func:`exobench.selection.validation.stability_case` gives the rows).
"""

from __future__ import annotations

import copy
import tempfile
from collections.abc import Mapping
from pathlib import Path

import numpy as np

from exobench import selection
from exobench.emulator.model import assumptions, discrepancy
from exobench.emulator.twin import twin
from exobench.emulator.validation import twin_arm
from exobench.selection import validation
from exobench.selection.assumptions import between_spreads

# The registry effects the session's rig has, as the twin's switches set them.
RIG_EFFECTS = ("mocap_zero", "mocap_gain", "mocap_clock", "cuff_compliance",
               "transmission_friction")  # fmt: skip
# How each constant of a between row changes in a trial: the twin's setting (effect, key) and
# whether the change is a share of the session's value; the torque sensor's zero is added to the
# recorded torque.
CHANGES = {
    "straps_between": ("cuff_compliance", "compliance_deg_per_Nm", True),
    "mocap_zero_between": ("mocap_alignment", "zero_deg", False),
    "torque_zero_between": (None, "brace_torque_Nm", False),
}
# The visible spread between trials of each constant (the table's between rows).
SPREADS = {row: spread for row, spread in between_spreads(assumptions.TABLE).items()
           if row in CHANGES}  # fmt: skip


def session_config(emulator_block: Mapping) -> dict:
    """The emulator block of the session's rig: the validation protocol, the rig's effects as
    the config sets them, no soft-tissue artefact, no count drop, no late release."""
    cfg = twin_arm.base_config(emulator_block)
    for name in ("soft_tissue_artefact", "encoder_count_drop", "clutch_departure"):
        cfg["effects"][name]["enabled"] = False
    for name in ("cuff_compliance", "transmission_friction", "mocap_alignment"):
        cfg["effects"][name]["enabled"] = True
    return cfg


def write(folder: Path, cfg: Mapping, seed: int, changed: Mapping[int, tuple[str, float]] = {}):
    """The twin's recordings of every condition, condition i with ``changed[i]`` = (constant,
    size) where given (and its own noise stream), else the session's rig."""
    recs = twin.run(cfg, seed)
    protocol = cfg["protocol"]
    conditions = [(s, k) for s in protocol["speeds_m_per_s"]
                  for k in protocol["stiffnesses_Nm_per_rad"]]  # fmt: skip
    for index, (constant, size) in changed.items():
        effect, key, relative = CHANGES[constant]
        own = copy.deepcopy(dict(cfg))
        if effect is not None:
            value = own["effects"][effect][key]
            own["effects"][effect][key] = value * (1.0 + size) if relative else value + size
        speed, stiffness = conditions[index]
        rng = np.random.default_rng([seed, 7919, index])
        rec = twin.simulate(speed, stiffness, own, rng, recs[index].name)
        if effect is None:
            rec.brace[key] = rec.brace[key] + size
        recs[index] = rec
    twin.write_recordings(recs, folder)
    return folder / "manifest.csv"


def observations(cfg: Mapping, seed: int, folds: int, changed: Mapping = {}):
    """The engine's observations and noise scales of :func:`write`'s recordings."""
    with tempfile.TemporaryDirectory() as tmp:
        manifest = write(Path(tmp), cfg, seed, changed)
        parts = twin_arm.chain_parts(manifest, cfg, seed)
    controller = cfg["controller"]
    return discrepancy.observations(parts, controller["equilibrium_deg"],
                                    controller["direction_blend_deg_per_s"], cfg["transmission"],
                                    folds, controller["torque_filter_Hz"])  # fmt: skip


def run_case(index: int, emulator_block: Mapping, engine: Mapping, seed: int) -> list[dict]:
    """One case: no change, or one constant changed in one condition
    (:func:`exobench.selection.drawn_change`); a row per constant tested."""
    case_seed = int(seed) * 100_003 + index
    rng = np.random.default_rng([case_seed, 37])
    cfg = session_config(emulator_block)
    protocol = cfg["protocol"]
    conditions = len(protocol["speeds_m_per_s"]) * len(protocol["stiffnesses_Nm_per_rad"])
    constant, trial, size = selection.drawn_change(rng, SPREADS, conditions)
    changed = {} if constant is None else {trial: (constant, size)}
    data, scales = observations(cfg, case_seed, int(engine["folds"]), changed)
    settings = selection.Settings.from_config(engine, case_seed)
    return validation.stability_case(
        "emulator",
        index,
        case_seed,
        discrepancy.problem(discrepancy.drop_located(data)),
        data,
        scales,
        settings,
        RIG_EFFECTS,
        discrepancy.session_trials(data),
        (constant, trial, size),
    )
