"""Inverse-dynamics stage: net knee moment from the ankle load cells (§2.4, docs/rig.md §1)."""

from __future__ import annotations

import pandas as pd

from exobench.phantom.chain import dynamics
from exobench.phantom.chain.angles import centres_from
from exobench.phantom.rig import ANALOG_RATE_HZ, LOAD_CELLS, Rig


def knee_kinetics(angles: pd.DataFrame, filtered: pd.DataFrame, rig: Rig) -> pd.DataFrame:
    """Net knee moment (extensor +), ankle forces (the hip closes the planar system), and what
    the discrepancy engine's terms need: the moment's sensitivity to the vertical ankle force,
    to a hip moment, to each segment value (to second order in a centre of mass) and to the
    knee's centre off its axis, and the thigh's angle from the vertical and angular velocity."""
    centres = centres_from(angles)
    joints = centres["hip"], centres["knee"], centres["ankle"]
    bal = dynamics.balance(*joints, 1 / ANALOG_RATE_HZ, rig)
    vertical = filtered[[f"{name}_N" for name in LOAD_CELLS]].to_numpy().sum(1)
    moment, horizontal = dynamics.knee_moment(bal, vertical)
    values = dynamics.value_sensitivities(bal)
    curvatures = dynamics.value_curvatures(bal)
    return pd.DataFrame(
        {
            "t_s": angles["t_s"].to_numpy(),
            "knee_moment_Nm": moment,
            "ankle_force_x_N": horizontal,
            "ankle_force_y_N": vertical,
            "moment_per_ankle_force_m": dynamics.moment_per_vertical_force(bal),
            "moment_per_hip_moment_Nm_per_Nm": dynamics.moment_per_hip_moment(bal),
            "thigh_rate_rad_per_s": bal.thigh_rate,
            "thigh_angle_rad": bal.thigh_angle,
            **{f"moment_per_{key}_scale_Nm": values[key] for key in dynamics.SEGMENT_VALUES},
            **{f"moment_per_{key}_scale2_Nm": curvatures[key] for key in curvatures},
            "moment_per_knee_shift_Nm_per_m": dynamics.moment_per_knee_shift(
                *joints, 1 / ANALOG_RATE_HZ, rig, vertical
            ),
        }
    )
