"""Small phantom configurations for fast tests."""

from __future__ import annotations

import copy

import numpy as np
import yaml

from conftest import REPO
from exobench import phantom
from exobench.phantom.reference import read_mean_cycle


def workflow_config() -> dict:
    return yaml.safe_load((REPO / "config" / "config.yaml").read_text())


def small_config(strides: int = 12, ramps: int = 1, seed: int = 0, **effects) -> dict:
    """Phantom settings with few strides; effects given as name -> value (None = disabled)."""
    config = copy.deepcopy(workflow_config())
    config["seed"] = seed
    block = config["phantom"]
    block["protocol"]["strides"] = strides
    block["protocol"]["ramp_strides"] = ramps
    for entry in block["twin"]["effects"].values():
        entry["enabled"] = False
    for name, value in effects.items():
        entry = block["twin"]["effects"][name]
        entry["enabled"] = value is not None
        if value is not None and isinstance(value, dict):
            entry.update(value)
        elif value is not None:
            key = next(k for k in entry if k != "enabled")
            entry[key] = value
    return config


def mean_cycle() -> np.ndarray:
    path = REPO / "raw" / "reference" / "phantom_knee_flexion_mean_cycle.csv"
    return read_mean_cycle(path)["knee_flexion_deg"].to_numpy()


def settings(config: dict) -> dict:
    return phantom.settings(config)


def swing_fraction() -> float:
    """The share of the stride at the reference cycle's peak flexion (as phantom_strides)."""
    from exobench.phantom import reference

    path = REPO / "raw" / "reference" / "phantom_knee_flexion_mean_cycle.csv"
    return reference.swing_fraction(read_mean_cycle(path))


def analyse_recordings(folder, config: dict, labels=None) -> dict:
    """Every trial of ``folder/manifest.csv`` through the workflow's stages in one process
    (:func:`exobench.phantom.validation.recordings.chain_tables`: acquisition with its glitch
    screening, filter, angles, strides, dynamics, kinetics, per-stride metrics): trial ->
    {"metrics", "strides", "qc"}."""
    from exobench.phantom.recordings import qc
    from exobench.phantom.rig import Rig
    from exobench.phantom.validation import recordings

    parts = recordings.chain_tables(folder / "manifest.csv", config, swing_fraction(), Rig(),
                                    labels)  # fmt: skip
    return {
        p["trial"]: {"metrics": p["metrics"], "strides": p["strides"],
                     "qc": qc.qc_table(p["trial"], p["events"], p["strides"])}
        for p in parts
    }  # fmt: skip
