"""The corrected law: a sit-to-stand onto a chair, on the chain whose knee and hip turn the human
way (link angles CD φ3, BC φ3 − φ2, AB φ3 − φ2 + φ1), with the study's links and timing.

At the seat (the study's 1.5 s) the hip is at the seat's height h and the trunk leans forward by
the size of the study's own lean at that moment (the as-written reading's |φ2 + φ3 − φ1|); the
shank's forward tilt φ3 is the smallest at which the body's centre of mass (anthropometric,
:mod:`exobench.sts.body`) stands ``margin`` in front of the heel's edge, solved by Brent's method,
and the knee flexion follows from the hip's height, φ2 = φ3 + arccos((h − l_CD cos φ3)/l_BC).
Seated (the last knot) the legs are still and the trunk is upright again, φ1 = φ2 − φ3. The
trunk leads the descent: half-way to the seat in time the legs are half-way in their
coordinates and the trunk already has its full lean. Quintic segments join the postures
(:func:`exobench.sts.laws.sample`). :func:`loaded_point_reach` states what the study's
loading (the whole weight at A) would need at the same seat.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import replace

import numpy as np
from scipy.optimize import brentq

from exobench.errors import InputError
from exobench.sts import body as body_model
from exobench.sts import laws
from exobench.sts.kinematics import CONVENTIONS, Chain, closed_loop
from exobench.sts.laws import LINKS, Law
from exobench.sts.motion import COORDINATES, Motion


def study_lean_rad(study: Law) -> float:
    """Size of the trunk's lean from the vertical in the study's posture at the seat (rad)."""
    return float(abs(CONVENTIONS["study"][2] @ study.angles_rad[study.seat_index]))


def seat_posture(chain: Chain, seat_m: float, ankle_rad: float, lean_rad: float) -> np.ndarray:
    """(φ1, φ2, φ3) with the shank tilted ``ankle_rad`` forward, the hip at ``seat_m`` and the
    trunk leaning ``lean_rad`` forward (module docstring)."""
    cosine = (seat_m - chain.l_CD_m * np.cos(ankle_rad)) / chain.l_BC_m
    knee = ankle_rad + np.arccos(np.clip(cosine, -1.0, 1.0))
    return np.array([lean_rad - ankle_rad + knee, knee, ankle_rad])


def points_of(chain: Chain, q: np.ndarray) -> np.ndarray:
    """C, B, A (m) of one posture."""
    still = Motion(np.zeros(1), q[None, :], np.zeros((1, 3)), np.zeros((1, 3)))
    return closed_loop(chain, still).position_m[0]


def corrected_law(
    name: str, study: Law, seat_mm: float, body: body_model.Body, heel_mm: float, margin_mm: float
) -> Law:
    """The corrected law onto a seat ``seat_mm`` high (module docstring), as a :class:`Law`."""
    signs = tuple(tuple(r) for r in CONVENTIONS["corrected"].tolist())
    chain = Chain.from_config(study.links_mm, signs)
    seat_m, lean = seat_mm / 1000.0, study_lean_rad(study)
    target = (margin_mm - heel_mm) / 1000.0
    # the shank tilts from where the thigh is level to where it stands vertical above the knee
    low = float(np.arccos(min(1.0, seat_m / chain.l_CD_m))) if seat_m < chain.l_CD_m else 0.0
    high = float(np.arccos(max(-1.0, (seat_m - chain.l_BC_m) / chain.l_CD_m)))

    def excess(ankle: float) -> float:
        points = points_of(chain, seat_posture(chain, seat_m, ankle, lean))
        return float(body_model.centre_of_mass(body, points)[0]) - target

    if not (excess(low) < 0.0 < excess(high)):
        raise InputError(
            "config",
            "sts.corrected",
            "a seat height and margin that a forward shank tilt brings over the foot",
            f"{seat_mm:g} mm, {margin_mm:g} mm",
        )
    at_seat = seat_posture(chain, seat_m, brentq(excess, low, high, xtol=1e-12), lean)
    if len(study.knots_s) != 3:
        raise InputError(
            "config",
            "sts.study_law.knots_s",
            "three knots: upright, seat, seated",
            list(study.knots_s),
        )
    midway = 0.5 * at_seat
    midway[0] = lean - midway[2] + midway[1]  # the trunk leads: its full lean at mid-descent
    seated = np.array([at_seat[1] - at_seat[2], at_seat[1], at_seat[2]])
    knots = (0.0, 0.5 * study.seat_s, study.seat_s, study.knots_s[-1])
    return Law(
        name,
        knots,
        np.vstack([np.zeros(3), midway, at_seat, seated]),
        "min_jerk",
        study.seat_s,
        signs,
        1,
        dict(study.links_mm),
        "A",
        float(seat_mm),
    )


def loaded_point_reach(
    chain: Chain,
    seat_mm: float,
    thigh_tolerance_deg: float,
    lean_max_deg: float,
    samples: int = 2001,
) -> dict:
    """The farthest forward the loaded point A can stand (mm from the ankle) with the hip at the
    seat, the thigh within the tolerance of horizontal and the trunk leaning at most
    ``lean_max_deg``: x_A = l_CD sin φ3 − l_BC cos θ + l_AB sin λ_max over the shank tilts that
    keep the thigh's angle θ above horizontal within the tolerance (hip above the knee)."""
    seat = seat_mm / 1000.0
    ankle = np.linspace(0.0, np.pi / 2, samples)
    rise = (seat - chain.l_CD_m * np.cos(ankle)) / chain.l_BC_m
    ok = np.abs(rise) <= np.sin(np.radians(thigh_tolerance_deg))
    hip_x = chain.l_CD_m * np.sin(ankle) - chain.l_BC_m * np.sqrt(np.clip(1 - rise**2, 0, 1))
    reach = hip_x + chain.l_AB_m * np.sin(np.radians(lean_max_deg))
    best = int(np.argmax(np.where(ok, reach, -np.inf)))
    return {
        "loaded_point_farthest_forward_mm": float(1000 * reach[best]),
        "at_shank_tilt_deg": float(np.degrees(ankle[best])),
        "hip_behind_ankle_mm": float(-1000 * hip_x[best]),
        "lean_max_deg": float(lean_max_deg),
        "seat_height_mm": float(seat_mm),
        "thigh_tolerance_deg": float(thigh_tolerance_deg),
    }


def summary(law: Law, body: body_model.Body, study: Law) -> dict:
    """The corrected postures in degrees, the hip's height and drop and the centre of mass at
    the seat (mm), beside the study's postures."""
    chain = law.chain
    points = [points_of(chain, q) for q in law.angles_rad]
    seat = points[law.seat_index]
    thigh = seat[1] - seat[0]

    def posture(q: np.ndarray) -> dict:
        return dict(zip(COORDINATES, np.degrees(q).tolist(), strict=True))

    return {
        "law": law.name,
        "signs": dict(zip(LINKS, [list(r) for r in law.signs], strict=True)),
        "seat_height_mm": law.seat_height_mm,
        "at_seat_deg": posture(law.angles_rad[law.seat_index]),
        "seated_deg": posture(law.angles_rad[-1]),
        "study_at_seat_deg": posture(study.angles_rad[study.seat_index]),
        "trunk_lean_at_seat_deg": float(np.degrees(study_lean_rad(study))),
        "thigh_from_horizontal_at_seat_deg": float(
            np.degrees(np.arctan2(abs(thigh[1]), abs(thigh[0])))
        ),
        "hip_height_standing_mm": float(1000 * points[0][1, 1]),
        "hip_height_at_seat_mm": float(1000 * seat[1, 1]),
        "hip_drop_mm": float(1000 * (points[0][1, 1] - seat[1, 1])),
        "centre_of_mass_at_seat_mm": float(1000 * body_model.centre_of_mass(body, seat)[0]),
        "method": (
            "the hip at the seat's height, the study's trunk lean turned forward, the smallest "
            "forward shank tilt that keeps the body's centre of mass over the foot (Brent's "
            "method); the trunk upright again when seated; minimum-jerk segments"
        ),
    }


def configured_laws(sts: Mapping) -> dict[str, Law]:
    """The laws of :data:`exobench.sts.motion.LAWS` from the ``sts`` block: the study's law, its
    minimum-jerk form, the corrected law onto the configured chair and onto the study's own seat
    (the hip's height at the study's seat knot), same links and timing."""
    study = laws.study_law(sts)
    body = body_model.Body.from_config(sts["body"], sts["links_mm"])
    heel = float(sts["checks"]["foot"]["ankle_from_heel_mm"])
    margin = float(sts["corrected"]["balance_margin_mm"])
    low, high = sts["corrected"]["chair_range_mm"]
    seat_mm = float(sts["corrected"]["seat_height_mm"])
    if not low <= seat_mm <= high:
        raise InputError(
            "config",
            "sts.corrected.seat_height_mm",
            f"a chair's seat height within sts.corrected.chair_range_mm, {low:g}-{high:g} mm",
            seat_mm,
        )
    study_seat_mm = 1000.0 * float(points_of(study.chain, study.angles_rad[study.seat_index])[1, 1])
    return {
        "piecewise": study,
        "smooth": replace(study, name="smooth", interpolation="min_jerk"),
        "corrected": corrected_law("corrected", study, seat_mm, body, heel, margin),
        "corrected_study_seat": corrected_law(
            "corrected_study_seat", study, study_seat_mm, body, heel, margin
        ),
    }
