"""Independent check of the closed-loop kinematics: a serial chain of homogeneous transforms.

Nothing here reuses :mod:`exobench.sts.kinematics`: joint frames are built by multiplying 3×3
homogeneous matrices (a clockwise joint rotation, then a translation along the link), point
velocities come from the rigid-body relation v = Σ ω × r over the proximal joints and
accelerations from a = Σ (α × r + ω × (ω × r)), with 3-D cross products.
"""

from __future__ import annotations

import numpy as np

from exobench.sts.motion import Motion

# Sense of each joint's rotation (ankle φ3, knee φ2, hip φ1) along the chain, per convention: the
# study's eqs. (1)–(3) turn the knee the ankle's way and the hip against it; the corrected chain
# turns the knee against the ankle and the hip with it.
JOINT_SENSES = {"study": (1.0, 1.0, -1.0), "corrected": (1.0, -1.0, 1.0)}


def _rotation(angle: np.ndarray) -> np.ndarray:
    """Homogeneous 2-D rotation by −angle (the chain's joint angles turn clockwise)."""
    c, s = np.cos(angle), np.sin(angle)
    out = np.zeros((*angle.shape, 3, 3))
    out[..., 0, 0], out[..., 0, 1] = c, s
    out[..., 1, 0], out[..., 1, 1] = -s, c
    out[..., 2, 2] = 1.0
    return out


def _translation_along_link(length: float) -> np.ndarray:
    """Homogeneous translation by ``length`` along the local link axis (local +Y)."""
    out = np.eye(3)
    out[1, 2] = length
    return out


def _joint_values(values: np.ndarray, convention: str) -> np.ndarray:
    """Joint rotations along the chain (ankle, knee, hip) with their senses: (samples, 3)."""
    return values[:, ::-1] * np.array(JOINT_SENSES[convention])


def joint_frames(lengths_m: np.ndarray, motion: Motion, convention: str = "study") -> np.ndarray:
    """Positions of D, C, B, A (samples, 4, 2) as T = Π R(φ_i)·T(l_i) from the ankle up."""
    rotations = _joint_values(motion.q_rad, convention).T
    frame = np.broadcast_to(np.eye(3), (len(motion.t_s), 3, 3))
    origins = [frame[:, :2, 2]]
    for rotation, length in zip(rotations, lengths_m, strict=True):
        frame = frame @ _rotation(rotation) @ _translation_along_link(length)
        origins.append(frame[:, :2, 2])
    return np.stack(origins, axis=1)


def _cross_z(w: np.ndarray, r: np.ndarray) -> np.ndarray:
    """(ω ẑ) × r for planar r, through numpy's 3-D cross product."""
    w3 = np.stack([np.zeros_like(w), np.zeros_like(w), w], axis=-1)
    r3 = np.concatenate([r, np.zeros((*r.shape[:-1], 1))], axis=-1)
    return np.cross(w3, r3)[..., :2]


def point_motion(lengths_m: np.ndarray, motion: Motion, convention: str = "study"):
    """Positions, velocities, accelerations of C, B, A from frames and rigid-body relations."""
    origins = joint_frames(lengths_m, motion, convention)
    rates = _joint_values(motion.qd_rad_per_s, convention)
    accels = _joint_values(motion.qdd_rad_per_s2, convention)
    # absolute angular velocity/acceleration of each link about +z (clockwise joints: minus)
    omega = -np.cumsum(rates, axis=1)
    alpha = -np.cumsum(accels, axis=1)
    links = np.diff(origins, axis=1)
    link_velocity = _cross_z(omega, links)
    link_acceleration = _cross_z(alpha, links) + _cross_z(omega, link_velocity)
    return (
        origins[:, 1:],
        np.cumsum(link_velocity, axis=1),
        np.cumsum(link_acceleration, axis=1),
    )


def deviations(paths, lengths_m: np.ndarray, motion: Motion, convention: str = "study") -> dict:
    """Largest absolute difference between the two formulations per quantity (SI units)."""
    position, velocity, acceleration = point_motion(lengths_m, motion, convention)
    return {
        "max_position_deviation_m": float(np.max(np.abs(position - paths.position_m))),
        "max_velocity_deviation_m_per_s": float(np.max(np.abs(velocity - paths.velocity_m_per_s))),
        "max_acceleration_deviation_m_per_s2": float(
            np.max(np.abs(acceleration - paths.acceleration_m_per_s2))
        ),
    }
