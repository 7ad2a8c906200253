"""The emulator group's cross-field config checks (run with the others when the DAG is built)."""

from __future__ import annotations

from collections.abc import Mapping

from exobench.emulator.twin import gait
from exobench.errors import InputError
from exobench.plumbing.config_checks import SOURCE, check_names


def check(config: Mapping) -> None:
    """The emulator block's keys against each other, and the lab's column map."""
    check_emulator(config["emulator"], config["acquisition"] == "synthetic")
    check_names("emulator.columns", config["emulator"].get("columns", {}))


def check_emulator(block: Mapping, synthetic: bool) -> None:
    """Emulator protocol: a gait shape for every speed the twin simulates."""
    if not synthetic:
        return
    for speed in block["protocol"]["speeds_m_per_s"]:
        try:
            gait.shape_for(block["gait"]["shapes"], float(speed))
        except KeyError:
            raise InputError(
                SOURCE,
                "emulator.protocol.speeds_m_per_s, emulator.gait.shapes",
                "a gait shape for every speed of the protocol",
                speed,
            ) from None
