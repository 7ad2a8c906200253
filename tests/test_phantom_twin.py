"""Digital twin physics: rigid theory, energy flows of the series chain, ankle dynamics."""

from __future__ import annotations

import numpy as np
import pytest

from exobench.errors import InputError
from exobench.phantom.chain import dynamics, metrics
from exobench.phantom.rig import ANALOG_RATE_HZ, Rig
from exobench.phantom.twin import trajectory, twin
from phantom_helpers import mean_cycle, settings, small_config

DT = 1.0 / ANALOG_RATE_HZ
RIG = Rig()
CALIBRATED = {
    "k_interface_Nm_per_rad": 55.0,
    "c_interface_Nms_per_rad": 0.8,
    "k_frame_Nm_per_rad": 900.0,
    "friction_Nm": 0.6,
    "k_drive_N_per_m": 60000.0,
}


def simulate(config):
    return list(twin.simulate_trials(mean_cycle(), RIG, settings(config), CALIBRATED))


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
        np.testing.assert_array_equal(phantom, stride_view(trial, "programmed_knee_angle_rad"))
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
        # k_θ of eq. (2.2) with docs/rig.md's r = 0.03 m, T/t = 5, k_tensioner = 0.1 N·m/rad.
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


@pytest.mark.parametrize(
    ("effects", "tolerance"),
    [({"interface_compliance": 60.0}, 1e-3), ({"drive_compliance": 60000.0}, 5e-3)],
    ids=["programmed motion", "compliant drive, rigid chain"],
)
def test_twin_lagrange_ankle_forces_carry_the_knee_moment_through_newton_euler(effects, tolerance):
    """The twin's ankle forces (Lagrange's equations, rates of the two segment angles) give the
    analysis's Newton–Euler (rates of the centre-of-mass paths) back the knee moment; the two
    derivations differ only by their central differences' error: ~0.05 mN·m on the programmed
    motion, ~2 mN·m where a compliant drive sharpens the motion at the clutch release."""
    config = small_config(**effects)
    trial = simulate(config)[0]
    theta = trial.truth["phantom_knee_angle_rad"].to_numpy()
    paths = twin.leg_paths(theta, RIG)
    bal = dynamics.balance(paths["hip"], paths["knee"], paths["ankle"], DT, RIG)
    moment, horizontal = dynamics.knee_moment(bal, trial.truth["ankle_force_y_N"].to_numpy())
    assert np.ptp(trial.truth["knee_moment_Nm"]) > 5.0
    np.testing.assert_allclose(moment, trial.truth["knee_moment_Nm"], rtol=0, atol=tolerance)
    np.testing.assert_allclose(horizontal, trial.truth["ankle_force_x_N"], rtol=0, atol=tolerance)
    summed = sum(trial.analogs[f"LC_ANKLE_{i}"] for i in (1, 2, 3))
    np.testing.assert_allclose(summed, trial.truth["ankle_force_y_N"], atol=1e-9)


def test_static_leg_gravity_balance():
    """Held still with no moment, the ankle carries the shank's and part of the thigh's weight
    (the analysis's Newton–Euler and the twin's Lagrange equations against hand statics)."""
    theta = np.full(50, np.deg2rad(30.0))
    paths = twin.leg_paths(theta, RIG)
    bal = dynamics.balance(paths["hip"], paths["knee"], paths["ankle"], DT, RIG)
    fx, fy = twin.ankle_force_N(paths["thigh"], paths["shank"], 0.0 * theta, DT, RIG)
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
    moment, horizontal = dynamics.knee_moment(bal, np.full_like(theta, expected_fy))
    assert moment[25] == pytest.approx(0.0, abs=1e-9)
    assert horizontal[25] == pytest.approx(expected_fx, rel=1e-9)
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


def test_prominent_peaks_follow_scipys_definition_on_random_signals_with_flat_tops():
    """The twin's own peak finder (no scipy.signal import in the twin) against
    scipy.signal.find_peaks as the oracle: random walks, half of them quantised so that flat
    tops and equal neighbours occur, at random prominence thresholds."""
    from scipy.signal import find_peaks

    rng = np.random.default_rng(20261123)
    for case in range(400):
        values = np.cumsum(rng.normal(size=int(rng.integers(3, 300))))
        if case % 2:
            values = np.round(values * rng.uniform(0.5, 3.0)) / 3.0
        prominence = float(rng.uniform(0.0, 3.0))
        expected = find_peaks(values, prominence=prominence)[0]
        np.testing.assert_array_equal(trajectory.prominent_peaks(values, prominence), expected)
    for short in ([], [1.0], [1.0, 2.0], [0, 3, 0], np.array([-128, 127, -128], np.int8)):
        expected = find_peaks(np.asarray(short, float), prominence=1.0)[0]
        np.testing.assert_array_equal(trajectory.prominent_peaks(short, 1.0), expected)
    with pytest.raises(ValueError, match="finite"):
        trajectory.prominent_peaks(np.array([0.0, 5.0, np.nan, 0.0]), 1.0)
    assert trajectory.cycle_extrema(mean_cycle()).size >= 3  # the boundary, a peak, a valley


def engaged_pairs(get):
    """Samples whose clutch is fully engaged at this and the previous sample (no clutch slip)."""
    full = get["clutch_level"] == 1
    both = full & np.roll(full, 1, -1)
    both[:, 0] = False
    return both


def step_change(values, pairs):
    """Change of a quantity from the previous sample, on the given sample pairs only."""
    return np.where(pairs, np.diff(values, prepend=0.0, axis=1), 0.0)


def element_work(moment, deflection, pairs):
    """Work M·Δ(deflection) the knee moment does on an element at each step."""
    return moment * step_change(deflection, pairs)


def test_every_element_balances_its_energy():
    """Work M·Δ(deflection) into each element = its stored energy change + what it dissipates."""
    k_i, beta, c_i, k_f, tau = 60.0, 30.0, 0.8, 900.0, 0.6
    config = small_config(
        interface_compliance=k_i,
        interface_stiffening=beta,
        interface_damping=c_i,
        frame_compliance=k_f,
        frame_friction=tau,
        transmission_play=0.01,
        drive_compliance=60000.0,
    )
    for trial in simulate(config)[::2]:
        get = {c: stride_view(trial, c) for c in trial.truth.columns}
        pairs = engaged_pairs(get)
        moment = get["knee_moment_Nm"]
        delta = get["interface_deflection_rad"]
        into = element_work(moment, delta, pairs)
        interface = step_change(k_i * (delta**2 / 2 + beta * delta**4 / 4), pairs)
        damping = c_i * step_change(delta, pairs) ** 2 / DT
        residual = into.sum() - interface.sum() - damping.sum()
        assert 0.0 <= residual < 0.01 * np.abs(into).sum()  # implicit Euler: a little, never < 0
        # Frame: backward-Euler work k·σₙ·Δσ = Δ(k·σ²/2) + k·Δσ²/2, nothing else.
        sigma = get["frame_deflection_rad"]
        frame = step_change(k_f * sigma**2 / 2, pairs) + k_f * step_change(sigma, pairs) ** 2 / 2
        assert element_work(moment, sigma, pairs).sum() == pytest.approx(frame.sum(), rel=1e-9)
        # Play: no moment while the chain is slack; work only in the step that takes it up.
        slack = get["chain_slack_rad"]
        play = element_work(moment, slack, pairs)
        assert np.all(slack[play != 0] == 0.01)
        assert np.abs(play).sum() < 1e-3 * np.abs(into).sum()
        # Spring side (taut branch, implicit step): M·Δs = k_θ·sₙ·Δs + τ·|Δs|, i.e. the change of
        # the spring energy k_θ·s²/2, its step term k_θ·Δs²/2 and the friction's dissipation.
        s = get["spring_side_rotation_rad"]
        k_theta = RIG.joint_stiffness(trial.spring_stiffness_N_per_m)
        taut = (get["spring_force_N"] > 0) & np.roll(get["spring_force_N"] > 0, 1, -1)
        ds = step_change(s, pairs & taut)
        into = moment * ds
        stored = step_change(k_theta * s**2 / 2, pairs & taut) + k_theta * ds**2 / 2
        friction = tau * np.abs(ds)
        np.testing.assert_allclose(into, stored + friction, atol=1e-12)
        assert friction.sum() > 0.05 * np.abs(into).sum()
        # Compatibility: the elements' deflections add up to the programme's rotation.
        total = sum(
            get[c]
            for c in (
                "drive_deflection_rad",
                "interface_deflection_rad",
                "frame_deflection_rad",
                "chain_slack_rad",
                "spring_side_rotation_rad",
            )
        )
        locked = get["programmed_knee_angle_rad"] - total
        full = get["clutch_level"] == 1
        spread = np.where(full, locked, np.nan)
        assert np.nanmax(np.nanmax(spread, 1) - np.nanmin(spread, 1)) < 1e-12


def test_interface_stiffening_raises_the_secant_stiffness():
    k_i, beta = 60.0, 40.0
    trial = simulate(small_config(interface_compliance=k_i, interface_stiffening=beta))[1]
    delta = trial.truth["interface_deflection_rad"].to_numpy()
    moment = trial.truth["knee_moment_Nm"].to_numpy()
    np.testing.assert_allclose(moment, k_i * (delta + beta * delta**3), atol=1e-9)
    loaded = np.abs(delta) > 0.01
    secant = moment[loaded] / delta[loaded]
    assert np.corrcoef(delta[loaded] ** 2, secant)[0, 1] > 0.99
    assert secant.max() > 1.1 * k_i


def test_stiffening_needs_interface_compliance():
    with pytest.raises(InputError, match=r"interface_stiffening.*interface_compliance"):
        simulate(small_config(interface_stiffening=10.0))


def test_transmission_play_passes_no_moment_for_the_first_play_rad():
    play = 0.03
    for trial in simulate(small_config(transmission_play=play))[::3]:
        get = {c: stride_view(trial, c) for c in trial.truth.columns}
        full = get["clutch_level"] == 1
        turned = get["phantom_knee_angle_rad"] - get["phantom_knee_angle_rad"][:, :1]
        k_theta = RIG.joint_stiffness(trial.spring_stiffness_N_per_m)
        expected = k_theta * np.maximum(turned - play, 0.0)
        np.testing.assert_allclose(get["knee_moment_Nm"][full], expected[full], atol=1e-9)
        assert np.all(get["knee_moment_Nm"][full & (turned < play)] == 0.0)
        assert (full & (turned > play)).sum() > 0.1 * full.sum()


def test_clutch_timing_delays_engagement():
    delay = 0.04
    trial = simulate(small_config(clutch_timing=delay))[2]
    get = {c: stride_view(trial, c) for c in trial.truth.columns}
    time = np.arange(get["knee_moment_Nm"].shape[1]) * DT
    early = time < delay - 1e-9
    assert np.all(get["knee_moment_Nm"][:, early] == 0.0)
    assert np.all(~get["engaged"][:, early]) and np.all(get["engaged"][:, ~early & (time < 0.5)])
    start = np.argmax(~early)
    turned = get["phantom_knee_angle_rad"] - get["phantom_knee_angle_rad"][:, start : start + 1]
    k_theta = RIG.joint_stiffness(trial.spring_stiffness_N_per_m)
    taut = (get["clutch_level"] == 1) & (get["spring_force_N"] > 0)
    np.testing.assert_allclose(get["knee_moment_Nm"][taut], k_theta * turned[taut], atol=1e-9)


def test_frame_friction_sticks_below_its_moment_and_slides_at_it():
    tau = 0.5
    trial = simulate(small_config(frame_friction=tau, interface_compliance=80.0))[1]
    get = {c: stride_view(trial, c) for c in trial.truth.columns}
    k_theta = RIG.joint_stiffness(trial.spring_stiffness_N_per_m)
    inside = engaged_pairs(get) & (get["spring_force_N"] > 0)
    excess = get["knee_moment_Nm"] - k_theta * get["spring_side_rotation_rad"]
    moving = inside & (np.abs(np.diff(get["spring_side_rotation_rad"], prepend=0.0, axis=1)) > 0)
    assert np.all(np.abs(excess[inside]) <= tau + 1e-9)
    np.testing.assert_allclose(np.abs(excess[moving]), tau, atol=1e-9)
    assert (inside & ~moving).sum() > 0  # it does stick


def test_drive_compliance_follows_its_definition():
    k_drive = 50000.0
    trial = simulate(small_config(drive_compliance=k_drive, interface_compliance=60.0))[1]
    programmed = trial.truth["programmed_knee_angle_rad"].to_numpy()
    l1, l2 = RIG.thigh_length_m, RIG.shank_length_m
    paths = twin.leg_paths(programmed, RIG)
    x_knee = paths["knee"][:, 0] - paths["hip"][:, 0]  # knee's distance from the hip–ankle line
    assert np.allclose(x_knee, l1 * l2 * np.sin(programmed) / (paths["hip"] - paths["ankle"])[:, 1])
    expected = programmed - trial.truth["knee_moment_Nm"].to_numpy() / (k_drive * x_knee**2)
    np.testing.assert_allclose(trial.truth["phantom_knee_angle_rad"], expected, atol=1e-12)
    # Against the programme's force with the exoskeleton disengaged, the ankle carries M/x_K.
    _, free = twin.ankle_force_N(paths["thigh"], paths["shank"], 0.0 * programmed, DT, RIG)
    moment = trial.truth["knee_moment_Nm"].to_numpy()
    extra = trial.truth["ankle_force_y_N"].to_numpy() - free
    loaded = np.abs(moment) > 2.0
    real = twin.leg_paths(trial.truth["phantom_knee_angle_rad"].to_numpy(), RIG)
    lever = (real["knee"] - real["hip"])[loaded, 0]
    ratio = extra[loaded] / (moment[loaded] / lever)
    assert np.median(np.abs(ratio - 1.0)) < 0.01  # the deflection's own weight and inertia aside


def stance_flexion_medians(trials):
    protocol = settings(small_config())["protocol"]
    medians = {}
    for trial in trials:
        get = {c: stride_view(trial, c)[1:-1] for c in metrics.SIGNALS}
        length = stride_view(trial, "spring_extension_m")[1:-1]
        powers = metrics.power_partition(*(get[c] for c in metrics.SIGNALS), length, DT)
        per = metrics.stride_metrics(get, powers, DT, protocol)
        medians[trial.spring_stiffness_N_per_m] = np.median(per["phantom_stance_flexion_deg"])
    return medians


def test_drive_compliance_lowers_phantom_stance_flexion_with_spring_stiffness():
    effects = {"interface_compliance": 60.0, "frame_compliance": 900.0}
    rigid = stance_flexion_medians(simulate(small_config(strides=16, **effects)))
    soft = stance_flexion_medians(
        simulate(small_config(strides=16, drive_compliance=50000.0, **effects))
    )
    springs = sorted(soft)
    drops = [rigid[k] - soft[k] for k in springs]
    assert all(np.diff(drops) > 0)  # a stiffer spring loads the drive more
    assert soft[springs[0]] - soft[springs[-1]] > 0.3
    assert abs(rigid[springs[0]] - rigid[springs[-1]]) < 1e-9  # same programme, no drive


def test_load_cell_offset_and_gain_change_only_the_spring_channel():
    offset, gain = 2.5, 1.07
    base = simulate(small_config())[0]
    trial = simulate(small_config(load_cell_offset=offset, load_cell_gain=gain))[0]
    force = trial.truth["spring_force_N"].to_numpy()
    np.testing.assert_allclose(trial.analogs["LC_SPRING"], gain * force + offset, atol=1e-12)
    for label in ("LC_ANKLE_1", "SYNC"):
        np.testing.assert_array_equal(trial.analogs[label], base.analogs[label])


@pytest.mark.parametrize("delay_s", [0.007, -0.0025])
def test_clock_offset_delays_every_analog_channel(delay_s):
    base = simulate(small_config())[0]
    trial = simulate(small_config(clock_offset=delay_s))[0]
    time = np.arange(trial.truth.shape[0]) * DT
    inner = (time > 0.05) & (time < time[-1] - 0.05)
    for label in ("LC_SPRING", "LC_ANKLE_2", "SYNC"):
        expected = np.interp(time - delay_s, time, base.analogs[label])
        np.testing.assert_allclose(trial.analogs[label][inner], expected[inner], atol=1e-9)
    np.testing.assert_array_equal(trial.markers_mm["PH_KNEE_LAT"], base.markers_mm["PH_KNEE_LAT"])
    if delay_s == 0.007:
        np.testing.assert_allclose(trial.analogs["SYNC"][7:], base.analogs["SYNC"][:-7], atol=1e-9)


def test_knee_marker_offset_moves_both_knee_markers_anterior_of_the_joint():
    offset_mm = 12.0
    base = simulate(small_config())[0]
    trial = simulate(small_config(knee_marker_offset=offset_mm))[0]
    theta = trial.truth["phantom_knee_angle_rad"].to_numpy()[:: int(ANALOG_RATE_HZ / 100)]
    paths = twin.leg_paths(theta, RIG)
    thigh = paths["knee"] - paths["hip"]
    for label in ("PH_KNEE_MED", "PH_KNEE_LAT"):
        shift = trial.markers_mm[label] - base.markers_mm[label]
        np.testing.assert_allclose(np.linalg.norm(shift, axis=1), offset_mm, rtol=1e-9)
        np.testing.assert_allclose((shift[:, :2] * thigh).sum(1), 0.0, atol=1e-9)
        assert np.all(shift[:, 0] > 0)  # anterior (+X) with the thigh pointing down
        assert np.all(shift[:, 2] == 0)
    for label in ("PH_HIP_LAT", "EX_THIGH_PROX"):
        np.testing.assert_array_equal(trial.markers_mm[label], base.markers_mm[label])


def test_unwrap_and_unit_vectors_are_numpys_to_the_last_bit():
    rng = np.random.default_rng(5)
    for _ in range(200):
        angle = np.cumsum(rng.normal(0.0, rng.choice([0.1, 2.0]), size=(3, 50)), axis=-1)
        angle[0, 0] = -0.0
        angle[1, 5:7] = angle[1, 4] + np.array([np.pi, 0.0])  # a step of exactly π
        assert dynamics.unwrap(angle).tobytes() == np.unwrap(angle, axis=-1).tobytes()
    vectors = rng.normal(size=(100, 2))
    expected = vectors / np.linalg.norm(vectors, axis=-1, keepdims=True)
    assert dynamics._unit(vectors).tobytes() == expected.tobytes()
