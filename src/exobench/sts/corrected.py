"""The corrected laws: the study's links and timing on a chain whose knee and hip turn the human
way, through postures that the study's words and balance decide.

At the seat (1.5 s) the shank keeps the study's tilt φ3 = 0.09π and the trunk leans forward by
the size of the study's own lean at that moment, |φ2 + φ3 − φ1| = 0.135π; the knee flexion φ2
is the deepest at which the centre of mass (load at A and links) still stands over the foot,
``margin`` in front of the heel's edge (solved by Brent's method); the hip flexion follows from
the lean, φ1 = lean − φ3 + φ2. Seated (2 s) the legs are still and the trunk is upright again,
φ1 = φ2 − φ3. Minimum-jerk segments join the postures (:func:`exobench.sts.motion.min_jerk`).
"""

from __future__ import annotations

import numpy as np
from scipy.optimize import brentq

from exobench.errors import InputError
from exobench.sts import motion
from exobench.sts.kinematics import CONVENTIONS, Chain, closed_loop
from exobench.sts.loads import Bodies, centre_of_mass_x


def study_lean_rad() -> float:
    """Size of the trunk's lean from the vertical in the study's posture at the seat (rad)."""
    return float(abs(CONVENTIONS["study"][2] @ motion.STUDY_POSTURES[0]))


def seat_posture(knee_rad: float) -> np.ndarray:
    """(φ1, φ2, φ3) at the seat for a knee flexion: the study's shank, the study's lean forward."""
    ankle = motion.STUDY_POSTURES[0][2]
    return np.array([study_lean_rad() - ankle + knee_rad, knee_rad, ankle])


def com_x_m(chain: Chain, bodies: Bodies, q: np.ndarray) -> float:
    """Horizontal centre of mass of one posture (m)."""
    still = motion.Motion(np.zeros(1), q[None, :], np.zeros((1, 3)), np.zeros((1, 3)))
    return float(centre_of_mass_x(bodies, closed_loop(chain, still).position_m)[0])


def postures(chain: Chain, bodies: Bodies, heel_m: float, margin_m: float):
    """The corrected postures at the seat (1.5 s) and seated (2 s) (module docstring)."""
    if chain.convention != "corrected":
        raise ValueError("the corrected postures need the corrected chain")
    target = -heel_m + margin_m
    ankle = motion.STUDY_POSTURES[0][2]
    low, high = ankle, ankle + np.pi / 2  # thigh from vertical to horizontal

    def excess(knee: float) -> float:
        return com_x_m(chain, bodies, seat_posture(knee)) - target

    if excess(low) < 0.0 or excess(high) > 0.0:
        raise InputError(
            "config",
            "sts.corrected.balance_margin_mm",
            "a centre-of-mass target on the foot that a knee flexion between the thigh upright "
            "and horizontal reaches",
            f"{1000 * margin_m:g} mm in front of the heel",
        )
    knee = brentq(excess, low, high, xtol=1e-12)
    at_seat = seat_posture(knee)
    seated = np.array([knee - ankle, knee, ankle])
    return at_seat, seated


def summary(chain: Chain, bodies: Bodies, at_seat: np.ndarray, seated: np.ndarray) -> dict:
    """The corrected postures in degrees, the hip's drop from standing to the seat and the
    centre of mass at the seat (mm), beside the study's postures."""
    still = motion.Motion(np.zeros(2), np.stack([np.zeros(3), at_seat]), np.zeros((2, 3)),
                          np.zeros((2, 3)))  # fmt: skip
    points = closed_loop(chain, still).position_m
    names = motion.COORDINATES
    return {
        "at_seat_deg": dict(zip(names, np.degrees(at_seat).tolist(), strict=True)),
        "seated_deg": dict(zip(names, np.degrees(seated).tolist(), strict=True)),
        "study_at_seat_deg": dict(
            zip(names, np.degrees(motion.STUDY_POSTURES[0]).tolist(), strict=True)
        ),
        "trunk_lean_at_seat_deg": float(np.degrees(study_lean_rad())),
        "hip_height_standing_mm": float(1000 * points[0, 1, 1]),
        "hip_height_at_seat_mm": float(1000 * points[1, 1, 1]),
        "hip_drop_mm": float(1000 * (points[0, 1, 1] - points[1, 1, 1])),
        "centre_of_mass_at_seat_mm": float(1000 * centre_of_mass_x(bodies, points)[1]),
        "method": (
            "the study's shank tilt and the size of its trunk lean at the seat, the lean turned "
            "forward; the deepest knee flexion that keeps the centre of mass over the foot "
            "(Brent's method); the trunk upright again when seated"
        ),
    }
