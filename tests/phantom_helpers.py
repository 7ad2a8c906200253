"""Small phantom configurations for fast tests."""

from __future__ import annotations

import copy

import numpy as np
import yaml

from conftest import REPO
from exobench import phantom
from exobench.reference import read_mean_cycle


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
