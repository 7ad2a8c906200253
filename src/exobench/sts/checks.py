"""The motion laws checked against what the study itself says and against balance.

Each check is one row per law (:data:`COLUMNS`): the quantity, its value, the range expected,
the decision ("holds" within the range, "violated" outside) and, for a violated row of a law on
the study's chain, the part of eqs. (1)–(4) that produces the departure. Forward is the way the
knee travels (+x). The study's words decide the trunk's lean (its direction and size over the
descent, upright again when seated) and the hip's path (quasi-elliptic, its curvature falling
towards the seat); anatomy decides the side of the shank the thigh ends on; balance, where the
study gives no number, decides the rest with the foot as bound: the loaded point A and the
centre of mass over the foot, the quasi-static joint moments per unit of body weight within
what a ground reaction inside the foot can give (ankle: W·x with x on the foot; knee and hip:
at most W times the farthest horizontal reach from the joint to the foot), and the centre of
pressure of the inverse dynamics (ankle moment / vertical ground force) on the foot.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass

import numpy as np
import pandas as pd

from exobench.sts import motion
from exobench.sts.kinematics import Chain, closed_loop
from exobench.sts.loads import JOINTS, Bodies, centre_of_mass_x, vertical_ground_force_N

COLUMNS = ["law", "check", "quantity", "value", "unit", "low", "high", "expected", "decision",
           "basis", "cause"]  # fmt: skip
POSTURES = {"upright": 0.0, "seat": motion.STAGE_END_S}
SIGN_OF_PHI2 = (
    "the sign of φ2 in eqs. (2)–(3): knee flexion turns the thigh forward, past the shank "
    "(φ2 + φ3), where a knee turns it back"
)
CAUSES = {  # check -> cause of a departure on the study's chain
    "lean_direction": SIGN_OF_PHI2 + "; the trunk's angle φ2 + φ3 − φ1 then falls behind the "
    "vertical as φ1 outgrows φ2 + φ3",
    "lean_size": "eq. (4): the amplitude of φ1 against φ2 + φ3",
    "upright_seated": "eq. (4): φ1's second stage",
    "knee_side": SIGN_OF_PHI2,
    "hip_path_inflections": SIGN_OF_PHI2,
    "hip_path_curvature": SIGN_OF_PHI2 + ": shank and thigh turn the same way, so the hip's "
    "path tightens towards the seat",
    "A_seat": SIGN_OF_PHI2 + ", carrying the hip and A in front of the toes",
    "com_seat": SIGN_OF_PHI2 + ", carrying the hip and A in front of the toes",
    "ankle_seat": SIGN_OF_PHI2 + " (the load's lever about the ankle)",
    "knee_seat": SIGN_OF_PHI2 + " (the load's lever about the knee)",
    "hip_seat": SIGN_OF_PHI2 + " (the load's lever about the hip)",
    "cop_descent": SIGN_OF_PHI2,
}


@dataclass(frozen=True)
class Settings:
    """The foot (ankle to heel and to toe, mm) and the lean thresholds (deg) of the checks."""

    heel_mm: float
    toe_mm: float
    slight_lean_max_deg: float
    upright_tolerance_deg: float

    @classmethod
    def from_config(cls, cfg: Mapping) -> Settings:
        """The ``sts.checks`` block."""
        foot = cfg["foot"]
        heel = float(foot["ankle_from_heel_mm"])
        return cls(heel, float(foot["length_mm"]) - heel, float(cfg["slight_lean_max_deg"]),
                   float(cfg["upright_tolerance_deg"]))  # fmt: skip

    @property
    def foot_text(self) -> str:
        return f"the foot, {-self.heel_mm:g} to {self.toe_mm:g} mm from the ankle"


def row(law: str, check: str, quantity: str, value: float, unit: str, low: float, high: float,
        expected: str, basis: str) -> dict:  # fmt: skip
    """One check: 'holds' when low ≤ value ≤ high, else 'violated' with its cause."""
    holds = bool(low <= value <= high)
    cause = ""
    if not holds and motion.law(law).convention == "study":
        cause = CAUSES.get(check, "not named")
    return {"law": law, "check": check, "quantity": quantity, "value": float(value),
            "unit": unit, "low": float(low), "high": float(high), "expected": expected,
            "decision": "holds" if holds else "violated", "basis": basis,
            "cause": cause}  # fmt: skip


def sample_at(frame: pd.DataFrame, t: float) -> int:
    """The sample index at time ``t``."""
    return int(np.argmin(np.abs(frame["t_s"].to_numpy(float) - t)))


def lean_deg(frame: pd.DataFrame) -> np.ndarray:
    """The trunk's lean from the vertical (forward +) from A and B, per sample."""
    forward = frame["xA_mm"].to_numpy(float) - frame["xB_mm"].to_numpy(float)
    up = frame["yA_mm"].to_numpy(float) - frame["yB_mm"].to_numpy(float)
    return np.degrees(np.arctan2(forward, up))


def hip_curvature(chain: Chain, at_seat: np.ndarray, samples: int = 401) -> np.ndarray:
    """Curvature κ = (x'y'' − y'x'')/|B'|³ (1/m) of the hip's path B(s) of the descent, where
    every law moves the coordinates as q = s·q_seat, s from 0 to 1 (derivatives in s from the
    closed loop with q̇ = q_seat, q̈ = 0)."""
    s = np.linspace(0.0, 1.0, samples)
    path = motion.Motion(s, s[:, None] * at_seat, np.tile(at_seat, (samples, 1)),
                         np.zeros((samples, 3)))  # fmt: skip
    paths = closed_loop(chain, path)
    d1, d2 = paths.velocity_m_per_s[:, 1], paths.acceleration_m_per_s2[:, 1]
    return (d1[:, 0] * d2[:, 1] - d1[:, 1] * d2[:, 0]) / np.hypot(*d1.T) ** 3


def words_checks(law: str, frame: pd.DataFrame, chain: Chain, settings: Settings) -> list[dict]:
    """The trunk's lean and the hip's path against the study's words; the knee's side."""
    lean = lean_deg(frame)
    descent = frame["t_s"].to_numpy(float) <= motion.STAGE_END_S
    largest = lean[descent][int(np.argmax(np.abs(lean[descent])))]
    seat = sample_at(frame, motion.STAGE_END_S)
    shank = frame.loc[seat, ["xC_mm", "yC_mm"]].to_numpy(float)
    thigh = frame.loc[seat, ["xB_mm", "yB_mm"]].to_numpy(float) - shank
    behind = (shank[0] * thigh[1] - shank[1] * thigh[0]) / np.hypot(*shank)
    q_seat = frame.loc[seat, ["phi1_rad", "phi2_rad", "phi3_rad"]].to_numpy(float)
    kappa = hip_curvature(chain, q_seat)
    turns = int(np.sum(np.diff(np.sign(kappa)) != 0))
    slight, upright = settings.slight_lean_max_deg, settings.upright_tolerance_deg
    words = "the study's words: the trunk "
    return [
        row(law, "lean_direction", "trunk's largest lean during the descent (forward +)",
            largest, "deg", 0.0, np.inf, "> 0 (forward)",
            words + "'initially leans slightly forward'"),
        row(law, "lean_size", "trunk's largest lean over the cycle, either way",
            float(np.max(np.abs(lean))), "deg", 0.0, slight, f"at most {slight:g}",
            words + f"leans 'slightly' (read as at most {slight:g}°: the study gives no number)"),
        row(law, "upright_seated", "trunk's lean seated (2 s)", lean[-1], "deg", -upright,
            upright, f"0 ± {upright:g}", words + "'returns to an upright posture'"),
        row(law, "knee_side", "hip's distance behind the shank's line at the seat (1.5 s)",
            behind, "mm", 0.0, np.inf, "> 0 (behind)",
            "anatomy: a knee flexes backwards, the thigh ends behind the shank"),
        row(law, "hip_path_inflections", "sign changes of the hip path's curvature, descent",
            turns, "1", 0.0, 0.0, "0", "the study's words: the hip's path is 'quasi-elliptic'"),
        row(law, "hip_path_curvature", "hip path's curvature at the seat over that at the start",
            abs(kappa[-1]) / abs(kappa[0]), "1", 0.0, 1.0, "below 1",
            "the study's words: its 'curvature decreases as the thigh approaches the seated "
            "configuration'"),
    ]  # fmt: skip


def balance_checks(law: str, frame: pd.DataFrame, loads: pd.DataFrame, bodies: Bodies,
                   settings: Settings) -> list[dict]:  # fmt: skip
    """A and the centre of mass over the foot, the joint moments per unit of body weight
    upright and at the seat, and the centre of pressure over the descent."""
    heel, toe, weight = settings.heel_mm, settings.toe_mm, bodies.design_load_N
    foot = f"{-heel:g} to {toe:g}"
    basis = f"balance: over {settings.foot_text} (a chosen foot: the study gives none)"
    positions = np.stack([frame[[f"x{p}_mm", f"y{p}_mm"]].to_numpy(float) for p in "CBA"], axis=1)
    com = centre_of_mass_x(bodies, positions)
    out = []
    for posture, t in POSTURES.items():
        k = sample_at(frame, t)
        when = f"{posture} ({t:g} s)"
        out.append(row(law, f"A_{posture}", f"loaded point A in front of the ankle, {when}",
                       frame.loc[k, "xA_mm"], "mm", -heel, toe, foot, basis))  # fmt: skip
        out.append(row(law, f"com_{posture}", f"centre of mass in front of the ankle, {when}",
                       com[k], "mm", -heel, toe, foot, basis))  # fmt: skip
        x_joint = {"ankle": 0.0, "knee": frame.loc[k, "xC_mm"], "hip": frame.loc[k, "xB_mm"]}
        for joint in JOINTS[::-1]:
            moment = loads.loc[k, f"{joint}_quasistatic_Nm"] / weight
            if joint == "ankle":
                low, high, said = -heel / 1000, toe / 1000, f"{-heel / 1000:g} to {toe / 1000:g}"
            else:
                reach = max(abs(toe - x_joint[joint]), abs(-heel - x_joint[joint])) / 1000
                low, high, said = -reach, reach, f"within ± {reach:.3f}"
            out.append(row(law, f"{joint}_{posture}",
                           f"{joint} extensor moment per unit of body weight, {when}", moment,
                           "m", low, high, said,
                           "body weight: the ground reaction (the design load) passes through "
                           f"{settings.foot_text}"))  # fmt: skip
    descent = (frame["t_s"] > 0.0) & (frame["t_s"] <= motion.STAGE_END_S)
    accelerations = np.stack([frame[[f"ax{p}_mm_per_s2", f"ay{p}_mm_per_s2"]].to_numpy(float)
                              for p in "CBA"], axis=1) / 1000.0  # fmt: skip
    ground = vertical_ground_force_N(bodies, accelerations)
    with np.errstate(divide="ignore", invalid="ignore"):
        cop = 1000.0 * loads["ankle_dynamic_Nm"].to_numpy(float) / ground
    outside = np.where(ground > 0.0, np.maximum(np.maximum(cop - toe, -heel - cop), 0.0), np.inf)
    out.append(
        row(
            law,
            "cop_descent",
            "centre of pressure's largest distance outside the foot, descent (0–1.5 s)",
            float(np.max(outside[descent.to_numpy()])),
            "mm",
            0.0,
            0.0,
            "0",
            f"balance: the inverse dynamics' centre of pressure on {settings.foot_text}",
        )
    )
    return out  # fmt: skip


def checks(trajectories: Mapping[str, pd.DataFrame], loads: pd.DataFrame, chains: Mapping,
           bodies: Bodies, settings: Settings) -> pd.DataFrame:  # fmt: skip
    """Every check for every law (:data:`COLUMNS`), laws in the order given."""
    rows = []
    for law, frame in trajectories.items():
        law_loads = loads[loads["law"] == law].reset_index(drop=True)
        chain = chains[motion.law(law).convention]
        rows += words_checks(law, frame, chain, settings)
        rows += balance_checks(law, frame, law_loads, bodies, settings)
    return pd.DataFrame(rows, columns=COLUMNS)
