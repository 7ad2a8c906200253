"""Closed-vector-loop kinematics of the planar ankle–knee–hip–trunk chain (seed 001 eqs. 1–3).

Origin at the ankle D, X horizontal (forward: the way the knee travels), Y up; every link angle
is measured from the vertical, so a link of length l at absolute angle θ spans (l sin θ, l cos θ).
Two conventions map the joint coordinates to the link angles (:data:`CONVENTIONS`): the study's
eqs. (1)–(3) as written, CD (shank) θ = φ3, BC (thigh) θ = φ2 + φ3, AB (trunk) θ = φ2 + φ3 − φ1,
where knee flexion turns the thigh forward past the shank; and the corrected one, where knee
flexion turns the thigh back (θ = φ3 − φ2) and hip flexion the trunk forward (θ = φ3 − φ2 + φ1).
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass

import numpy as np
import pandas as pd

from exobench.sts.motion import COORDINATES, Motion

POINTS = ("C", "B", "A")
# Absolute link angles as combinations of (φ1, φ2, φ3): rows CD, BC, AB.
CONVENTIONS = {
    "study": np.array([[0.0, 0.0, 1.0], [0.0, 1.0, 1.0], [-1.0, 1.0, 1.0]]),
    "corrected": np.array([[0.0, 0.0, 1.0], [0.0, -1.0, 1.0], [1.0, -1.0, 1.0]]),
}


@dataclass(frozen=True)
class Chain:
    """Link lengths CD (shank), BC (thigh), AB (trunk) in metres (docs/rig.md §2)."""

    l_CD_m: float = 0.460
    l_BC_m: float = 0.500
    l_AB_m: float = 0.160
    convention: str | tuple = "study"

    @classmethod
    def from_config(cls, links_mm: Mapping, convention: str | tuple = "study") -> Chain:
        """Chain from the config's ``links_mm`` (l_CD, l_BC, l_AB in millimetres)."""
        lengths = (links_mm["l_CD"] / 1000.0, links_mm["l_BC"] / 1000.0, links_mm["l_AB"] / 1000.0)
        return cls(*lengths, convention)

    @property
    def lengths_m(self) -> np.ndarray:
        """Link lengths CD, BC, AB (m)."""
        return np.array([self.l_CD_m, self.l_BC_m, self.l_AB_m])

    @property
    def link_angle_matrix(self) -> np.ndarray:
        """Rows CD, BC, AB of link angles in (φ1, φ2, φ3): a named convention or given rows."""
        if not isinstance(self.convention, str):
            return np.array(self.convention, float)
        if self.convention not in CONVENTIONS:
            raise KeyError(f"unknown convention '{self.convention}': one of {sorted(CONVENTIONS)}")
        return CONVENTIONS[self.convention]


@dataclass(frozen=True)
class PointPaths:
    """Positions, velocities and accelerations of C, B, A: arrays (samples, 3 points, xy)."""

    position_m: np.ndarray
    velocity_m_per_s: np.ndarray
    acceleration_m_per_s2: np.ndarray


def link_angles(chain: Chain, motion: Motion) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Absolute angles θ of CD, BC, AB from the vertical and their first two derivatives."""
    matrix = chain.link_angle_matrix.T
    return motion.q_rad @ matrix, motion.qd_rad_per_s @ matrix, motion.qdd_rad_per_s2 @ matrix


def closed_loop(chain: Chain, motion: Motion) -> PointPaths:
    """Seed 001 eqs. (1)–(3) and their time derivatives for C, B and A, summed along the chain."""
    theta, omega, alpha = link_angles(chain, motion)
    sin, cos = np.sin(theta), np.cos(theta)
    lengths = chain.lengths_m
    link_position = np.stack([lengths * sin, lengths * cos], axis=-1)
    link_velocity = np.stack([lengths * cos * omega, -lengths * sin * omega], axis=-1)
    link_acceleration = np.stack(
        [
            lengths * (cos * alpha - sin * omega**2),
            -lengths * (sin * alpha + cos * omega**2),
        ],
        axis=-1,
    )
    return PointPaths(
        np.cumsum(link_position, axis=1),
        np.cumsum(link_velocity, axis=1),
        np.cumsum(link_acceleration, axis=1),
    )


def trajectory_table(motion: Motion, paths: PointPaths) -> pd.DataFrame:
    """Coordinates and the paths of C, B, A in millimetres with rates and accelerations."""
    columns = {"t_s": motion.t_s}
    for i, name in enumerate(COORDINATES):
        columns[f"{name}_rad"] = motion.q_rad[:, i]
        columns[f"{name}_rad_per_s"] = motion.qd_rad_per_s[:, i]
        columns[f"{name}_rad_per_s2"] = motion.qdd_rad_per_s2[:, i]
    for prefix, values, suffix in (
        ("", paths.position_m, "mm"),
        ("v", paths.velocity_m_per_s, "mm_per_s"),
        ("a", paths.acceleration_m_per_s2, "mm_per_s2"),
    ):
        for k, point in enumerate(POINTS):
            for j, axis in enumerate("xy"):
                columns[f"{prefix}{axis}{point}_{suffix}"] = 1000.0 * values[:, k, j]
    return pd.DataFrame(columns)


def motion_from_table(frame: pd.DataFrame) -> Motion:
    """The motion law stored in a trajectory table."""

    def block(suffix: str) -> np.ndarray:
        """The coordinates' columns with one suffix as an array."""
        return frame[[f"{name}_{suffix}" for name in COORDINATES]].to_numpy(float)

    return Motion(
        frame["t_s"].to_numpy(float), block("rad"), block("rad_per_s"), block("rad_per_s2")
    )
