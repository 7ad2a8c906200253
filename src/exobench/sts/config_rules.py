"""The sit-to-stand group's cross-field config checks (run with the others at the DAG build)."""

from __future__ import annotations

from collections.abc import Mapping

from exobench.sts import motion


def check(config: Mapping) -> None:
    """Sit-to-stand: a sample rate whose time grid holds the stage change (its own check)."""
    motion.time_grid(float(config["sts"]["sample_rate_Hz"]))
