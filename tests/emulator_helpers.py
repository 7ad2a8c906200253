"""Small emulator configurations for fast tests."""

from __future__ import annotations

import copy

import yaml

from conftest import REPO

DEFAULT = yaml.safe_load((REPO / "config" / "config.yaml").read_text())


def emulator_config(**effects: bool) -> dict:
    """The default emulator block with each named effect switched on or off."""
    cfg = copy.deepcopy(DEFAULT["emulator"])
    for name, enabled in effects.items():
        cfg["effects"][name]["enabled"] = enabled
    return cfg


def analysis_settings(cfg: dict) -> dict:
    return {
        **cfg["analysis"],
        "velocity_cutoff_Hz": cfg["controller"]["velocity_cutoff_Hz"],
        "equilibrium_deg": cfg["controller"]["equilibrium_deg"],
        "direction_blend_deg_per_s": cfg["controller"]["direction_blend_deg_per_s"],
        "seed": 0,
    }
