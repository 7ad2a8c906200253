"""Digital twin physics: rigid theory, energy flows of the series chain, ankle dynamics."""

from __future__ import annotations

import numpy as np
import pytest

from exobench.phantom import dynamics, metrics, twin
from exobench.phantom.rig import ANALOG_RATE_HZ, Rig
from phantom_helpers import mean_cycle, settings, small_config

DT = 1.0 / ANALOG_RATE_HZ
RIG = Rig()
CALIBRATED = {
    "k_interface_Nm_per_rad": 55.0,
    "c_interface_Nms_per_rad": 0.8,
    "k_frame_Nm_per_rad": 900.0,
    "friction_Nm": 0.6,
}


def simulate(config):
    return twin.simulate_trials(mean_cycle(), RIG, settings(config), CALIBRATED)


def stride_view(trial, column):
    strides = trial.truth["stride"].max() + 1
    return trial.truth[column].to_numpy().reshape(strides, -1)


def test_rigid_theory_when_all_effects_are_off():
    trials = simulate(small_config())
    for trial in trials:
        phantom = stride_view(trial, "phantom_knee_angle_rad")
        exo = stride_view(trial, "exo_knee_angle_rad")
        moment = stride_view(trial, "knee_moment_Nm")
        level = stride_view(trial, "clutch_level")
        force = stride_view(trial, "spring_force_N")
        np.testing.assert_array_equal(exo, phantom)
        k_theta = RIG.joint_stiffness(trial.spring_stiffness_N_per_m)
        start = phantom[:, :1]
        taut = (level == 1) & (force > 0)
        expected = k_theta * (phantom - start)
        np.testing.assert_allclose(moment[taut], expected[taut], atol=1e-9)
        assert taut.sum() > 0.25 * taut.size
        assert np.all(moment[level == 0] == 0.0)
        # While the clutch releases, the moment never exceeds the falling capacity.
        last_full = np.argmin(level == 1, axis=1) - 1
        held = np.abs(moment[np.arange(len(moment)), last_full])[:, None]
        releasing = (level > 0) & (level < 1)
        assert np.all(np.abs(moment[releasing]) <= (level * held)[releasing] + 1e-9)
        # k_θ of eq. (2.2) with RIG.md's r = 0.03 m, T/t = 5, k_tensioner = 0.1 N·m/rad.
        assert k_theta == pytest.approx((trial.spring_stiffness_N_per_m - 0.1 / 0.03**2) * 0.0225)


def test_rigid_theory_spring_force_and_length_follow_transmission():
    trial = simulate(small_config())[0]
    phantom = stride_view(trial, "phantom_knee_angle_rad")
    engaged = stride_view(trial, "engaged")
    force = stride_view(trial, "spring_force_N")
    extension = stride_view(trial, "spring_extension_m")
    rotation = np.where(engaged, phantom - phantom[:, :1], 0.0)
    taut = (force > 0) & (stride_view(trial, "clutch_level") == 1)
    np.testing.assert_allclose(extension[taut], 0.15 * rotation[taut], atol=1e-12)
    expected = 3.0 + trial.spring_stiffness_N_per_m * 0.15 * rotation
    np.testing.assert_allclose(force[taut], expected[taut], atol=1e-9)


def test_power_partition_matches_each_elements_constitutive_law():
    config = small_config(
        interface_compliance=CALIBRATED["k_interface_Nm_per_rad"],
        interface_damping=CALIBRATED["c_interface_Nms_per_rad"],
        frame_compliance=CALIBRATED["k_frame_Nm_per_rad"],
        frame_friction=CALIBRATED["friction_Nm"],
    )
    for trial in simulate(config)[::5]:
        get = {c: stride_view(trial, c) for c in trial.truth.columns}
        rest = 0.08
        powers = metrics.power_partition(
            get["knee_moment_Nm"],
            get["phantom_knee_angle_rad"],
            get["exo_knee_angle_rad"],
            get["spring_force_N"],
            rest + get["spring_extension_m"],
            DT,
        )
        np.testing.assert_allclose(
            powers["knee"], powers["exoskeleton"] + powers["interface"], rtol=0, atol=1e-12
        )
        np.testing.assert_allclose(
            powers["exoskeleton"], powers["frame"] + powers["spring"], rtol=0, atol=1e-12
        )
        # Interface (Kelvin–Voigt) absorbs k·δ·δ̇ + c·δ̇²: the delivered power is its negative.
        delta = get["interface_deflection_rad"]
        rate = metrics.rate(delta, DT)
        k, c = CALIBRATED["k_interface_Nm_per_rad"], CALIBRATED["c_interface_Nms_per_rad"]
        law = -(k * delta * rate + c * rate**2)
        peak = np.abs(powers["interface"]).max()
        full = get["clutch_level"] == 1
        inside = full & np.roll(full, 1, -1) & np.roll(full, -1, -1)
        assert np.abs(powers["interface"] - law)[inside].max() < 0.03 * peak
        # Frame: elastic energy of the frame, the tensioner and Coulomb friction.
        sigma = get["frame_deflection_rad"]
        s = get["spring_side_rotation_rad"]
        taut = inside & (get["spring_force_N"] > 0)
        n2kt = RIG.chain_ratio**2 * RIG.tensioner_stiffness_Nm_per_rad
        s_rate = metrics.rate(s, DT)
        absorbed = (
            CALIBRATED["k_frame_Nm_per_rad"] * sigma * metrics.rate(sigma, DT)
            - n2kt * s * s_rate
            - 3.0 * 0.15 * s_rate
            + CALIBRATED["friction_Nm"] * np.abs(s_rate)
        )
        peak = np.abs(powers["frame"]).max()
        assert np.abs(powers["frame"] + absorbed)[taut].max() < 0.05 * peak


def test_interface_and_frame_soften_the_joint_as_in_series():
    """Twin's true stiffnesses: exo = series(k_θ, k_f); phantom = series(k_θ, k_f, k_i)."""
    k_i, k_f = 60.0, 1200.0
    config = small_config(strides=20, interface_compliance=k_i, frame_compliance=k_f)
    for trial in simulate(config)[1::3]:
        get = {c: stride_view(trial, c) for c in trial.truth.columns}
        signals = {
            "phantom_knee_angle_rad": get["phantom_knee_angle_rad"],
            "exo_knee_angle_rad": get["exo_knee_angle_rad"],
            "knee_moment_Nm": get["knee_moment_Nm"],
            "spring_force_N": get["spring_force_N"],
        }
        protocol = settings(config)["protocol"]
        powers = metrics.power_partition(
            *(signals[c] for c in metrics.SIGNALS), get["spring_extension_m"], DT
        )
        per = metrics.stride_metrics(signals, powers, DT, protocol)
        keep = per["peak_spring_force_N"] > 5.0
        k_theta = RIG.joint_stiffness(trial.spring_stiffness_N_per_m)
        exo = 1.0 / (1.0 / k_theta + 1.0 / k_f)
        phantom = 1.0 / (1.0 / exo + 1.0 / k_i)
        assert np.median(per["exo_stiffness_Nm_per_rad"][keep]) == pytest.approx(exo, rel=0.02)
        assert np.median(per["phantom_stiffness_Nm_per_rad"][keep]) == pytest.approx(
            phantom, rel=0.02
        )


def test_ankle_forces_carry_the_knee_moment_through_newton_euler():
    config = small_config(interface_compliance=60.0)
    trial = simulate(config)[0]
    theta = trial.truth["phantom_knee_angle_rad"].to_numpy()
    paths = twin.leg_paths(theta, RIG)
    bal = dynamics.balance(paths["hip"], paths["knee"], paths["ankle"], DT, RIG)
    moment, horizontal = dynamics.knee_moment(bal, trial.truth["ankle_force_y_N"].to_numpy())
    np.testing.assert_allclose(moment, trial.truth["knee_moment_Nm"], atol=1e-9)
    np.testing.assert_allclose(horizontal, trial.truth["ankle_force_x_N"], atol=1e-9)
    summed = sum(trial.analogs[f"LC_ANKLE_{i}"] for i in (1, 2, 3))
    np.testing.assert_allclose(summed, trial.truth["ankle_force_y_N"], atol=1e-9)


def test_static_leg_gravity_balance():
    """Held still with no moment, the ankle carries the shank's and part of the thigh's weight."""
    theta = np.full(50, np.deg2rad(30.0))
    paths = twin.leg_paths(theta, RIG)
    bal = dynamics.balance(paths["hip"], paths["knee"], paths["ankle"], DT, RIG)
    fx, fy = dynamics.ankle_force(bal, np.zeros_like(theta))
    g = 9.81
    hip, knee, ankle = (paths[k][0] for k in ("hip", "knee", "ankle"))
    com1 = hip + RIG.thigh_com_m * (knee - hip) / np.linalg.norm(knee - hip)
    com2 = knee + RIG.shank_com_m * (ankle - knee) / np.linalg.norm(ankle - knee)
    depth = hip[1] - ankle[1]
    # Leg about the hip: d·Fx = g·Σ m_i (x_Gi − x_H).
    expected_fx = (
        g
        * (RIG.thigh_mass_kg * (com1[0] - hip[0]) + RIG.shank_mass_kg * (com2[0] - hip[0]))
        / depth
    )
    # Shank about the knee: (x_A − x_K)·Fy − (y_A − y_K)·Fx = m2·g·(x_G2 − x_K).
    expected_fy = (
        RIG.shank_mass_kg * g * (com2[0] - knee[0]) + (ankle[1] - knee[1]) * expected_fx
    ) / (ankle[0] - knee[0])
    assert fx[25] == pytest.approx(expected_fx, rel=1e-9)
    assert fy[25] == pytest.approx(expected_fy, rel=1e-9)
    weight = (RIG.thigh_mass_kg + RIG.shank_mass_kg) * g
    assert 0.0 < fy[25] < weight


def test_twin_is_deterministic_and_seeded():
    first = simulate(small_config(marker_noise=0.3, occlusion={"gaps_per_marker_per_min": 5}))
    again = simulate(small_config(marker_noise=0.3, occlusion={"gaps_per_marker_per_min": 5}))
    other = simulate(small_config(seed=1, marker_noise=0.3))
    a, b = first[0].markers_mm["PH_KNEE_LAT"], again[0].markers_mm["PH_KNEE_LAT"]
    np.testing.assert_array_equal(a, b)
    assert np.isnan(np.concatenate([m for m in first[0].markers_mm.values()])).any()
    assert not np.allclose(
        first[0].truth["phantom_knee_angle_rad"], other[0].truth["phantom_knee_angle_rad"]
    )
    # The programmed trajectories are shared by every spring (seed 000 §2.3).
    np.testing.assert_array_equal(
        first[0].truth["phantom_knee_angle_rad"], first[3].truth["phantom_knee_angle_rad"]
    )


def test_trajectory_perturbations_have_the_programmed_spread():
    config = small_config(strides=400, ramps=0)
    flexion = np.rad2deg(twin.programmed_flexion(mean_cycle(), settings(config)))
    peaks = flexion[:, 200:400].max(1)
    assert np.std(peaks) == pytest.approx(4.0, rel=0.15)
    assert np.mean(peaks) == pytest.approx(
        mean_cycle().max(initial=0, where=np.arange(2000) < 400), abs=0.8
    )
