"""What the seed's motion laws get wrong and the gain of smooth laws through the same postures.

The piecewise-linear laws of eq. (4) jump in rate at 0, 1.5 and 2 s; the jumps are impulses in
acceleration and in the inverse-dynamic joint torques. Their heights on a sampled grid are
impulse/Δt, so they are reported with the grid step and as grid-free impulses (N·m·s).
"""

from __future__ import annotations

import numpy as np
import pandas as pd

from exobench.sts.kinematics import POINTS
from exobench.sts.loads import JOINTS
from exobench.sts.motion import STAGE_END_S, rate_jumps


def jump_samples(t_s: np.ndarray) -> dict[str, int]:
    """Sample index of each rate jump of the piecewise laws (0, 1.5 and 2 s)."""
    return {"0.0": 0, "1.5": int(np.searchsorted(t_s, STAGE_END_S)), "2.0": len(t_s) - 1}


def _peaks(trajectory: pd.DataFrame, loads: pd.DataFrame) -> dict:
    """Peak accelerations of the points and coordinates, peak torques, dynamic increments.

    ``peak_dynamic_torque_between_jumps`` leaves out the jump samples of the piecewise laws:
    the torque the motion asks for away from its impulses.
    """
    out = {}
    between = np.ones(len(loads), dtype=bool)
    between[list(jump_samples(loads["t_s"].to_numpy(float)).values())] = False
    for point in POINTS:
        acc = np.hypot(trajectory[f"ax{point}_mm_per_s2"], trajectory[f"ay{point}_mm_per_s2"])
        out[f"peak_acceleration_{point}_m_per_s2"] = float(acc.max() / 1000.0)
    for i, joint in enumerate(JOINTS):
        out[f"peak_angular_acceleration_{joint}_rad_per_s2"] = float(
            trajectory[f"phi{i + 1}_rad_per_s2"].abs().max()
        )
        dynamic = loads[f"{joint}_dynamic_Nm"]
        out[f"peak_dynamic_torque_{joint}_Nm"] = float(dynamic.abs().max())
        out[f"peak_dynamic_torque_between_jumps_{joint}_Nm"] = float(
            dynamic.abs().to_numpy()[between].max()
        )
        out[f"peak_dynamic_increment_{joint}_Nm"] = float(
            (dynamic - loads[f"{joint}_quasistatic_Nm"]).abs().max()
        )
    return out


def _impulses(loads: pd.DataFrame) -> dict:
    """Angular impulse ∫(dynamic − quasi-static) dt of each joint over the sample of each jump."""
    t = loads["t_s"].to_numpy(float)
    dt = t[1] - t[0]
    return {
        event: {
            f"{joint}_Nms": float(
                (loads[f"{joint}_dynamic_Nm"] - loads[f"{joint}_quasistatic_Nm"]).iloc[k] * dt
            )
            for joint in JOINTS
        }
        for event, k in jump_samples(t).items()
    }


def compare(trajectories: dict[str, pd.DataFrame], loads: pd.DataFrame) -> dict:
    """Peaks of both laws, the piecewise impulses and the relative gain of the smooth laws."""
    peaks = {
        law: _peaks(trajectories[law], loads[loads["law"] == law].reset_index(drop=True))
        for law in ("piecewise", "smooth")
    }
    gain = {
        key: {
            "piecewise": peaks["piecewise"][key],
            "smooth": peaks["smooth"][key],
            "reduction_pct": 100.0 * (1.0 - peaks["smooth"][key] / peaks["piecewise"][key]),
        }
        for key in peaks["smooth"]
    }
    dt = float(np.diff(loads["t_s"].to_numpy(float)[:2])[0])
    return {
        "sample_step_s": dt,
        "rate_jumps_rad_per_s": rate_jumps(),
        "piecewise_impulses": _impulses(loads[loads["law"] == "piecewise"].reset_index(drop=True)),
        "peaks": peaks,
        "gain": gain,
        "note": (
            "Piecewise peaks sit on single samples: they equal impulse/step and grow without "
            "bound as the step shrinks; the smooth (minimum-jerk) peaks do not depend on the step."
        ),
    }
