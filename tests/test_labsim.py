"""The independent recording generator: contract, physics and faults from first principles."""

import filecmp
from pathlib import Path

import ezc3d
import numpy as np
import pytest

from exobench import labsim
from exobench.phantom.recordings import c3d

CYCLE = Path(__file__).resolve().parents[1] / "raw/reference/phantom_knee_flexion_mean_cycle.csv"
L1, L2 = 0.299, 0.304
M1, M2, C1, C2, I1, I2 = 3.15, 1.62, 0.152, 0.113, 0.0165, 0.0130
R, RATIO, KT, F0 = 0.030, 5.0, 0.1, 3.0
ANKLES = ["LC_ANKLE_1", "LC_ANKLE_2", "LC_ANKLE_3"]
RIG_MARKERS = [  # docs/rig.md §1, in order
    *(f"PH_{j}_{side}" for j in ("HIP", "KNEE", "ANK") for side in ("MED", "LAT")),
    *("EX_THIGH_PROX", "EX_THIGH_DIST", "EX_SHANK_PROX", "EX_SHANK_DIST"),
    *("EX_SPRING_A", "EX_SPRING_B"),
]
QUIET = {"marker_noise_mm": 0.0, "cell_noise_N": 0.0}


def k_theta(k: float, r: float = R) -> float:
    """Seed 000 eq. (2.2): knee-equivalent spring stiffness."""
    return (k * r**2 - KT) * RATIO**2


def study(folder: Path, **kwargs) -> Path:
    args = {
        "cycle_csv": CYCLE,
        "springs_N_per_m": [9200.0, 3400.0],
        "strides": 4,
        "ramp_strides": 1,
        "effects": {},
        "faults": {},
        "seed": 7,
    }
    args.update(kwargs)
    return labsim.write_study(folder, **args)


def trial(manifest: Path, name: str):
    return c3d.read_trial(manifest.parent / f"{name}.c3d")


def xy(mk, label: str) -> np.ndarray:
    return mk[[f"{label}_x_mm", f"{label}_y_mm"]].to_numpy() / 1000.0


def centre(mk, joint: str) -> np.ndarray:
    return 0.5 * (xy(mk, f"PH_{joint}_MED") + xy(mk, f"PH_{joint}_LAT"))


def flexion(proximal: np.ndarray, distal: np.ndarray) -> np.ndarray:
    """Flexion between two segment direction vectors (shank turning clockwise = flexion)."""
    cross = proximal[:, 0] * distal[:, 1] - proximal[:, 1] * distal[:, 0]
    return np.arctan2(-cross, (proximal * distal).sum(axis=1))


def phantom_angle(mk) -> np.ndarray:
    hip, knee, ankle = centre(mk, "HIP"), centre(mk, "KNEE"), centre(mk, "ANK")
    return flexion(knee - hip, ankle - knee)


def exo_angle(mk) -> np.ndarray:
    thigh = xy(mk, "EX_THIGH_DIST") - xy(mk, "EX_THIGH_PROX")
    shank = xy(mk, "EX_SHANK_DIST") - xy(mk, "EX_SHANK_PROX")
    return flexion(thigh, shank)


def at_frames(an, column: str) -> np.ndarray:
    return an[column].to_numpy()[::10]


def ankle_sum(an) -> np.ndarray:
    return an[[f"{c}_N" for c in ANKLES]].sum(axis=1).to_numpy()


def engaged_frames(n_frames: int, start: float = 0.0, stop: float = 0.69) -> np.ndarray:
    """Frames inside the engaged window of each stride (stride start from 0 %)."""
    phase = (np.arange(n_frames) / 100.0) % 2.0
    return (phase >= start) & (phase <= stop)


def single_stride(theta_fn, fs: float = 4000.0, seconds: float = 0.7):
    """Synthetic one-stride phantom angle sampled at fs from the clutch instant."""
    t = np.arange(round(seconds * fs)) / fs
    return t, theta_fn(t)


# --- contract ------------------------------------------------------------------------------


def test_files_meet_the_rig_contract(tmp_path):
    manifest = study(tmp_path, springs_N_per_m=[9200.0, 21700.0, 3400.0], strides=4)
    table = c3d.read_manifest(manifest)
    assert list(table.columns)[:5] == list(labsim.MANIFEST_COLUMNS)
    assert table["trial"].tolist() == ["k9200", "k21700", "k3400"]
    assert table["spring_stiffness_N_per_m"].tolist() == [9200.0, 21700.0, 3400.0]
    assert table["test_order"].tolist() == [1, 2, 3]
    assert table["ramp_strides"].tolist() == [1, 1, 1]
    for name in table["trial"]:
        mk, an = trial(manifest, name)
        assert len(mk) == 4 * 200 and len(an) == 4 * 2000
        raw = ezc3d.c3d(str(manifest.parent / f"{name}.c3d"))
        par = raw["parameters"]
        assert par["POINT"]["LABELS"]["value"] == RIG_MARKERS
        assert par["POINT"]["RATE"]["value"][0] == 100.0
        assert par["POINT"]["UNITS"]["value"] == ["mm"]
        assert par["ANALOG"]["RATE"]["value"][0] == 1000.0
        assert par["ANALOG"]["LABELS"]["value"] == [*ANKLES, "LC_SPRING", "SYNC"]
        assert par["ANALOG"]["UNITS"]["value"] == ["N", "N", "N", "N", "V"]


def test_sync_pulses_mark_every_programmed_stride(tmp_path):
    manifest = study(tmp_path, strides=5, springs_N_per_m=[6100.0])
    _, an = trial(manifest, "k6100")
    sync = an["SYNC_V"].to_numpy()
    rising = np.flatnonzero(np.diff(np.r_[0.0, sync]) > 2.5)
    assert rising.tolist() == [0, 2000, 4000, 6000, 8000]
    assert set(np.unique(sync)) == {0.0, 5.0}
    assert np.count_nonzero(sync == 5.0) == 5 * 20


def test_noise_has_the_stated_levels(tmp_path):
    quiet = study(tmp_path / "quiet", springs_N_per_m=[6100.0], strides=3, **QUIET)
    noisy = study(tmp_path / "noisy", springs_N_per_m=[6100.0], strides=3)
    (mk0, an0), (mk1, an1) = trial(quiet, "k6100"), trial(noisy, "k6100")
    markers = (mk1 - mk0).drop(columns="t_s").to_numpy()
    columns = [f"{c}_N" for c in [*ANKLES, "LC_SPRING"]]
    cells = an1[columns].to_numpy() - an0[columns].to_numpy()
    assert markers.std() == pytest.approx(0.15, rel=0.03)
    assert cells.std(axis=0) == pytest.approx([0.5] * 4, rel=0.05)
    assert np.abs(cells.mean(axis=0)).max() < 0.03
    assert an1["SYNC_V"].equals(an0["SYNC_V"])


def test_joint_markers_and_hexapod_geometry(tmp_path):
    mk, _ = trial(study(tmp_path, springs_N_per_m=[3400.0], **QUIET), "k3400")
    hip, knee, ankle = centre(mk, "HIP"), centre(mk, "KNEE"), centre(mk, "ANK")
    np.testing.assert_allclose(np.ptp(hip, axis=0), 0.0, atol=1e-6)  # hip fixed
    np.testing.assert_allclose(ankle[:, 0], hip[:, 0], atol=1e-6)  # ankle below the hip
    np.testing.assert_allclose(np.linalg.norm(knee - hip, axis=1), L1, atol=1e-6)
    np.testing.assert_allclose(np.linalg.norm(ankle - knee, axis=1), L2, atol=1e-6)
    assert np.all(knee[:, 0] > hip[:, 0])  # the knee flexes anteriorly (+X)
    z = mk[[f"{m}_z_mm" for m in RIG_MARKERS if m.endswith("_LAT")]].to_numpy()
    assert np.all(z > 0)  # lateral is +Z


def test_ramps_start_at_mean_posture_and_trajectory_is_shared(tmp_path):
    manifest = study(tmp_path, springs_N_per_m=[3400.0, 21700.0], **QUIET)
    mk_a, _ = trial(manifest, "k3400")
    mk_b, _ = trial(manifest, "k21700")
    cycle = np.deg2rad(np.loadtxt(CYCLE, delimiter=",", skiprows=1)[:, 1])
    theta = phantom_angle(mk_a)
    assert theta[0] == pytest.approx(cycle.mean(), abs=1e-5)
    assert theta[-1] == pytest.approx(cycle.mean(), abs=2e-3)
    np.testing.assert_allclose(theta, phantom_angle(mk_b), atol=1e-6)  # same hexapod program


def test_strides_vary_peaks_by_four_degrees_at_fixed_timing(tmp_path):
    strides = 40
    manifest = study(tmp_path, springs_N_per_m=[3400.0], strides=strides, **QUIET)
    mk, _ = trial(manifest, "k3400")
    theta = np.rad2deg(phantom_angle(mk)).reshape(strides, 200)[1:-1]
    cycle = np.loadtxt(CYCLE, delimiter=",", skiprows=1)[:, 1]
    swing_peak = theta[:, 130:170].max(axis=1) - cycle[1300:1700].max()
    stance_valley = theta[:, 70:110].min(axis=1) - cycle[700:1100].min()
    deviations = np.r_[swing_peak, stance_valley]
    assert 3.0 < deviations.std() < 5.2
    assert abs(deviations.mean()) < 1.5
    assert np.all(np.abs(theta[:, 130:170].argmax(axis=1) + 130 - 150) <= 4)  # ±40 ms of 75 %


# --- rigid exoskeleton ---------------------------------------------------------------------


def test_rigid_spring_follows_eq_2_1_and_eq_2_2(tmp_path):
    manifest = study(tmp_path, springs_N_per_m=[21700.0, 3400.0], **QUIET)
    mk_a, an_a = trial(manifest, "k21700")
    _, an_b = trial(manifest, "k3400")
    theta = phantom_angle(mk_a)
    np.testing.assert_allclose(exo_angle(mk_a), theta, atol=1e-6)  # rigid: exo = phantom
    u = theta - np.repeat(theta[::200], 200)  # rotation since the 0 % engagement
    window = engaged_frames(len(mk_a), 0.0, 0.69) & (u >= 0)
    for an, k in ((an_a, 21700.0), (an_b, 3400.0)):
        spring = at_frames(an, "LC_SPRING_N")
        np.testing.assert_allclose(spring[window] - F0, k * R * RATIO * u[window], atol=0.05)
        free = engaged_frames(len(mk_a), 0.81, 1.99)
        np.testing.assert_allclose(spring[free], F0, atol=1e-4)  # pretension with clutch free
    # The two trials share the motion, so their ankle forces differ only through the knee
    # moment: ΔM = −ΔF_y·(x_ankle − x_knee) (shank statics of the moment alone).
    lever = centre(mk_a, "ANK")[:, 0] - centre(mk_a, "KNEE")[:, 0]
    d_moment = -(ankle_sum(an_a)[::10] - ankle_sum(an_b)[::10]) * lever
    expected = (k_theta(21700.0) - k_theta(3400.0)) * u
    np.testing.assert_allclose(d_moment[window], expected[window], atol=2e-3)
    free = engaged_frames(len(mk_a), 0.81, 1.99)
    np.testing.assert_allclose(d_moment[free], 0.0, atol=1e-4)


def test_spring_goes_slack_and_tensioner_acts_alone():
    k = 21700.0
    _, theta = single_stride(lambda t: 0.5 - 0.05 * t)
    exo = labsim.exoskeleton_response(theta, 4000.0, k, {})
    u = theta - theta[0]
    slack = u < -F0 / (k * R * RATIO)
    assert slack.any()
    np.testing.assert_allclose(exo.tension[slack], 0.0)
    np.testing.assert_allclose(exo.moment[slack], -F0 * R * RATIO - KT * RATIO**2 * u[slack])
    taut = ~slack
    np.testing.assert_allclose(exo.moment[taut], k_theta(k) * u[taut], atol=1e-9)
    np.testing.assert_allclose(exo.spring_length[slack], 0.080 - F0 / k)


# --- leg dynamics --------------------------------------------------------------------------


def independent_positions(theta: np.ndarray) -> dict[str, np.ndarray]:
    """Joint and COM positions (hip at the origin) from the hip-ankle triangle's cosine law."""
    d = np.sqrt(L1**2 + L2**2 + 2 * L1 * L2 * np.cos(theta))
    hip_angle = np.arccos((L1**2 + d**2 - L2**2) / (2 * L1 * d))
    knee = np.stack([L1 * np.sin(hip_angle), -L1 * np.cos(hip_angle)], axis=1)
    ankle = np.stack([np.zeros_like(d), -d], axis=1)
    return {
        "knee": knee,
        "ankle": ankle,
        "com1": C1 / L1 * knee,
        "com2": knee + C2 / L2 * (ankle - knee),
    }


def potential(theta: np.ndarray, m2: float = M2) -> np.ndarray:
    pos = independent_positions(theta)
    return 9.81 * (M1 * pos["com1"][:, 1] + m2 * pos["com2"][:, 1])


@pytest.mark.parametrize("theta0", [0.35, 0.9, 1.4])
@pytest.mark.parametrize("moment", [0.0, 7.5, -2.0])
def test_ankle_force_matches_virtual_work_statics(theta0, moment):
    # Virtual work at rest: F_y·δy_ankle − M·δθ = δV (M extensor, on shank vs thigh).
    h = 1e-6
    theta = np.array([theta0 - h, theta0 + h])
    dv = np.diff(potential(theta))[0] / (2 * h)
    dy = np.diff(independent_positions(theta)["ankle"][:, 1])[0] / (2 * h)
    expected = (dv + moment) / dy
    still = labsim.KneeMotion(np.array([theta0]), np.zeros(1), np.zeros(1))
    force = labsim.ankle_vertical_force(still, np.array([moment]))
    assert force[0] == pytest.approx(expected, rel=1e-7)


def test_ankle_force_at_right_angle_by_hand():
    # θ = 90°: the ankle sits at d = √(L1² + L2²) below the hip; with no knee moment the
    # shank's weight and the ankle force balance about the knee, whose horizontal reaction
    # follows from moments about the hip.
    d = np.hypot(L1, L2)
    knee = np.array([L1 * L2 / d, -(L1**2) / d])
    ankle = np.array([0.0, -d])
    com1, com2 = C1 / L1 * knee, knee + C2 / L2 * (ankle - knee)
    # Whole leg about the hip: d·Fx − g(m1 x1 + m2 x2) = 0.
    fx = 9.81 * (M1 * com1[0] + M2 * com2[0]) / d
    # Shank about the knee: (A − K) × F + (c2 − K) × (0, −m2 g) = 0.
    rel, relc = ankle - knee, com2 - knee
    fy = (rel[1] * fx + M2 * 9.81 * relc[0]) / rel[0]
    still = labsim.KneeMotion(np.array([np.pi / 2]), np.zeros(1), np.zeros(1))
    assert labsim.ankle_vertical_force(still, np.zeros(1))[0] == pytest.approx(fy, rel=1e-12)
    assert 0 < fy < (M1 + M2) * 9.81


@pytest.mark.parametrize("shank_factor", [1.0, 1.4])
def test_ankle_force_balances_power(shank_factor):
    # F_y·ẏ_ankle − M·θ̇ = d(T + V)/dt, energies from independently computed positions.
    fs = 2000.0
    t = np.arange(round(3.0 * fs)) / fs
    w1, w2 = 2 * np.pi * 0.9, 2 * np.pi * 2.3
    theta = 0.8 + 0.35 * np.sin(w1 * t) + 0.1 * np.sin(w2 * t)
    omega = 0.35 * w1 * np.cos(w1 * t) + 0.1 * w2 * np.cos(w2 * t)
    alpha = -0.35 * w1**2 * np.sin(w1 * t) - 0.1 * w2**2 * np.sin(w2 * t)
    moment = 6.0 * np.sin(2 * np.pi * 0.7 * t)
    force = labsim.ankle_vertical_force(
        labsim.KneeMotion(theta, omega, alpha), moment, shank_mass_factor=shank_factor
    )
    m2, i2 = M2 * shank_factor, I2 * shank_factor
    pos = independent_positions(theta)
    vel = {key: np.gradient(p, 1 / fs, axis=0) for key, p in pos.items()}
    phi1 = np.arctan2(pos["knee"][:, 0], -pos["knee"][:, 1])
    rel = pos["ankle"] - pos["knee"]
    phi2 = np.arctan2(rel[:, 0], -rel[:, 1])
    kinetic = 0.5 * (
        M1 * (vel["com1"] ** 2).sum(axis=1)
        + m2 * (vel["com2"] ** 2).sum(axis=1)
        + I1 * np.gradient(phi1, 1 / fs) ** 2
        + i2 * np.gradient(phi2, 1 / fs) ** 2
    )
    energy_rate = np.gradient(kinetic + potential(theta, m2), 1 / fs)
    y_rate = vel["ankle"][:, 1]
    ok = np.abs(y_rate) > 0.05
    ok[:5] = ok[-5:] = False
    expected = (energy_rate + moment * omega)[ok] / y_rate[ok]
    np.testing.assert_allclose(force[ok], expected, rtol=1e-4, atol=0.01)


# --- series chain --------------------------------------------------------------------------


def test_interface_and_frame_in_series(tmp_path):
    k, ki, kf = 9200.0, 60.0, 250.0
    series = 1 / (1 / ki + 1 / kf + 1 / k_theta(k))
    effects = {
        "interface_compliance": {"k_interface_Nm_per_rad": ki},
        "frame_compliance": {"k_frame_Nm_per_rad": kf},
    }
    _, theta = single_stride(lambda t: 0.5 + 0.25 * np.sin(np.pi * t / 0.7))
    exo = labsim.exoskeleton_response(theta, 4000.0, k, effects)
    u = theta - theta[0]
    np.testing.assert_allclose(exo.moment, series * u, rtol=1e-9, atol=1e-12)
    np.testing.assert_allclose(exo.interface, exo.moment / ki, rtol=1e-9, atol=1e-12)
    np.testing.assert_allclose(exo.tension - F0, k * R * RATIO * exo.moment / k_theta(k), rtol=1e-9)
    # The same law read from the recorded files alone.
    manifest = study(tmp_path, springs_N_per_m=[k], effects=effects, **QUIET)
    mk, an = trial(manifest, f"k{k:.0f}")
    phantom = phantom_angle(mk)
    u = phantom - np.repeat(phantom[::200], 200)
    moment = k_theta(k) * (at_frames(an, "LC_SPRING_N") - F0) / (k * R * RATIO)
    window = engaged_frames(len(mk), 0.02, 0.68) & (u > 0.0)
    np.testing.assert_allclose(moment[window], series * u[window], rtol=1e-3, atol=2e-3)
    interface = phantom - exo_angle(mk)
    np.testing.assert_allclose(ki * interface[window], moment[window], rtol=1e-3, atol=2e-3)
    free = engaged_frames(len(mk), 0.81, 1.99)
    np.testing.assert_allclose(interface[free], 0.0, atol=1e-6)


def test_interface_stiffening_is_cubic():
    ki, beta = 50.0, 8.0
    effects = {
        "interface_compliance": {"k_interface_Nm_per_rad": ki},
        "interface_stiffening": {"stiffening_per_rad2": beta},
    }
    _, theta = single_stride(lambda t: 0.5 + 0.4 * np.sin(np.pi * t / 0.7))
    exo = labsim.exoskeleton_response(theta, 4000.0, 13600.0, effects)
    delta = exo.interface
    np.testing.assert_allclose(exo.moment, ki * (delta + beta * delta**3), rtol=1e-9, atol=1e-12)
    np.testing.assert_allclose(theta - theta[0], delta + exo.moment / k_theta(13600.0), rtol=1e-9)


def test_interface_damping_is_kelvin_voigt():
    ki, ci = 60.0, 0.8
    effects = {
        "interface_compliance": {"k_interface_Nm_per_rad": ki},
        "interface_damping": {"c_interface_Nms_per_rad": ci},
    }
    fs = 4000.0
    t, theta = single_stride(lambda t: 0.5 + 0.25 * np.sin(np.pi * t / 0.7), fs, 2.0)
    exo = labsim.exoskeleton_response(theta, fs, 9200.0, effects)
    rate = np.gradient(exo.interface, 1 / fs)
    inside = (t > 0.01) & (t < 0.69)
    residual = exo.moment - ki * exo.interface - ci * rate
    assert np.abs(residual[inside]).max() < 2e-3 * np.abs(ci * rate[inside]).max()
    loop = np.sum(exo.moment[1:] * np.diff(exo.interface))  # ∮ M dδ over the stride
    dissipated = np.sum(ci * rate[1:] * np.diff(exo.interface))
    assert loop == pytest.approx(dissipated, rel=0.02) and loop > 0
    assert abs(exo.interface[-1]) < 1e-9  # the free interface relaxes to δ = 0


def test_play_delays_the_spring_loading():
    k, play = 6100.0, 0.03
    _, theta = single_stride(lambda t: 0.5 + 0.25 * np.sin(np.pi * t / 0.7))
    u = theta - theta[0]
    for effects, series in (
        ({}, k_theta(k)),
        (
            {"interface_compliance": {"k_interface_Nm_per_rad": 80.0}},
            1 / (1 / 80.0 + 1 / k_theta(k)),
        ),
    ):
        effects = {**effects, "transmission_play": {"play_rad": play}}
        exo = labsim.exoskeleton_response(theta, 4000.0, k, effects)
        np.testing.assert_allclose(exo.moment, series * np.maximum(u - play, 0.0), atol=1e-9)
        early = u < play
        np.testing.assert_allclose(exo.tension[early], F0)
        np.testing.assert_allclose(exo.spring_side[~early], exo.moment[~early] / k_theta(k))


def triangle_stride(peak: float):
    """Flexion up by `peak` over 0.35 s then back down over 0.35 s."""
    return single_stride(lambda t: 0.5 + peak * (1 - np.abs(t - 0.35) / 0.35))


def branch_moment(u, moment, level):
    """Moment where u crosses `level` on the way up and on the way down."""
    top = np.argmax(u)
    up = np.interp(level, u[: top + 1], moment[: top + 1])
    down = np.interp(level, u[top:][::-1], moment[top:][::-1])
    return up, down


def test_frame_friction_hysteresis_is_two_tau_wide():
    k, tau = 13600.0, 0.4
    _, theta = triangle_stride(0.2)
    u = theta - theta[0]
    exo = labsim.exoskeleton_response(theta, 4000.0, k, {"frame_friction": {"friction_Nm": tau}})
    up, down = branch_moment(u, exo.moment, 0.1)
    assert up - down == pytest.approx(2 * tau, rel=1e-9)
    assert up == pytest.approx(k_theta(k) * 0.1 + tau, rel=1e-9)
    # In series with a compliant frame the spring side sticks after each reversal; while it
    # slides M = M_s(s) ± τ, so the M–u loop narrows to 2τ / (1 + k_θ / k_f).
    kf = 150.0
    effects = {
        "frame_friction": {"friction_Nm": tau},
        "frame_compliance": {"k_frame_Nm_per_rad": kf},
    }
    exo = labsim.exoskeleton_response(theta, 4000.0, k, effects)
    up, down = branch_moment(u, exo.moment, 0.1)
    assert up - down == pytest.approx(2 * tau / (1 + k_theta(k) / kf), rel=1e-6)
    excess = exo.moment - k_theta(k) * exo.spring_side
    assert np.all(np.abs(excess) <= tau + 1e-9)
    sliding = np.abs(np.diff(exo.spring_side)) > 0
    np.testing.assert_allclose(np.abs(excess[1:][sliding]), tau, rtol=1e-9)


def test_all_effects_together_stay_consistent():
    k = 18000.0
    effects = {
        "interface_compliance": {"k_interface_Nm_per_rad": 70.0},
        "interface_stiffening": {"stiffening_per_rad2": 6.0},
        "interface_damping": {"c_interface_Nms_per_rad": 0.4},
        "frame_compliance": {"k_frame_Nm_per_rad": 300.0},
        "frame_friction": {"friction_Nm": 0.3},
        "transmission_play": {"play_rad": 0.01},
    }
    fs = 4000.0
    _, theta = single_stride(lambda t: 0.5 + 0.3 * np.sin(np.pi * t / 0.7) ** 2, fs)
    exo = labsim.exoskeleton_response(theta, fs, k, effects)
    u = theta - theta[0]
    delta, m = exo.interface, exo.moment
    rate = np.concatenate([[0.0], np.diff(delta) * fs])  # implicit Euler
    np.testing.assert_allclose(m, 70.0 * (delta + 6.0 * delta**3) + 0.4 * rate, atol=1e-9)
    assert np.all(m >= 0)  # tension-only chain
    taut = m > 0
    frame_out = u - delta - m / 300.0
    np.testing.assert_allclose(frame_out[taut] - exo.spring_side[taut], 0.01, atol=1e-9)
    assert np.all(frame_out - exo.spring_side <= 0.01 + 1e-9)
    excess = m[taut] - k_theta(k) * exo.spring_side[taut]
    assert np.all(np.abs(excess) <= 0.3 + 1e-9)


def test_clutch_delay_moves_the_engagement():
    k, delay = 9200.0, 0.05
    fs = 4000.0
    t, theta = single_stride(lambda t: 0.5 + 0.25 * np.sin(np.pi * t / 0.7), fs)
    exo = labsim.exoskeleton_response(theta, fs, k, {"clutch_timing": {"delay_s": delay}})
    before = t < delay
    np.testing.assert_allclose(exo.moment[before], 0.0)
    np.testing.assert_allclose(exo.tension[before], F0)
    start = np.argmax(~before)
    after = ~before & (theta >= theta[start])  # taut spring
    np.testing.assert_allclose(exo.moment[after], k_theta(k) * (theta[after] - theta[start]))


# --- faults --------------------------------------------------------------------------------

SPRING_CHANGES = {*ANKLES, "LC_SPRING", "EX_SPRING_B"}
FAULTS = {
    "ankle_cell_gain": ({"gain": 1.2, "channel": "LC_ANKLE_2"}, {"LC_ANKLE_2"}),
    "ankle_cell_offset": ({"offset_N": 4.0, "channel": "LC_ANKLE_2"}, {"LC_ANKLE_2"}),
    "ankle_cell_drift": ({"rate_N_per_s": 0.3, "channel": "LC_ANKLE_3"}, {"LC_ANKLE_3"}),
    "spring_cell_drift": ({"rate_N_per_s": 0.2}, {"LC_SPRING"}),
    "spring_mislabelled": ({"factor": 1.15}, SPRING_CHANGES),
    "pulley_radius": ({"factor": 0.9}, SPRING_CHANGES),
    "shank_mass": ({"factor": 1.3}, set(ANKLES)),
    "phantom_knee_friction": ({"friction_Nm": 0.5}, set(ANKLES)),
    "phantom_knee_damping": ({"c_Nms_per_rad": 0.3}, set(ANKLES)),
    "progressive_spring": ({"per_m": 8.0}, SPRING_CHANGES),
}


def changed(base, other) -> set[str]:
    (mk0, an0), (mk1, an1) = base, other
    out = {
        c
        for c in [*ANKLES, "LC_SPRING", "SYNC"]
        if not an0.filter(like=c).equals(an1.filter(like=c))
    }
    return out | {m for m in RIG_MARKERS if not mk0.filter(like=m).equals(mk1.filter(like=m))}


@pytest.fixture(scope="module")
def baseline(tmp_path_factory):
    folder = tmp_path_factory.mktemp("base")
    return study(folder, springs_N_per_m=[13600.0], strides=3)


@pytest.mark.parametrize("family", sorted(FAULTS))
def test_each_fault_changes_only_its_channels(tmp_path, baseline, family):
    params, expected = FAULTS[family]
    manifest = study(tmp_path, springs_N_per_m=[13600.0], strides=3, faults={family: params})
    assert changed(trial(baseline, "k13600"), trial(manifest, "k13600")) == expected
    assert c3d.read_manifest(manifest).equals(c3d.read_manifest(baseline))


def quiet_pair(folder: Path, faults: dict, k: float = 13600.0, **kwargs):
    base = study(folder / "base", springs_N_per_m=[k], strides=3, **QUIET, **kwargs)
    bad = study(folder / "bad", springs_N_per_m=[k], strides=3, faults=faults, **QUIET, **kwargs)
    return trial(base, f"k{k:.0f}"), trial(bad, f"k{k:.0f}")


def test_cell_faults_have_their_stated_size(tmp_path):
    faults = {
        "ankle_cell_gain": {"gain": 1.2, "channel": "LC_ANKLE_1"},
        "ankle_cell_offset": {"offset_N": 4.0, "channel": "LC_ANKLE_2"},
        "ankle_cell_drift": {"rate_N_per_s": 0.3, "channel": "LC_ANKLE_3"},
        "spring_cell_drift": {"rate_N_per_s": 0.2},
    }
    (_, an0), (_, an1) = quiet_pair(tmp_path, faults)
    t = an0["t_s"].to_numpy()
    col = {c: (an0[f"{c}_N"].to_numpy(), an1[f"{c}_N"].to_numpy()) for c in [*ANKLES, "LC_SPRING"]}
    np.testing.assert_allclose(col["LC_ANKLE_1"][1], 1.2 * col["LC_ANKLE_1"][0], rtol=1e-6)
    np.testing.assert_allclose(col["LC_ANKLE_2"][1] - col["LC_ANKLE_2"][0], 4.0, atol=1e-4)
    np.testing.assert_allclose(col["LC_ANKLE_3"][1] - col["LC_ANKLE_3"][0], 0.3 * t, atol=1e-4)
    np.testing.assert_allclose(col["LC_SPRING"][1] - col["LC_SPRING"][0], 0.2 * t, atol=1e-4)
    shares = np.array([col[c][0] for c in ANKLES])
    np.testing.assert_allclose(
        shares / shares.sum(axis=0), [[0.30], [0.33], [0.37]] * np.ones_like(shares), atol=1e-5
    )


@pytest.mark.parametrize(
    ("family", "params", "k_factor", "r_factor"),
    [
        ("spring_mislabelled", {"factor": 1.15}, 1.15, 1.0),
        ("pulley_radius", {"factor": 0.9}, 1.0, 0.9),
    ],
)
def test_spring_faults_scale_force_and_moment(tmp_path, family, params, k_factor, r_factor):
    k = 13600.0
    (_, an0), (mk1, an1) = quiet_pair(tmp_path, {family: params}, k)
    theta = phantom_angle(mk1)
    u = theta - np.repeat(theta[::200], 200)
    window = engaged_frames(len(mk1), 0.0, 0.69) & (u >= 0)
    spring = at_frames(an1, "LC_SPRING_N")
    stretch = k_factor * k * r_factor * R * RATIO * u
    np.testing.assert_allclose(spring[window] - F0, stretch[window], atol=0.05)
    lever = centre(mk1, "ANK")[:, 0] - centre(mk1, "KNEE")[:, 0]
    d_moment = -(ankle_sum(an1)[::10] - ankle_sum(an0)[::10]) * lever
    expected = (k_theta(k_factor * k, r_factor * R) - k_theta(k)) * u
    np.testing.assert_allclose(d_moment[window], expected[window], atol=2e-3)
    length = np.linalg.norm(
        mk1[["EX_SPRING_A_x_mm", "EX_SPRING_A_y_mm", "EX_SPRING_A_z_mm"]].to_numpy()
        - mk1[["EX_SPRING_B_x_mm", "EX_SPRING_B_y_mm", "EX_SPRING_B_z_mm"]].to_numpy(),
        axis=1,
    )
    np.testing.assert_allclose(
        length[window] / 1000 - 0.080, r_factor * R * RATIO * u[window], atol=1e-6
    )


def test_progressive_spring_reads_on_its_length(tmp_path):
    k, a = 13600.0, 8.0
    (_, _), (mk, an) = quiet_pair(tmp_path, {"progressive_spring": {"per_m": a}}, k)
    a_pt = mk[["EX_SPRING_A_x_mm", "EX_SPRING_A_y_mm", "EX_SPRING_A_z_mm"]].to_numpy()
    b_pt = mk[["EX_SPRING_B_x_mm", "EX_SPRING_B_y_mm", "EX_SPRING_B_z_mm"]].to_numpy()
    x = np.linalg.norm(a_pt - b_pt, axis=1) / 1000 - 0.080
    taut = x > 0
    force = at_frames(an, "LC_SPRING_N")
    np.testing.assert_allclose(
        force[taut] - F0, k * x[taut] * (1 + a * x[taut]), rtol=1e-4, atol=0.02
    )


@pytest.mark.parametrize(
    ("family", "params"),
    [
        ("phantom_knee_friction", {"friction_Nm": 0.5}),
        ("phantom_knee_damping", {"c_Nms_per_rad": 0.3}),
    ],
)
def test_phantom_knee_faults_add_a_hinge_moment(tmp_path, family, params):
    (_, an0), (mk1, an1) = quiet_pair(tmp_path, {family: params})
    theta = phantom_angle(mk1)
    omega = np.gradient(theta, 0.01)
    lever = centre(mk1, "ANK")[:, 0] - centre(mk1, "KNEE")[:, 0]
    d_moment = -(ankle_sum(an1)[::10] - ankle_sum(an0)[::10]) * lever
    moving = np.abs(omega) > 0.05
    if family == "phantom_knee_friction":
        np.testing.assert_allclose(d_moment[moving], 0.5 * np.sign(omega[moving]), atol=1e-3)
    else:
        np.testing.assert_allclose(d_moment[moving], 0.3 * omega[moving], rtol=0.02, atol=2e-3)


# --- determinism and validation ------------------------------------------------------------


def test_same_seed_gives_same_bytes(tmp_path):
    kwargs = {"springs_N_per_m": [3400.0, 6100.0], "strides": 3, "occlusions_per_marker": 1.5}
    a = study(tmp_path / "a", **kwargs)
    b = study(tmp_path / "b", **kwargs)
    c = study(tmp_path / "c", seed=8, **kwargs)
    for name in ("manifest.csv", "k3400.c3d", "k6100.c3d"):
        assert filecmp.cmp(a.parent / name, b.parent / name, shallow=False)
    assert not filecmp.cmp(a.parent / "k3400.c3d", c.parent / "k3400.c3d", shallow=False)


def test_occlusions_are_nan_gaps_the_reader_accepts(tmp_path):
    manifest = study(tmp_path, springs_N_per_m=[3400.0], strides=3, occlusions_per_marker=2.0)
    mk, _ = trial(manifest, "k3400")
    gaps = mk.drop(columns="t_s").isna()
    assert gaps.to_numpy().any()
    for marker in RIG_MARKERS:  # a marker vanishes in all three coordinates at once
        cols = gaps.filter(like=marker)
        assert (cols.all(axis=1) == cols.any(axis=1)).all()


@pytest.mark.parametrize(
    ("effects", "faults"),
    [
        ({"interface_damping": {"c_interface_Nms_per_rad": 0.3}}, {}),
        ({"frame_compliance": {"k_frame": 100.0}}, {}),
        ({"backlash": {"play_rad": 0.1}}, {}),
        ({}, {"ankle_cell_gain": {"gain": 1.1, "channel": "LC_SPRING"}}),
        ({}, {"spring_broken": {"factor": 0.5}}),
    ],
)
def test_bad_effects_or_faults_are_refused(tmp_path, effects, faults):
    with pytest.raises(ValueError):
        study(tmp_path, effects=effects, faults=faults)
