"""Angles stage: sagittal knee angles of phantom and exoskeleton, spring length (§2.4)."""

from __future__ import annotations

import numpy as np
import pandas as pd
from scipy.interpolate import CubicSpline

from exobench.phantom.chain.dynamics import cross

JOINTS = {"hip": "HIP", "knee": "KNEE", "ankle": "ANK"}
# The stage's own columns, its Parquet file: the joint centres are the filtered markers'
# midpoints (the filtered stage's file holds those markers; :func:`with_centres`).
OWN_COLUMNS = ["t_s", "phantom_knee_angle_rad", "exo_knee_angle_rad", "spring_length_m"]


def point(table: pd.DataFrame, label: str) -> np.ndarray:
    """Sagittal (x, y) path of a marker in m."""
    return table[[f"{label}_x_mm", f"{label}_y_mm"]].to_numpy(float) / 1000.0


def joint_centre(table: pd.DataFrame, joint: str) -> np.ndarray:
    """Joint centre = midpoint of the medial and lateral markers (docs/rig.md §1), in m."""
    return 0.5 * (point(table, f"PH_{joint}_MED") + point(table, f"PH_{joint}_LAT"))


def flexion(proximal: np.ndarray, distal: np.ndarray) -> np.ndarray:
    """Knee flexion (rad) between a proximal and a distal direction, both pointing distally."""
    return np.arctan2(-cross(proximal, distal), np.sum(proximal * distal, axis=-1))


def knee_angles(table: pd.DataFrame) -> pd.DataFrame:
    """Phantom and exoskeleton knee angles, spring length and joint centres per sample."""
    centres = {name: joint_centre(table, code) for name, code in JOINTS.items()}
    phantom = flexion(centres["knee"] - centres["hip"], centres["ankle"] - centres["knee"])
    thigh_bar = point(table, "EX_THIGH_DIST") - point(table, "EX_THIGH_PROX")
    shank_bar = point(table, "EX_SHANK_DIST") - point(table, "EX_SHANK_PROX")
    spring = point(table, "EX_SPRING_B") - point(table, "EX_SPRING_A")
    out = {
        "t_s": table["t_s"].to_numpy(),
        "phantom_knee_angle_rad": phantom,
        "exo_knee_angle_rad": flexion(thigh_bar, shank_bar),
        "spring_length_m": np.linalg.norm(spring, axis=-1),
    }
    for name, xy in centres.items():
        out[f"{name}_x_m"], out[f"{name}_y_m"] = xy[:, 0], xy[:, 1]
    return pd.DataFrame(out)


def with_centres(angles: pd.DataFrame, markers: pd.DataFrame) -> pd.DataFrame:
    """The angles table with its joint centres again, from the filtered stage's marker paths at
    their own rate (their cubic spline at the angles' times, as the chain draws them)."""
    times = angles["t_s"].to_numpy()
    columns = [f"PH_{code}_{side}_{axis}_mm" for code in JOINTS.values()
               for side in ("MED", "LAT") for axis in "xy"]  # fmt: skip
    paths = CubicSpline(markers["t_s"].to_numpy(), markers[columns].to_numpy(), axis=0)
    dense = pd.DataFrame(paths(times), columns=columns)
    out = {column: angles[column].to_numpy() for column in angles.columns}
    for name, code in JOINTS.items():
        xy = joint_centre(dense, code)
        out[f"{name}_x_m"], out[f"{name}_y_m"] = xy[:, 0], xy[:, 1]
    return pd.DataFrame(out)


def centres_from(table: pd.DataFrame) -> dict[str, np.ndarray]:
    """Joint-centre paths (n, 2) in m from an angles table."""
    return {name: table[[f"{name}_x_m", f"{name}_y_m"]].to_numpy() for name in JOINTS}
