"""Sit-to-stand joint loads: statics by hand, a power balance, module tuning, the smooth gain."""

from __future__ import annotations

import numpy as np
import pandas as pd
import pytest

from exobench.sts import kinematics, loads, motion, smoothing, tuning

G = loads.GRAVITY_M_PER_S2


def _bodies(seed: int) -> loads.Bodies:
    rng = np.random.default_rng(seed)
    return loads.Bodies(float(rng.uniform(500, 2000)), tuple(rng.uniform(0.5, 3.0, 3).tolist()))


def test_quasi_static_torques_are_the_moments_of_the_weights_about_each_joint():
    bodies = _bodies(1)
    chain = kinematics.Chain()
    sampled = motion.piecewise(motion.time_grid(100.0))
    paths = kinematics.closed_loop(chain, sampled)
    x = np.concatenate([np.zeros((len(sampled.t_s), 1)), paths.position_m[..., 0]], axis=1)
    com = 0.5 * (x[:, :-1] + x[:, 1:])  # shank, thigh, trunk
    m = bodies.link_masses_kg
    # joint: (its x, flexion direction in x of the parts above it, weights above it)
    weights = {
        "ankle": (x[:, 0], 1.0, [(m[0], com[:, 0]), (m[1], com[:, 1]), (m[2], com[:, 2])]),
        "knee": (x[:, 1], 1.0, [(m[1], com[:, 1]), (m[2], com[:, 2])]),
        "hip": (x[:, 2], -1.0, [(m[2], com[:, 2])]),  # φ1 turns the trunk towards −x
    }
    torque = -loads.generalized_torques(chain, bodies, sampled, dynamic=False)
    for i, joint in enumerate(loads.JOINTS):
        x_joint, flexion, distal = weights[joint]
        expected = bodies.design_load_N * (x[:, 3] - x_joint)
        expected += sum(mass * G * (x_com - x_joint) for mass, x_com in distal)
        expected *= flexion
        np.testing.assert_allclose(torque[:, i], expected, atol=1e-9)


@pytest.mark.parametrize("convention", sorted(kinematics.CONVENTIONS))
def test_inverse_dynamics_balances_the_power_of_the_joints_with_the_energy_rate(convention):
    bodies = _bodies(2)
    chain = kinematics.Chain(convention=convention)
    t = motion.time_grid(4000.0)
    sampled = motion.smooth(t)
    paths = kinematics.closed_loop(chain, sampled)
    _, omega, _ = kinematics.link_angles(chain, sampled)
    v = np.concatenate([np.zeros((len(t), 1, 2)), paths.velocity_m_per_s], axis=1)
    y = np.concatenate([np.zeros((len(t), 1)), paths.position_m[..., 1]], axis=1)
    m = np.asarray(bodies.link_masses_kg)
    load_mass = bodies.design_load_N / G
    v_com = 0.5 * (v[:, :-1] + v[:, 1:])
    inertia = m * chain.lengths_m**2 / 12
    kinetic = 0.5 * load_mass * np.sum(v[:, -1] ** 2, axis=1)
    kinetic += np.sum(0.5 * m * np.sum(v_com**2, axis=2) + 0.5 * inertia * omega**2, axis=1)
    potential = load_mass * G * y[:, -1] + np.sum(m * G * 0.5 * (y[:, :-1] + y[:, 1:]), axis=1)
    energy_rate = np.gradient(kinetic + potential, t)
    power = np.sum(
        loads.generalized_torques(chain, bodies, sampled, dynamic=True) * sampled.qd_rad_per_s,
        axis=1,
    )
    inner = (t > 0.01) & (t < 1.99) & (np.abs(t - 1.5) > 0.01)
    scale = np.abs(power).max()
    np.testing.assert_allclose(power[inner], energy_rate[inner], atol=1e-4 * scale)


def test_centre_of_mass_and_ground_force_add_up_the_bodies():
    bodies = loads.Bodies(981.0, (1.0, 2.0, 3.0))  # 100 kg at A
    points = np.array([[[0.1, 0.4], [-0.2, 0.8], [0.0, 1.0]]])  # C, B, A
    middles = np.array([0.05, -0.05, -0.1])  # shank, thigh, trunk
    expected = (100 * 0.0 + middles @ np.array([1.0, 2.0, 3.0])) / 106.0
    assert loads.centre_of_mass_x(bodies, points)[0] == pytest.approx(expected)
    accelerations = np.array([[[0.0, 2.0], [0.0, 4.0], [0.0, -1.0]]])
    ay = np.array([1.0, 3.0, 1.5])  # link mid-points
    expected_force = 100 * (G - 1.0) + np.array([1.0, 2.0, 3.0]) @ (G + ay)
    assert loads.vertical_ground_force_N(bodies, accelerations)[0] == pytest.approx(expected_force)


def test_thigh_bending_follows_eq5_at_the_horizontal_thigh():
    chain = kinematics.Chain()
    bodies = loads.Bodies(1500.0, (0.0, 0.0, 0.0))
    horizontal = motion.Motion(
        np.zeros(1), np.array([[0.0, np.pi / 2, 0.0]]), np.zeros((1, 3)), np.zeros((1, 3))
    )
    bending, axial = loads.thigh_loads(chain, bodies, horizontal)
    assert bending[0] == pytest.approx(750.0)  # seed 001 eq. (5)
    assert axial[0] == pytest.approx(0.0, abs=1e-9)


def test_tuning_recovers_hidden_module_parameters():
    rng = np.random.default_rng(31)
    t = motion.time_grid(500.0)
    sampled = motion.smooth(t)
    hidden = {
        joint: {
            "preload_Nm": float(rng.uniform(0, 40)),
            "stiffness_Nm_per_rad": float(rng.uniform(50, 600)),
            "damping_Nms_per_rad": float(rng.uniform(1, 50)),
        }
        for joint in loads.JOINTS
    }
    required = loads.module_torques(sampled, hidden) + rng.normal(0, 0.5, (len(t), 3))
    bounds = {
        "lower": dict.fromkeys(tuning.PARAMETERS, 0.0),
        "upper": dict.fromkeys(tuning.PARAMETERS, 1000.0),
    }
    fit = tuning.tune(sampled, required, bounds)
    for joint in loads.JOINTS:
        assert fit[joint]["user_rms_Nm"] < 0.6
        for parameter in tuning.PARAMETERS:
            assert fit[joint][parameter] == pytest.approx(hidden[joint][parameter], abs=1.0)


def test_smooth_laws_remove_the_impulses_of_the_piecewise_laws():
    chain = kinematics.Chain()
    bodies = _bodies(3)
    t = motion.time_grid(1000.0)
    modules = {
        j: dict.fromkeys(("preload_Nm", "stiffness_Nm_per_rad", "damping_Nms_per_rad"), 0.0)
        for j in loads.JOINTS
    }
    trajectories, parts = {}, []
    for law, build in (("piecewise", motion.piecewise), ("smooth", motion.smooth)):
        sampled = build(t)
        trajectories[law] = kinematics.trajectory_table(
            sampled, kinematics.closed_loop(chain, sampled)
        )
        parts.append(loads.load_table(law, chain, bodies, sampled, modules))
    report = smoothing.compare(trajectories, pd.concat(parts, ignore_index=True))
    for joint in loads.JOINTS:
        assert report["gain"][f"peak_dynamic_torque_{joint}_Nm"]["reduction_pct"] > 90.0
    # the 1.5 s impulse of the knee is M(q)·Δφ̇, independent of the grid: check its sign and size
    knee = report["piecewise_impulses"]["1.5"]["knee_Nms"]
    assert knee != 0.0
    coarse = motion.time_grid(250.0)
    coarse_loads = loads.load_table("piecewise", chain, bodies, motion.piecewise(coarse), modules)
    k = int(np.searchsorted(coarse, 1.5))
    dt = coarse[1] - coarse[0]
    coarse_impulse = (coarse_loads["knee_dynamic_Nm"] - coarse_loads["knee_quasistatic_Nm"])[k] * dt
    assert coarse_impulse == pytest.approx(knee, rel=0.02)
