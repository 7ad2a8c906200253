"""The corrected law: a sit-to-stand onto a chair, on the chain whose knee and hip turn the human
way (link angles CD φ3, BC φ3 − φ2, AB φ3 − φ2 + φ1), with the study's links and timing.

At the seat (the study's 1.5 s) the hip is at the seat's height h and the trunk leans forward by
the size of the study's own lean at that moment (the as-written reading's |φ2 + φ3 − φ1|); the
shank's forward tilt φ3 is the smallest at which the feet's centre of pressure
(:func:`exobench.sts.body.centre_of_pressure`) stays on the foot before the seat, the
cop_standing check itself: scanned upwards in 1° steps, then Brent's method on the first step
that reaches the heel's edge (where none does, the best tilt is kept and the check fails),
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
    """(φ1, φ2, φ3): φ3 the tilt, φ2 = φ3 + arccos((h − l_CD cos φ3)/l_BC), φ1 = λ − φ3 + φ2."""
    cosine = (seat_m - chain.l_CD_m * np.cos(ankle_rad)) / chain.l_BC_m
    knee = ankle_rad + np.arccos(np.clip(cosine, -1.0, 1.0))
    return np.array([lean_rad - ankle_rad + knee, knee, ankle_rad])


def points_of(chain: Chain, q: np.ndarray) -> np.ndarray:
    """C, B, A (m) of one posture."""
    still = Motion(np.zeros(1), q[None, :], np.zeros((1, 3)), np.zeros((1, 3)))
    return closed_loop(chain, still).position_m[0]


def knots(study: Law) -> tuple[float, ...]:
    """The corrected law's knots: upright, half-way to the seat, the seat, seated (s)."""
    return (0.0, 0.5 * study.seat_s, study.seat_s, study.knots_s[-1])


def heel_clearance_mm(law: Law, body: body_model.Body, heel_mm: float, rate_Hz: float) -> float:
    """Least x_p + heel before the hip reaches the seat (mm; negative: past the heel's edge)."""
    t = laws.time_grid(law, rate_Hz)
    points = closed_loop(law.chain, laws.sample(law, t)).position_m
    cop = body_model.centre_of_pressure(body, t, points)
    contact = body_model.contact_index(points[:, 1, 1], law.seat_height_mm / 1000.0)
    return float(1000.0 * cop[: len(t) if contact is None else contact].min() + heel_mm)


def corrected_law(
    name: str, study: Law, seat_mm: float, body: body_model.Body, heel_mm: float, rate_Hz: float
) -> Law:
    """The corrected law onto a seat ``seat_mm`` high, its shank tilt the root of the clearance."""
    signs = tuple(tuple(r) for r in CONVENTIONS["corrected"].tolist())
    chain = Chain.from_config(study.links_mm, signs)
    seat_m, lean = seat_mm / 1000.0, study_lean_rad(study)
    # the shank tilts from where the thigh is level to where it stands vertical above the knee
    low = float(np.arccos(min(1.0, seat_m / chain.l_CD_m))) if seat_m < chain.l_CD_m else 0.0
    high = float(np.arccos(max(-1.0, (seat_m - chain.l_BC_m) / chain.l_CD_m)))
    if len(study.knots_s) != 3:
        raise InputError(
            "config",
            "sts.study_law.knots_s",
            "three knots: upright, seat, seated",
            list(study.knots_s),
        )

    def built(ankle: float) -> Law:
        """The law with the shank tilted ``ankle`` at the seat."""
        at_seat = seat_posture(chain, seat_m, ankle, lean)
        midway = 0.5 * at_seat
        midway[0] = lean - midway[2] + midway[1]  # the trunk leads: its full lean at mid-descent
        seated = np.array([at_seat[1] - at_seat[2], at_seat[1], at_seat[2]])
        angles = np.vstack([np.zeros(3), midway, at_seat, seated])
        return Law(name, knots(study), angles, "min_jerk", study.seat_s, signs, 1,
                   dict(study.links_mm), "A", float(seat_mm))  # fmt: skip

    def clearance(ankle: float) -> float:
        """The law's heel clearance at the shank tilt ``ankle`` (mm)."""
        return heel_clearance_mm(built(ankle), body, heel_mm, rate_Hz)

    tilts = np.linspace(low, high, int(np.ceil(np.degrees(high - low))) + 1)  # 1° steps or finer
    margins = []
    for tilt in tilts:  # upwards to the first tilt that puts the centre of pressure on the foot
        margins.append(clearance(tilt))
        if margins[-1] >= 0.0:
            break
    if margins[-1] < 0.0 or len(margins) == 1:  # none does, or the least does: checked as it is
        return built(float(tilts[int(np.argmax(margins))]))
    from scipy.optimize import brentq  # here: the DAG build's config check imports this module

    xtol = 1e-9  # rad; the root's upper side, so the check's own rounding cannot put it outside
    return built(brentq(clearance, tilts[len(margins) - 2], tilts[len(margins) - 1], xtol=xtol)
                 + 2 * xtol)  # fmt: skip


def loaded_point_reach(
    chain: Chain,
    seat_mm: float,
    thigh_tolerance_deg: float,
    lean_max_deg: float,
    samples: int = 2001,
) -> dict:
    """A's farthest x_A = l_CD sin φ3 − l_BC cos θ + l_AB sin λ_max with |θ| ≤ tol (mm)."""
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
    """The corrected postures (deg), the hip's height and drop and the centre of mass (mm)."""
    chain = law.chain
    points = [points_of(chain, q) for q in law.angles_rad]
    seat = points[law.seat_index]
    thigh = seat[1] - seat[0]

    def posture(q: np.ndarray) -> dict:
        """One posture's coordinates in degrees, by name."""
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
            "forward shank tilt that keeps the feet's centre of pressure on the foot before the "
            "seat (the cop_standing check, Brent's method); the trunk upright again when "
            "seated; minimum-jerk segments"
        ),
    }


def configured_laws(sts: Mapping) -> dict[str, Law]:
    """The study's law, its minimum-jerk form, the corrected law on the chair and study's seat."""
    study = laws.study_law(sts)
    body = body_model.Body.from_config(sts["body"], sts["links_mm"])
    heel = float(sts["checks"]["foot"]["ankle_from_heel_mm"])
    rate = float(sts["sample_rate_Hz"])
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
        "corrected": corrected_law("corrected", study, seat_mm, body, heel, rate),
        "corrected_study_seat": corrected_law(
            "corrected_study_seat", study, study_seat_mm, body, heel, rate
        ),
    }


def chair_laws(sts: Mapping) -> dict[str, Law]:
    """The corrected law at the chair range's two ends (``sts.corrected.chair_range_mm``)."""
    study = laws.study_law(sts)
    body = body_model.Body.from_config(sts["body"], sts["links_mm"])
    heel, rate = float(sts["checks"]["foot"]["ankle_from_heel_mm"]), float(sts["sample_rate_Hz"])
    return {
        f"corrected, {h:g} mm chair": corrected_law(
            f"corrected, {h:g} mm chair", study, float(h), body, heel, rate
        )
        for h in sts["corrected"]["chair_range_mm"]
    }
