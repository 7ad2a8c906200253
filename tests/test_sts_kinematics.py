"""Sit-to-stand kinematics: eqs. (1)–(4), the independent formulation and the smooth laws."""

from __future__ import annotations

import math

import numpy as np
import pytest
import yaml

from conftest import REPO
from exobench.errors import InputError
from exobench.sts import corrected, kinematics, laws, motion, verification

L_CD, L_BC, L_AB = 0.460, 0.500, 0.160  # docs/rig.md §2, metres
CONFIG = yaml.safe_load((REPO / "config" / "config.yaml").read_text())["sts"]
BUILT = corrected.configured_laws(CONFIG)


def seed_equations(t: float) -> dict[str, float]:
    """Seed 001 eqs. (1)–(4) typed out term by term for one instant (metres)."""
    if t <= 1.5:
        phi3, phi2, phi1 = 0.06 * math.pi * t, 0.25 * math.pi * t, 0.4 * math.pi * t
    else:
        phi3, phi2 = 0.09 * math.pi, 0.375 * math.pi
        phi1 = 0.6 * math.pi - 0.3 * math.pi * (t - 1.5)
    xC, yC = L_CD * math.sin(phi3), L_CD * math.cos(phi3)
    xB = xC + L_BC * math.sin(phi2 + phi3)
    yB = yC + L_BC * math.cos(phi2 + phi3)
    xA = xB + L_AB * math.sin(phi2 + phi3 - phi1)
    yA = yB + L_AB * math.cos(phi2 + phi3 - phi1)
    return {"xC": xC, "yC": yC, "xB": xB, "yB": yB, "xA": xA, "yA": yA}


def test_trajectories_match_the_seed_equations_to_numerical_precision():
    t = motion.time_grid(1000.0)
    paths = kinematics.closed_loop(kinematics.Chain(), motion.piecewise(t))
    rng = np.random.default_rng(7)
    for k in [*rng.choice(len(t), 25, replace=False).tolist(), 0, 1500, 2000]:
        expected = seed_equations(float(t[k]))
        for j, point in enumerate(kinematics.POINTS):
            assert paths.position_m[k, j, 0] == pytest.approx(expected[f"x{point}"], abs=1e-12)
            assert paths.position_m[k, j, 1] == pytest.approx(expected[f"y{point}"], abs=1e-12)


def test_trajectory_table_carries_the_issue_columns_in_millimetres():
    t = motion.time_grid(500.0)
    sampled = motion.piecewise(t)
    table = kinematics.trajectory_table(
        sampled, kinematics.closed_loop(kinematics.Chain(), sampled)
    )
    for column in ("t_s", "xC_mm", "yC_mm", "xB_mm", "yB_mm", "xA_mm", "yA_mm", "vxA_mm_per_s"):
        assert column in table.columns
    assert table["yA_mm"].iloc[0] == pytest.approx(1000 * (L_CD + L_BC + L_AB))
    back = kinematics.motion_from_table(table)
    np.testing.assert_array_equal(back.q_rad, sampled.q_rad)


def sampled_law(law: str, t: np.ndarray) -> tuple[kinematics.Chain, motion.Motion]:
    """A law of :data:`motion.LAWS` on its chain (the corrected laws from the shipped config)."""
    chain = kinematics.Chain(convention=motion.law(law).convention)
    if law.startswith("corrected"):
        return chain, laws.sample(BUILT[law], t)
    return chain, {"piecewise": motion.piecewise, "smooth": motion.smooth}[law](t)


@pytest.mark.parametrize("law", sorted(motion.LAWS))
def test_homogeneous_transforms_agree_with_the_closed_loop(law):
    t = motion.time_grid(1000.0)
    chain, sampled = sampled_law(law, t)
    deviation = verification.deviations(
        kinematics.closed_loop(chain, sampled), chain.lengths_m, sampled, chain.convention
    )
    assert deviation["max_position_deviation_m"] < 1e-9
    assert deviation["max_velocity_deviation_m_per_s"] < 1e-9
    assert deviation["max_acceleration_deviation_m_per_s2"] < 1e-6


def test_verification_detects_a_wrong_link_length():
    t = motion.time_grid(200.0)
    sampled = motion.smooth(t)
    chain = kinematics.Chain()
    wrong = chain.lengths_m + np.array([0.0, 1e-6, 0.0])
    deviation = verification.deviations(kinematics.closed_loop(chain, sampled), wrong, sampled)
    assert deviation["max_position_deviation_m"] > 5e-7


def test_smooth_velocities_and_accelerations_are_the_derivatives_of_the_paths():
    t = motion.time_grid(2000.0)
    paths = kinematics.closed_loop(kinematics.Chain(), motion.smooth(t))
    dt = t[1] - t[0]
    velocity = np.gradient(paths.position_m, dt, axis=0)
    acceleration = np.gradient(paths.velocity_m_per_s, dt, axis=0)
    # central differences, away from the ends and from the jerk step of φ1 at 1.5 s
    inner = (t > 0.002) & (t < 1.998) & (np.abs(t - 1.5) > 0.002)
    np.testing.assert_allclose(velocity[inner], paths.velocity_m_per_s[inner], atol=1e-5)
    np.testing.assert_allclose(acceleration[inner], paths.acceleration_m_per_s2[inner], atol=1e-4)


def test_smooth_laws_pass_the_seed_postures_at_rest():
    t = motion.time_grid(1000.0)
    smooth, piecewise = motion.smooth(t), motion.piecewise(t)
    for k in (0, 1500, 2000):
        np.testing.assert_allclose(smooth.q_rad[k], piecewise.q_rad[k], atol=1e-12)
        np.testing.assert_allclose(smooth.qd_rad_per_s[k], 0.0, atol=1e-12)
        np.testing.assert_allclose(smooth.qdd_rad_per_s2[k], 0.0, atol=1e-9)


def test_piecewise_jumps_are_impulses_whose_height_scales_with_the_rate():
    peaks = {}
    for rate in (500.0, 2000.0):
        t = motion.time_grid(rate)
        sampled = motion.piecewise(t)
        # the impulses integrate to the rate jumps of eq. (4)
        k = int(np.searchsorted(t, 1.5))
        jump = sampled.qdd_rad_per_s2[k] * (t[1] - t[0])
        np.testing.assert_allclose(jump, np.array([-0.7, -0.25, -0.06]) * np.pi, atol=1e-12)
        peaks[rate] = (
            np.abs(sampled.qdd_rad_per_s2).max(),
            np.abs(motion.smooth(t).qdd_rad_per_s2).max(),
        )
    assert peaks[2000.0][0] == pytest.approx(4 * peaks[500.0][0])
    assert peaks[2000.0][1] == pytest.approx(peaks[500.0][1], rel=1e-3)


def test_the_corrected_chain_bends_the_knee_back_and_the_hip_forward():
    """Written out for one posture: shank forward by φ3, thigh back by φ2 − φ3, trunk forward
    by φ3 − φ2 + φ1 (angles from the vertical, forward +)."""
    phi1, phi2, phi3 = 0.9, 0.7, 0.2
    still = motion.Motion(np.zeros(1), np.array([[phi1, phi2, phi3]]), np.zeros((1, 3)),
                          np.zeros((1, 3)))  # fmt: skip
    points = kinematics.closed_loop(kinematics.Chain(convention="corrected"), still).position_m[0]
    xC, xB = L_CD * math.sin(phi3), L_CD * math.sin(phi3) + L_BC * math.sin(phi3 - phi2)
    xA = xB + L_AB * math.sin(phi3 - phi2 + phi1)
    np.testing.assert_allclose(points[:, 0], [xC, xB, xA], atol=1e-12)
    with pytest.raises(KeyError, match="unknown convention"):
        kinematics.closed_loop(kinematics.Chain(convention="mirrored"), still)
    with pytest.raises(KeyError, match="unknown motion law"):
        motion.law("quadratic")


def test_the_study_law_as_data_samples_as_eq4_and_its_minimum_jerk_form():
    """The config's law file fields, sampled by exobench.sts.laws, give motion.py's eq. (4) and
    its minimum-jerk form sample by sample."""
    t = motion.time_grid(1000.0)
    for name, reference in (("piecewise", motion.piecewise), ("smooth", motion.smooth)):
        sampled, expected = laws.sample(BUILT[name], t), reference(t)
        for got, want in zip((sampled.q_rad, sampled.qd_rad_per_s, sampled.qdd_rad_per_s2),
                             (expected.q_rad, expected.qd_rad_per_s, expected.qdd_rad_per_s2),
                             strict=True):  # fmt: skip
            np.testing.assert_allclose(got, want, atol=1e-9)


def test_a_rate_without_a_sample_at_the_stage_change_is_refused():
    with pytest.raises(InputError, match=r"sts\.sample_rate_Hz"):
        motion.time_grid(333.0)
