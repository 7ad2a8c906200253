"""The checks of the motion laws: a departure drawn at random into the corrected laws is found
by its own check, the hip path's curvature is the trajectory's, the study's laws fail where the
issue says."""

from __future__ import annotations

import numpy as np
import pandas as pd
import pytest

import seeds
from exobench.sts import checks, corrected, kinematics, loads, motion

BODIES = loads.Bodies(1500.0, (1.0, 1.2, 1.5))
SETTINGS = checks.Settings(heel_mm=50.0, toe_mm=210.0, slight_lean_max_deg=30.0,
                           upright_tolerance_deg=5.0)  # fmt: skip
CHAINS = {c: kinematics.Chain(convention=c) for c in kinematics.CONVENTIONS}
MODULES = {j: dict.fromkeys(("preload_Nm", "stiffness_Nm_per_rad", "damping_Nms_per_rad"), 0.0)
           for j in loads.JOINTS}  # fmt: skip


def table_of(laws: dict[str, motion.Motion]) -> pd.DataFrame:
    """The checks of sampled laws, each on the chain its name's law runs on."""
    trajectories, parts = {}, []
    for law, sampled in laws.items():
        chain = CHAINS[motion.law(law).convention]
        trajectories[law] = kinematics.trajectory_table(
            sampled, kinematics.closed_loop(chain, sampled)
        )
        parts.append(loads.load_table(law, chain, BODIES, sampled, MODULES))  # fmt: skip
    return checks.checks(trajectories, pd.concat(parts, ignore_index=True), CHAINS, BODIES,
                         SETTINGS)  # fmt: skip


def test_a_departure_drawn_into_the_corrected_laws_is_found_by_its_check():
    seed = seeds.drawn("sts, a departure drawn into the corrected laws")
    rng = np.random.default_rng(seed)
    kind = str(rng.choice(["lean_back", "lean_far", "deeper", "none"]))
    size = float(np.radians(rng.uniform(10.0, 25.0)))
    t = motion.time_grid(200.0)
    at_seat, seated = corrected.postures(CHAINS["corrected"], BODIES, 0.05, 0.02)
    at_seat = at_seat.copy()
    if kind == "lean_back":  # the trunk leans back instead: φ1 smaller by twice the lean
        at_seat[0] -= 2 * corrected.study_lean_rad() + size
    elif kind == "lean_far":  # beyond 'slightly'
        at_seat[0] += np.radians(30.0) - corrected.study_lean_rad() + size
    elif kind == "deeper":  # the knee flexes further, past what balance allows
        at_seat[0] += size
        at_seat[1] += size
    table = table_of({"corrected": motion.min_jerk(t, at_seat, seated)}).set_index("check")
    violated = set(table.index[table["decision"] == "violated"])
    expected = {"lean_back": "lean_direction", "lean_far": "lean_size", "deeper": "com_seat",
                "none": None}[kind]  # fmt: skip
    assert (expected in violated) if expected else not violated, (kind, size, violated)
    assert (table["cause"] == "").all()  # no part of eqs. (1)-(4) is blamed on the corrected chain


def test_the_study_laws_fail_where_the_issue_says_and_name_the_sign():
    t = motion.time_grid(200.0)
    table = table_of({"piecewise": motion.piecewise(t)}).set_index("check")
    for check in ("lean_direction", "knee_side", "A_seat", "com_seat", "ankle_seat"):
        assert table.loc[check, "decision"] == "violated", check
        assert "sign of φ2" in table.loc[check, "cause"]
    for check in ("lean_size", "upright_seated", "A_upright", "com_upright"):
        assert table.loc[check, "decision"] == "holds", check


def test_the_hip_curvature_is_the_trajectorys():
    """κ of the hip's path from the closed loop in s equals the curvature of the sampled
    piecewise trajectory (constant rates in the first stage) by finite differences."""
    t = motion.time_grid(2000.0)
    sampled = motion.piecewise(t)
    paths = kinematics.closed_loop(CHAINS["study"], sampled).position_m[:, 1]
    first = t <= 1.5
    x, y = paths[first, 0], paths[first, 1]
    dx, dy = np.gradient(x, t[first]), np.gradient(y, t[first])
    ddx, ddy = np.gradient(dx, t[first]), np.gradient(dy, t[first])
    kappa_t = (dx * ddy - dy * ddx) / np.hypot(dx, dy) ** 3
    kappa_s = checks.hip_curvature(CHAINS["study"], sampled.q_rad[np.searchsorted(t, 1.5)], 301)
    # the same point of the path: s = t/1.5 (inner samples, away from the one-sided ends)
    for s in (0.2, 0.5, 0.8):
        k = int(np.argmin(np.abs(t[first] - 1.5 * s)))
        assert kappa_s[round(300 * s)] == pytest.approx(kappa_t[k], rel=1e-3)
