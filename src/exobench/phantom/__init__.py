"""Phantom + passive knee exoskeleton (seed 000_b1875d82ee234a6a)."""

from collections.abc import Iterable, Mapping


def settings(config: Mapping) -> dict:
    """The phantom block of the workflow config with the global seed."""
    return {**config["phantom"], "seed": int(config["seed"])}


def trial_name(spring_N_per_m: float) -> str:
    """Trial identifier from the spring stiffness, e.g. k03400."""
    return f"k{round(spring_N_per_m):05d}"


def twin_trial_names(config: Mapping) -> list[str]:
    """Trial names the digital twin writes, in test order."""
    return [trial_name(k) for k in config["phantom"]["protocol"]["test_order_N_per_m"]]


def twin_files(trial_names: Iterable[str]) -> list[str]:
    """The files the twin writes for these trials (all it may overwrite)."""
    return ["manifest.csv", *(f"{name}.c3d" for name in trial_names)]
