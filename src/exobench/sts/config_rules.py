"""The sit-to-stand group's cross-field config checks (run with the others at the DAG build)."""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import replace

from exobench.sts import corrected, laws


def check(config: Mapping) -> None:
    """Sit-to-stand: a sample rate that puts a sample on every knot of every configured law."""
    study = laws.study_law(config["sts"])
    rate = float(config["sts"]["sample_rate_Hz"])
    for law in (study, replace(study, name="corrected", knots_s=corrected.knots(study))):
        laws.time_grid(law, rate)
