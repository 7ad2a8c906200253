"""Joint torques of the sit-to-stand chain under the design load, and what the modules take over.

The design load F acts at A as the weight of a point mass F/g; the three links are uniform rods
with the configured masses. Generalized torques follow from virtual work,
Q = Σ_bodies Jᵀ m (a + g ŷ) + Σ_links I θ̈ ∂θ/∂φ (inverse dynamics; quasi-static: a = θ̈ = 0),
and are reported as extensor torques −Q, since the load flexes every joint.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass

import numpy as np
import pandas as pd

from exobench.sts.kinematics import Chain, closed_loop, link_angles
from exobench.sts.motion import Motion

GRAVITY_M_PER_S2 = 9.81
JOINTS = ("hip", "knee", "ankle")  # joint of φ1, φ2, φ3


@dataclass(frozen=True)
class Bodies:
    """Design load at A and link masses (shank CD, thigh BC, trunk/pelvis AB)."""

    design_load_N: float
    link_masses_kg: tuple[float, float, float]

    @classmethod
    def from_config(cls, cfg: Mapping) -> Bodies:
        masses = cfg["link_masses_kg"]
        return cls(float(cfg["design_load_N"]), (masses["CD"], masses["BC"], masses["AB"]))


def _link_jacobians(chain: Chain, theta: np.ndarray) -> np.ndarray:
    """∂(link vector)/∂φ: (samples, link, xy, coordinate)."""
    lengths = chain.lengths_m
    dvec = np.stack([lengths * np.cos(theta), -lengths * np.sin(theta)], axis=-1)
    return dvec[..., None] * chain.link_angle_matrix[None, :, None, :]


def generalized_torques(
    chain: Chain, bodies: Bodies, motion: Motion, *, dynamic: bool
) -> np.ndarray:
    """Generalized torques Q (samples, φ1..φ3) the joints apply, by virtual work (module doc)."""
    theta, _, alpha = link_angles(chain, motion)
    paths = closed_loop(chain, motion)
    jac_points = np.cumsum(_link_jacobians(chain, theta), axis=1)  # C, B, A
    jac_proximal = np.concatenate([np.zeros_like(jac_points[:, :1]), jac_points[:, :-1]], axis=1)
    jac_com = 0.5 * (jac_proximal + jac_points)
    gravity = np.array([0.0, GRAVITY_M_PER_S2])
    acc_points = paths.acceleration_m_per_s2 if dynamic else np.zeros_like(paths.position_m)
    acc_proximal = np.concatenate([np.zeros_like(acc_points[:, :1]), acc_points[:, :-1]], axis=1)
    acc_com = 0.5 * (acc_proximal + acc_points) + gravity
    masses = np.asarray(bodies.link_masses_kg)
    q_links = np.einsum("l,nlx,nlxi->ni", masses, acc_com, jac_com)
    load_mass = bodies.design_load_N / GRAVITY_M_PER_S2
    q_load = load_mass * np.einsum("nx,nxi->ni", acc_points[:, -1] + gravity, jac_points[:, -1])
    if not dynamic:
        return q_links + q_load
    inertia = masses * chain.lengths_m**2 / 12.0
    q_rotation = (inertia * alpha) @ chain.link_angle_matrix
    return q_links + q_load + q_rotation


def module_torques(motion: Motion, modules: Mapping) -> np.ndarray:
    """Extensor torque of each spring–damper module: preload + k·φ + c·φ̇ (samples, φ1..φ3)."""
    params = np.array(
        [
            [
                modules[j]["preload_Nm"],
                modules[j]["stiffness_Nm_per_rad"],
                modules[j]["damping_Nms_per_rad"],
            ]
            for j in JOINTS
        ]
    )
    return params[:, 0] + params[:, 1] * motion.q_rad + params[:, 2] * motion.qd_rad_per_s


def thigh_loads(chain: Chain, bodies: Bodies, motion: Motion) -> tuple[np.ndarray, np.ndarray]:
    """Bending moment and axial compression of the thigh at the knee from F at the hip (eq. 5)."""
    theta_thigh = link_angles(chain, motion)[0][:, 1]
    force = bodies.design_load_N
    return force * chain.l_BC_m * np.abs(np.sin(theta_thigh)), force * np.cos(theta_thigh)


def load_table(law: str, chain: Chain, bodies: Bodies, motion: Motion, modules) -> pd.DataFrame:
    """Per-sample joint, module and user torques and thigh loads of one motion law."""
    quasi_static = -generalized_torques(chain, bodies, motion, dynamic=False)
    dynamic = -generalized_torques(chain, bodies, motion, dynamic=True)
    module = module_torques(motion, modules)
    bending, axial = thigh_loads(chain, bodies, motion)
    columns = {"law": law, "t_s": motion.t_s}
    for i, joint in enumerate(JOINTS):
        columns[f"{joint}_quasistatic_Nm"] = quasi_static[:, i]
        columns[f"{joint}_dynamic_Nm"] = dynamic[:, i]
        columns[f"{joint}_module_Nm"] = module[:, i]
        columns[f"{joint}_user_Nm"] = dynamic[:, i] - module[:, i]
    columns["thigh_bending_moment_Nm"] = bending
    columns["thigh_axial_force_N"] = axial
    return pd.DataFrame(columns)


def weights_N(bodies: Bodies) -> np.ndarray:
    """Weights of the shank, thigh and trunk links and of the design load at A (N)."""
    return np.append(np.asarray(bodies.link_masses_kg) * GRAVITY_M_PER_S2, bodies.design_load_N)


def _body_points(points: np.ndarray) -> np.ndarray:
    """Mid-points of CD, BC, AB and the point A from C, B, A: (..., 4, xy)."""
    joints = np.concatenate([np.zeros_like(points[..., :1, :]), points], axis=-2)
    return np.concatenate([0.5 * (joints[..., :-1, :] + joints[..., 1:, :]), points[..., -1:, :]],
                          axis=-2)  # fmt: skip


def centre_of_mass_x(bodies: Bodies, positions: np.ndarray) -> np.ndarray:
    """Horizontal centre of mass x = Σ W_i x_i / Σ W_i of the links (mid-points) and the load
    at A, from the positions of C, B, A (samples, 3, xy)."""
    weights = weights_N(bodies)
    return _body_points(positions)[..., 0] @ weights / weights.sum()


def vertical_ground_force_N(bodies: Bodies, accelerations: np.ndarray) -> np.ndarray:
    """Vertical ground reaction R_y = Σ m_i (g + a_y,i) of the links and the load (samples)."""
    masses = weights_N(bodies) / GRAVITY_M_PER_S2
    return (GRAVITY_M_PER_S2 + _body_points(accelerations)[..., 1]) @ masses
