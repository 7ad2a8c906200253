"""The checks every motion law goes through, the same for each reading of the study and for any
user's law file: one row per check (:data:`COLUMNS`) with its category, value, bounds, decision
and the source of its bounds.

Positions are in the law's forward frame (x the way the user faces). Categories:
- *words*: the study's words decide the trunk's lean (forward during the descent, slight,
  upright again when seated) and the hip's path (quasi-elliptic, its curvature falling towards
  the seat);
- *loading*: the study's loading case (Fig. 6b, eq. 5) has the thigh horizontal at the seat;
- *anatomy*: a knee flexes backwards, the thigh ends behind the shank; each joint stays within
  its range of motion (sourced bounds);
- *balance* under the seat model (:mod:`exobench.sts.body`): before the hip reaches the seat
  the feet carry the whole body, so its centre of mass (quasi-static) and its centre of pressure
  (with the segments' accelerations) lie on the foot; from contact on, seat and feet share the
  weight and the centre of mass lies over the sitting base, from the hip (the ischia on the
  seat) to the toes.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass

import numpy as np
import pandas as pd

from exobench.sts import body as body_model
from exobench.sts import motion
from exobench.sts.kinematics import closed_loop, trajectory_table

COLUMNS = [
    "law",
    "check",
    "category",
    "quantity",
    "value",
    "unit",
    "low",
    "high",
    "expected",
    "decision",
    "basis",
]
CATEGORIES = ("words", "loading", "anatomy", "balance")


@dataclass(frozen=True)
class Settings:
    """The foot (mm), the lean, thigh and joint-range thresholds (deg) and their sources."""

    heel_mm: float
    toe_mm: float
    slight_lean_max_deg: float
    upright_tolerance_deg: float
    thigh_tolerance_deg: float
    foot_source: str = "a chosen foot"
    range_of_motion: Mapping | None = None

    @classmethod
    def from_config(cls, cfg: Mapping) -> Settings:
        """The ``sts.checks`` block."""
        foot = cfg["foot"]
        heel = float(foot["ankle_from_heel_mm"])
        return cls(
            heel,
            float(foot["length_mm"]) - heel,
            float(cfg["slight_lean_max_deg"]),
            float(cfg["upright_tolerance_deg"]),
            float(cfg["thigh_horizontal_tolerance_deg"]),
            str(foot["source"]),
            dict(cfg["range_of_motion"]),
        )

    @property
    def foot_text(self) -> str:
        """The foot's extent from the ankle and its source, in words."""
        return (
            f"the foot, {-self.heel_mm:g} to {self.toe_mm:g} mm from the ankle ({self.foot_source})"
        )


def row(
    law: str,
    check: str,
    category: str,
    quantity: str,
    value: float,
    unit: str,
    low: float,
    high: float,
    expected: str,
    basis: str,
) -> dict:
    """One check: 'holds' when low ≤ value ≤ high, else 'violated'."""
    holds = bool(low <= value <= high)
    return {
        "law": law,
        "check": check,
        "category": category,
        "quantity": quantity,
        "value": float(value),
        "unit": unit,
        "low": float(low),
        "high": float(high),
        "expected": expected,
        "decision": "holds" if holds else "violated",
        "basis": basis,
    }


def forward_frame(frame: pd.DataFrame, facing: int) -> pd.DataFrame:
    """A trajectory table with its horizontal columns turned the way the user faces."""
    out = frame.copy()
    for column in out.columns:
        if column.startswith(("xC", "xB", "xA", "vxC", "vxB", "vxA", "axC", "axB", "axA")):
            out[column] = facing * out[column]
    return out


def sample_at(frame: pd.DataFrame, t: float) -> int:
    """The sample index at time ``t``."""
    return int(np.argmin(np.abs(frame["t_s"].to_numpy(float) - t)))


def lean_deg(frame: pd.DataFrame) -> np.ndarray:
    """The trunk's lean from the vertical (forward +) from A and B, per sample."""
    forward = frame["xA_mm"].to_numpy(float) - frame["xB_mm"].to_numpy(float)
    up = frame["yA_mm"].to_numpy(float) - frame["yB_mm"].to_numpy(float)
    return np.degrees(np.arctan2(forward, up))


def hip_curvature(frame: pd.DataFrame, seat_s: float, points: int = 51) -> np.ndarray:
    """Menger curvature κ = 2 (b − a) × (c − b)/(|b − a||c − b||c − a|) along equal arcs (1/m)."""
    descent = frame["t_s"].to_numpy(float) <= seat_s + 1e-9
    path = frame.loc[descent, ["xB_mm", "yB_mm"]].to_numpy(float) / 1000.0
    step = np.hypot(*np.diff(path, axis=0).T)
    keep = np.concatenate([[True], step > 0.0])
    path, arc = path[keep], np.concatenate([[0.0], np.cumsum(step[step > 0.0])])
    even = np.linspace(0.0, arc[-1], points)
    p = np.column_stack([np.interp(even, arc, path[:, 0]), np.interp(even, arc, path[:, 1])])
    a, b, c = p[:-2], p[1:-1], p[2:]
    ab, bc, ac = b - a, c - b, c - a
    cross = ab[:, 0] * bc[:, 1] - ab[:, 1] * bc[:, 0]
    return 2.0 * cross / (np.hypot(*ab.T) * np.hypot(*bc.T) * np.hypot(*ac.T))


def joint_angles_deg(frame: pd.DataFrame) -> dict[str, np.ndarray]:
    """Ankle dorsiflexion atan2(x_C, y_C) (foot flat), knee and hip flexion ∠(DC, CB), ∠(CB, BA)."""
    c, b, a = (frame[[f"x{p}_mm", f"y{p}_mm"]].to_numpy(float) for p in "CBA")

    def between(u: np.ndarray, v: np.ndarray) -> np.ndarray:
        """Unsigned angle from u to v per sample, |atan2(u × v, u · v)| (deg)."""
        cross, dot = u[:, 0] * v[:, 1] - u[:, 1] * v[:, 0], np.sum(u * v, axis=1)
        return np.degrees(np.abs(np.arctan2(cross, dot)))

    return {
        "ankle_dorsiflexion": np.degrees(np.arctan2(c[:, 0], c[:, 1])),
        "knee_flexion": between(c, b - c),
        "hip_flexion": between(b - c, a - b),
    }


def range_checks(law: str, frame: pd.DataFrame, settings: Settings) -> list[dict]:
    """Each joint's largest angle over the cycle against its sourced range of motion."""
    rom, angles = settings.range_of_motion, joint_angles_deg(frame)
    return [
        row(
            law,
            f"{joint}_range",
            "anatomy",
            f"largest {joint.replace('_', ' ')} over the cycle",
            float(np.max(angles[joint])),
            "deg",
            -np.inf,
            float(rom[joint]["max_deg"]),
            f"at most {rom[joint]['max_deg']:g}",
            f"anatomy: {joint.replace('_', ' ')}'s range ({rom[joint]['source']}; "
            f"sts.checks.range_of_motion.{joint})",
        )
        for joint in angles
    ]


def words_checks(law: str, frame: pd.DataFrame, seat_s: float, settings: Settings) -> list[dict]:
    """The lean and hip path against the words, the thigh against the loading, the knee's side."""
    lean = lean_deg(frame)
    descent = frame["t_s"].to_numpy(float) <= seat_s
    largest = lean[descent][int(np.argmax(np.abs(lean[descent])))]
    seat = sample_at(frame, seat_s)
    shank = frame.loc[seat, ["xC_mm", "yC_mm"]].to_numpy(float)
    thigh = frame.loc[seat, ["xB_mm", "yB_mm"]].to_numpy(float) - shank
    behind = (shank[0] * thigh[1] - shank[1] * thigh[0]) / np.hypot(*shank)
    thigh_deg = float(np.degrees(np.arctan2(abs(thigh[1]), abs(thigh[0]))))
    kappa = hip_curvature(frame, seat_s)
    turns = int(np.sum(np.diff(np.sign(kappa)) != 0))
    slight, upright = settings.slight_lean_max_deg, settings.upright_tolerance_deg
    words = "the study's words: the trunk "
    return [
        row(
            law,
            "lean_direction",
            "words",
            "trunk's largest lean before the seat (forward +)",
            largest,
            "deg",
            0.0,
            np.inf,
            "> 0 (forward)",
            words + "'initially leans slightly forward'",
        ),
        row(
            law,
            "lean_size",
            "words",
            "trunk's largest lean over the cycle, either way",
            float(np.max(np.abs(lean))),
            "deg",
            0.0,
            slight,
            f"at most {slight:g}",
            words + f"leans 'slightly' (read as at most {slight:g}°, sts.checks."
            "slight_lean_max_deg: the study gives no number)",
        ),
        row(
            law,
            "upright_seated",
            "words",
            "trunk's lean at the end (seated)",
            lean[-1],
            "deg",
            -upright,
            upright,
            f"0 ± {upright:g}",
            words + "'returns to an upright posture' "
            f"(within {upright:g}°, sts.checks.upright_tolerance_deg)",
        ),
        row(
            law,
            "hip_path_inflections",
            "words",
            "sign changes of the hip path's curvature, descent",
            turns,
            "1",
            0.0,
            0.0,
            "0",
            "the study's words: the hip's path is 'quasi-elliptic'",
        ),
        row(
            law,
            "hip_path_curvature",
            "words",
            "hip path's curvature at the seat over that at the start",
            abs(kappa[-1]) / abs(kappa[0]),
            "1",
            0.0,
            1.0,
            "below 1",
            "the study's words: its 'curvature decreases as the thigh approaches the seated "
            "configuration'",
        ),
        row(
            law,
            "thigh_at_seat",
            "loading",
            "thigh's angle from the horizontal at the seat",
            thigh_deg,
            "deg",
            0.0,
            settings.thigh_tolerance_deg,
            f"at most {settings.thigh_tolerance_deg:g}",
            "the study's loading case: the thigh horizontal at the seat (Fig. 6b, eq. 5), within "
            f"{settings.thigh_tolerance_deg:g}° (sts.checks.thigh_horizontal_tolerance_deg)",
        ),
        row(
            law,
            "knee_side",
            "anatomy",
            "hip's distance behind the shank's line at the seat",
            behind,
            "mm",
            0.0,
            np.inf,
            "> 0 (behind)",
            "anatomy: a knee flexes backwards, the thigh ends behind the shank",
        ),
    ]


def _outside(values: np.ndarray, low: np.ndarray | float, high: np.ndarray | float) -> float:
    """The largest distance of ``values`` outside [low, high] (0 when all inside; mm)."""
    if values.size == 0:
        return 0.0
    return float(np.max(np.maximum(np.maximum(values - high, low - values), 0.0)))


def balance_checks(
    law: str, frame: pd.DataFrame, body: body_model.Body, seat_mm: float, settings: Settings
) -> list[dict]:
    """Mass and pressure centres on the foot before the seat; mass over the sitting base after."""
    t = frame["t_s"].to_numpy(float)
    points = np.stack([frame[[f"x{p}_mm", f"y{p}_mm"]].to_numpy(float) for p in "CBA"], axis=1)
    com = 1000.0 * body_model.centre_of_mass(body, points / 1000.0)[:, 0]
    cop = 1000.0 * body_model.centre_of_pressure(body, t, points / 1000.0)
    contact = body_model.contact_index(points[:, 1, 1], seat_mm)
    standing = slice(0, len(t) if contact is None else contact)
    reached = "never" if contact is None else f"{t[contact]:g} s"
    heel, toe = settings.heel_mm, settings.toe_mm
    table = f"masses and centres: {body.source}"
    before = f"before the hip reaches the seat (reached: {reached})"
    seated = np.s_[len(t) :] if contact is None else np.s_[contact:]
    hip_x = points[seated, 1, 0]
    return [
        row(
            law,
            "com_standing",
            "balance",
            f"body's centre of mass outside the foot, {before}",
            _outside(com[standing], -heel, toe),
            "mm",
            0.0,
            0.0,
            "0",
            f"balance: the feet carry the whole body, so its centre of mass stays over "
            f"{settings.foot_text}; {table}",
        ),
        row(
            law,
            "cop_standing",
            "balance",
            f"centre of pressure outside the foot, {before}",
            _outside(cop[standing], -heel, toe),
            "mm",
            0.0,
            0.0,
            "0",
            f"balance: the feet's centre of pressure (the body's weight and accelerations) lies "
            f"on {settings.foot_text}; {table}",
        ),
        row(
            law,
            "com_seated",
            "balance",
            "body's centre of mass outside the sitting base (hip "
            f"to toes), from the seat's contact ({reached})",
            _outside(com[seated], hip_x, toe) if contact is not None else np.inf,
            "mm",
            0.0,
            0.0,
            "0",
            "balance: seat (under the hip) and feet share the weight, so the centre of "
            f"mass lies between the hip and the toes ({toe:g} mm, {settings.foot_text}); "
            f"{table}",
        ),
    ]


def law_checks(
    law, sampled: motion.Motion, body: body_model.Body, settings: Settings
) -> tuple[pd.DataFrame, pd.DataFrame]:
    """Every check of one law (:class:`exobench.sts.laws.Law`) and its forward-frame trajectory."""
    frame = forward_frame(trajectory_table(sampled, closed_loop(law.chain, sampled)), law.facing)
    seat_mm = law.seat_height_mm
    if seat_mm is None:
        seat_mm = float(frame.loc[sample_at(frame, law.seat_s), "yB_mm"])
    rows = words_checks(law.name, frame, law.seat_s, settings) + range_checks(
        law.name, frame, settings
    )
    rows += balance_checks(law.name, frame, body, seat_mm, settings)
    return pd.DataFrame(rows, columns=COLUMNS), frame
