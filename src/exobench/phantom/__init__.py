"""Phantom + passive knee exoskeleton (seed 000_b1875d82ee234a6a)."""

from collections.abc import Mapping


def settings(config: Mapping) -> dict:
    """The phantom block of the workflow config with the global seed."""
    return {**config["phantom"], "seed": int(config["seed"])}


def twin_trial_names(config: Mapping) -> list[str]:
    """Trial names the digital twin writes, in test order."""
    from exobench.phantom.twin import trial_name

    return [trial_name(k) for k in config["phantom"]["protocol"]["test_order_N_per_m"]]
