"""One trial's whole chain in memory: acquisition, filtering, angles, strides, inverse dynamics
and the power partition, each stage's table kept for its own Parquet file (a per-trial job)."""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass
from pathlib import Path

import pandas as pd

from exobench.phantom.chain import angles, filtering, inverse_dynamics, kinetics, segmentation
from exobench.phantom.recordings import acquire, c3d, qc
from exobench.phantom.rig import Rig


@dataclass(frozen=True)
class TrialTables:
    """Every stage's table of one trial, in the chain's order."""

    markers: pd.DataFrame
    analog: pd.DataFrame
    events: pd.DataFrame
    filtered: pd.DataFrame
    angles: pd.DataFrame
    strides: pd.DataFrame
    qc: pd.DataFrame
    moments: pd.DataFrame
    kinetics: pd.DataFrame


def run(
    path: Path,
    row: Mapping,
    settings: Mapping,
    swing_fraction: float,
    rig: Rig,
    labels: Mapping[str, str] | None = None,
) -> TrialTables:
    """The chain of the trial in manifest ``row`` recorded in ``path``: ``settings`` holds the
    ``chain`` block and the protocol's ``stride_time_s`` and ``min_spring_force_N``."""
    chain, trial = settings["chain"], str(row["trial"])
    ramp = int(row["ramp_strides"])
    markers, analog, events = acquire.screened_trial(path, labels or {}, chain, rig)
    c3d.check_duration(path, len(markers), ramp, float(settings["stride_time_s"]))
    filtered = filtering.filter_trial(markers, analog, chain, str(path))
    ang = angles.knee_angles(filtered)
    strides = segmentation.segment(
        filtered, ang, ramp, swing_fraction, chain, float(settings["min_spring_force_N"]),
        f"trial {trial} ({path})",
    )  # fmt: skip
    moments = inverse_dynamics.knee_kinetics(ang, filtered, rig)
    return TrialTables(
        markers=markers,
        analog=analog,
        events=events,
        filtered=filtered,
        angles=ang,
        strides=strides,
        qc=qc.qc_table(trial, events, strides),
        moments=moments,
        kinetics=kinetics.kinetics_table(ang, moments, filtered, strides),
    )
