"""Inverse-dynamics stage: net knee moment from the ankle load cells (§2.4, docs/rig.md §1)."""

from __future__ import annotations

import pandas as pd

from exobench.phantom.chain import dynamics
from exobench.phantom.chain.angles import centres_from
from exobench.phantom.rig import ANALOG_RATE_HZ, LOAD_CELLS, Rig


def knee_kinetics(angles: pd.DataFrame, filtered: pd.DataFrame, rig: Rig) -> pd.DataFrame:
    """Net knee moment (extensor +), ankle forces, the moment's sensitivity to the vertical
    ankle force and its parts due to each segment's mass and inertia; the hip closes the planar
    system."""
    centres = centres_from(angles)
    bal = dynamics.balance(
        centres["hip"], centres["knee"], centres["ankle"], 1 / ANALOG_RATE_HZ, rig
    )
    vertical = filtered[[f"{name}_N" for name in LOAD_CELLS]].to_numpy().sum(1)
    moment, horizontal = dynamics.knee_moment(bal, vertical)
    thigh, shank = dynamics.segment_moments(bal)
    return pd.DataFrame(
        {
            "t_s": angles["t_s"].to_numpy(),
            "knee_moment_Nm": moment,
            "ankle_force_x_N": horizontal,
            "ankle_force_y_N": vertical,
            "moment_per_ankle_force_m": dynamics.moment_per_vertical_force(bal),
            "moment_from_thigh_Nm": thigh,
            "moment_from_shank_Nm": shank,
        }
    )
