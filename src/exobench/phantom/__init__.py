"""Phantom + passive knee exoskeleton (seed 000_b1875d82ee234a6a)."""

from collections.abc import Iterable, Mapping


def settings(config: Mapping) -> dict:
    """The phantom block of the workflow config with the global seed."""
    return {**config["phantom"], "seed": int(config["seed"])}


def trial_name(spring_N_per_m: float, repeat: int = 1, repeats: int = 1) -> str:
    """Trial name from the spring: k03400, or k03400_r2 for its second trial when repeated."""
    base = f"k{round(spring_N_per_m):05d}"
    return base if repeats == 1 else f"{base}_r{repeat}"


def twin_trials(config: Mapping) -> list[tuple[str, float, int]]:
    """(name, spring, repeat) per twin trial: the test order, or every repeat seeded-shuffled."""
    phantom = config["phantom"]
    repeats = int(phantom["protocol"]["trials"]["repeats"])
    order = [float(k) for k in phantom["protocol"]["test_order_N_per_m"]]
    trials = [(k, r) for r in range(1, repeats + 1) for k in order]
    if repeats > 1:
        import numpy as np

        shuffled = np.random.default_rng([int(config["seed"]), 2]).permutation(len(trials))
        trials = [trials[i] for i in shuffled]
    return [(trial_name(k, r, repeats), k, r) for k, r in trials]


def twin_trial_names(config: Mapping) -> list[str]:
    """Trial names the digital twin writes, in test order."""
    return [name for name, _, _ in twin_trials(config)]


def twin_files(trial_names: Iterable[str]) -> list[str]:
    """The files the twin writes for these trials (all it may overwrite)."""
    return ["manifest.csv", *(f"{name}.c3d" for name in trial_names)]
