"""Small emulator configurations for fast tests."""

from __future__ import annotations

import copy

import yaml

import seeds
from conftest import REPO
from exobench import emulator

DEFAULT = yaml.safe_load((REPO / "config" / "config.yaml").read_text())


def emulator_config(**effects: bool) -> dict:
    """The default emulator block with each named effect switched on or off."""
    cfg = copy.deepcopy(DEFAULT["emulator"])
    for name, enabled in effects.items():
        cfg["effects"][name]["enabled"] = enabled
    return cfg


def analysis_settings(cfg: dict) -> dict:
    """The analysis settings the workflow derives from an emulator block."""
    return emulator.analysis_settings({"emulator": cfg, "seed": 0})


def random_seed(name: str) -> int:
    """The seed of a drawn case (:func:`seeds.drawn`: fixed, or fresh under --explore)."""
    return seeds.drawn(name)


def contradicted(summary: str) -> list[str]:
    """The rows of summary.md's table of set against recovered values whose set value lies
    outside its interval, when the summary says nothing is left unexplained (else none): a
    verdict its own numbers contradict."""
    left = summary.split("## Left unexplained", 1)[1].lstrip()
    if not left.startswith("Nothing"):
        return []
    table = summary.split("## Set in the twin, recovered from its recordings", 1)[1]
    table = table.split("\n## ", 1)[0]
    return [
        line for line in table.splitlines() if line.startswith("| ") and line.endswith("| no |")
    ]
