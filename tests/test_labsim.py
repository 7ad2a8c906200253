"""The independent recording generator: contract, physics and violations from first principles."""

import filecmp
import functools
from pathlib import Path

import ezc3d
import numpy as np
import pandas as pd
import pytest
from scipy.interpolate import CubicSpline

import assumption_rows
from assumption_rows import relaxations, table_lines
from exobench.phantom.validation import labsim

ROOT = Path(__file__).resolve().parents[1]
CYCLE = ROOT / "raw/reference/phantom_knee_flexion_mean_cycle.csv"
ASSUMPTIONS = ROOT / "docs/assumptions.md"
L1, L2 = 0.299, 0.304
M1, M2, C1, C2, I1, I2 = 3.15, 1.62, 0.152, 0.113, 0.0165, 0.0130
R, RATIO, KT, F0, LEN0 = 0.030, 5.0, 0.1, 3.0, 0.080
ANKLES = ["LC_ANKLE_1", "LC_ANKLE_2", "LC_ANKLE_3"]
CELLS = [*ANKLES, "LC_SPRING"]
RIG_MARKERS = [  # docs/rig.md §1, in order
    *(f"PH_{j}_{side}" for j in ("HIP", "KNEE", "ANK") for side in ("MED", "LAT")),
    *("EX_THIGH_PROX", "EX_THIGH_DIST", "EX_SHANK_PROX", "EX_SHANK_DIST"),
    *("EX_SPRING_A", "EX_SPRING_B"),
]
QUIET = {"marker_noise_mm": 0.0, "cell_noise_N": 0.0}
MARKER_NOISE_MM, CELL_NOISE_N = 0.15, 0.5


def k_theta(k: float, r: float = R, n: float = RATIO, kt: float = KT) -> float:
    """Seed 000 eq. (2.2): knee-equivalent spring stiffness."""
    return (k * r**2 - kt) * n**2


# --- recordings in memory and on disk --------------------------------------------------------


@functools.cache
def _simulated(violations: tuple, spring: float, strides: int, quiet: bool, seed: int, extra):
    args = {
        "cycle_csv": CYCLE,
        "springs_N_per_m": [spring],
        "strides": strides,
        "ramp_strides": 1,
        "violations": {key: dict(params) for key, params in violations},
        "seed": seed,
        **{key: dict(value) if key == "between_z" else value for key, value in extra},
    }
    if quiet:
        args.update(QUIET)
    return labsim.simulate_study(**args)[0]


def sim(violations=None, *, spring=9200.0, strides=3, quiet=True, seed=7, **extra):
    """One simulated trial (cached): markers in m (frames × 3) and analog channels by label."""
    frozen = tuple(sorted((k, tuple(sorted(v.items()))) for k, v in (violations or {}).items()))
    if "between_z" in extra:  # key → one z per trial
        extra["between_z"] = tuple((k, tuple(z)) for k, z in sorted(extra["between_z"].items()))
    trial = _simulated(frozen, spring, strides, quiet, seed, tuple(sorted(extra.items())))
    markers = {m: trial.points_mm[:, i, :].T / 1000.0 for i, m in enumerate(labsim.MARKERS)}
    return markers, dict(zip(labsim.CHANNELS, trial.analogs, strict=True))


def study(folder: Path, **kwargs) -> Path:
    args = {
        "cycle_csv": CYCLE,
        "springs_N_per_m": [9200.0, 3400.0],
        "strides": 4,
        "ramp_strides": 1,
        "violations": {},
        "seed": 7,
    }
    args.update(kwargs)
    return labsim.write_study(folder, **args)


def read_c3d(path: Path):
    """Markers (m, frames × 3) and analog channels of a C3D file, by label (ezc3d alone)."""
    raw = ezc3d.c3d(str(path))
    labels = raw["parameters"]["POINT"]["LABELS"]["value"]
    points = raw["data"]["points"][:3]
    markers = {m: points[:, i, :].T / 1000.0 for i, m in enumerate(labels)}
    analog_labels = raw["parameters"]["ANALOG"]["LABELS"]["value"]
    analogs = raw["data"]["analogs"][0]
    return markers, dict(zip(analog_labels, analogs, strict=True))


def xy(mk, label: str) -> np.ndarray:
    return mk[label][:, :2]


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


def spring_stretch(mk) -> np.ndarray:
    return np.linalg.norm(mk["EX_SPRING_B"] - mk["EX_SPRING_A"], axis=1) - LEN0


def at_frames(an, column: str) -> np.ndarray:
    return an[column][::10]


def ankle_sum(an) -> np.ndarray:
    return sum(an[c] for c in ANKLES)


def engaged_frames(n_frames: int, start: float = 0.0, stop: float = 0.69) -> np.ndarray:
    """Frames inside the engaged window of each stride (stride start from 0 %)."""
    phase = (np.arange(n_frames) / 100.0) % 2.0
    return (phase >= start) & (phase <= stop)


def since_engagement(theta: np.ndarray) -> np.ndarray:
    """Knee rotation since each stride's 0 % (markers at 100 Hz)."""
    return theta - np.repeat(theta[::200], 200)


def single_stride(theta_fn, fs: float = 4000.0, seconds: float = 0.7):
    """Synthetic one-stride phantom angle sampled at fs from the clutch instant."""
    t = np.arange(round(seconds * fs)) / fs
    return t, theta_fn(t)


def d_moment(mk, an_bad, an_base) -> np.ndarray:
    """Knee moment change from the ankle force change: ΔM = −ΔF_y·(x_ankle − x_knee).

    Shank statics of the moment alone; exact while the ankle line stays below the hip (the hip
    balance fixes F_x independently of the knee moment).
    """
    lever = centre(mk, "ANK")[:, 0] - centre(mk, "KNEE")[:, 0]
    return -(ankle_sum(an_bad)[::10] - ankle_sum(an_base)[::10]) * lever


# --- the table of docs/assumptions.md --------------------------------------------------------

TABLE = relaxations(ASSUMPTIONS)


def least_visible(key: str) -> list[float]:
    """The table's smallest visible sizes of a relaxation, as values (both signs where ±)."""
    return assumption_rows.least_visible(TABLE[key])


def with_needs(key: str, value: float) -> tuple[dict, dict]:
    """(baseline, violated): the needed terms at their least visible size, then the term added."""
    base = {
        need: {TABLE[need]["parameter"]: least_visible(need)[0]} for need in TABLE[key]["needs"]
    }
    return base, {**base, key: {TABLE[key]["parameter"]: value}}


BAR_MARKERS = {"EX_THIGH_PROX", "EX_THIGH_DIST", "EX_SHANK_PROX", "EX_SHANK_DIST"}
SPRING_MARKERS = {"EX_SPRING_A", "EX_SPRING_B"}
LEG_MOVES = {*RIG_MARKERS} - {"PH_HIP_MED", "PH_HIP_LAT"} | set(ANKLES)
THROUGH_INTERFACE = {*ANKLES, "LC_SPRING", *BAR_MARKERS, *SPRING_MARKERS}
STRETCH = {*ANKLES, "LC_SPRING", "EX_SPRING_B"}


def expected_changes(key: str) -> set[str]:
    """The channels (markers and analog labels) a violation changes, from the rig's physics."""
    row = key.split(".")[0]
    if row in ("interface", "straps_between"):
        return THROUGH_INTERFACE  # δ turns the bars and the spring on the thigh bar
    if row in ("frame", "transmission", "clutch", "pulley_radius", "chain_ratio"):
        return STRETCH
    if key in ("spring.value", "spring.stiffening", "spring.drifting"):
        return STRETCH  # the slack length −F0/k moves with the spring's law
    if key == "spring.viscous":
        return {*ANKLES, "LC_SPRING"}  # a rigid chain keeps the stretch kinematic
    if key == "bars.offset":
        return {"EX_THIGH_PROX", "EX_THIGH_DIST", *SPRING_MARKERS}
    if row in ("segment_lengths", "ankle_path"):
        return LEG_MOVES
    if row == "knee_markers":
        return {"PH_KNEE_MED", "PH_KNEE_LAT"}
    if row in CELLS:
        return {row}
    if row == "cells_zero_between":
        return {"LC_SPRING"}
    if row == "cell_linearity":
        return set(CELLS)
    if row == "clocks":
        return {*CELLS, "SYNC"}
    # spring.coulomb, tensioner, the phantom's knee and hip, segment values, the cells' axis
    return set(ANKLES)


def changed(base, other) -> set[str]:
    (mk0, an0), (mk1, an1) = base, other
    out = {c for c in labsim.CHANNELS if not np.array_equal(an0[c], an1[c])}
    return out | {m for m in RIG_MARKERS if not np.array_equal(mk0[m], mk1[m])}


def detection_z(base, other, channels: set[str], analysed: slice) -> float:
    """Ideal-observer detection of a known change in white noise: z² = Σ (Δ/σ)², analysed strides.

    SYNC holds no noise; its change is weighed against the cells' σ in volts.
    """
    (mk0, an0), (mk1, an1) = base, other
    z2 = 0.0
    for c in channels:
        if c in labsim.CHANNELS:
            z2 += np.sum(((an1[c] - an0[c])[analysed] / CELL_NOISE_N) ** 2)
        else:
            frames = slice(analysed.start // 10, analysed.stop // 10)
            z2 += np.sum(((mk1[c] - mk0[c])[frames] * 1000.0 / MARKER_NOISE_MM) ** 2)
    return float(np.sqrt(z2))


def test_the_table_and_the_generator_name_the_same_violations():
    # every relaxation line of the doc was read (the table's size follows from the doc itself)
    assert len(TABLE) == table_lines(ASSUMPTIONS) > 0
    assert set(TABLE) == set(labsim.VIOLATIONS)
    for key, row in TABLE.items():
        assert labsim.VIOLATIONS[key] == (row["parameter"],), key
        assert labsim.REQUIRES.get(key, ()) == row["needs"], key


CASES = [(key, value) for key in TABLE for value in least_visible(key)]


@pytest.mark.parametrize(("key", "value"), CASES, ids=[f"{k}={v:g}" for k, v in CASES])
def test_each_violation_changes_its_channels_visibly(key, value):
    # Fourteen strides (twelve analysed) of one spring with the default noise: the violation at
    # its least visible size changes exactly its channels, and a fit over the recording sees it
    # above the noise (an ideal observer's z > 5). Faintest: the segments' inertias (z ≈ 7–9, a
    # change of ~3 % of the noise per sample) and frame.viscous at k_frame = 2500 (z ≈ 18). A
    # between-trial relaxation is taken in a trial one standard deviation off (z_i = 1).
    base_violations, violations = with_needs(key, value)
    extra = {"between_z": {key: [1.0]}} if key in labsim.BETWEEN else {}
    base = sim(base_violations, strides=14, quiet=False)
    bad = sim(violations, strides=14, quiet=False, **extra)
    assert changed(base, bad) == expected_changes(key)
    z = detection_z(base, bad, expected_changes(key), slice(2000, 13 * 2000))
    assert z > 5.0, f"{key} = {value}: detection z = {z:.1f}"


# --- contract ------------------------------------------------------------------------------


def test_files_meet_the_rig_contract(tmp_path):
    manifest = study(tmp_path, springs_N_per_m=[9200.0, 21700.0, 3400.0], strides=3)
    table = pd.read_csv(manifest)
    assert list(table.columns) == list(labsim.MANIFEST_COLUMNS)
    assert table["trial"].tolist() == ["k9200", "k21700", "k3400"]
    assert table["file"].tolist() == ["k9200.c3d", "k21700.c3d", "k3400.c3d"]
    assert table["spring_stiffness_N_per_m"].tolist() == [9200.0, 21700.0, 3400.0]
    assert table["test_order"].tolist() == [1, 2, 3]
    assert table["ramp_strides"].tolist() == [1, 1, 1]
    trials = labsim.simulate_study(
        cycle_csv=CYCLE,
        springs_N_per_m=[9200.0, 21700.0, 3400.0],
        strides=3,
        ramp_strides=1,
        violations={},
        seed=7,
    )
    for name, trial in zip(table["trial"], trials, strict=True):
        raw = ezc3d.c3d(str(manifest.parent / f"{name}.c3d"))
        par = raw["parameters"]
        assert par["POINT"]["LABELS"]["value"] == RIG_MARKERS
        assert par["POINT"]["RATE"]["value"][0] == 100.0
        assert par["POINT"]["UNITS"]["value"] == ["mm"]
        assert par["ANALOG"]["RATE"]["value"][0] == 1000.0
        assert par["ANALOG"]["LABELS"]["value"] == [*CELLS, "SYNC"]
        assert par["ANALOG"]["UNITS"]["value"] == ["N", "N", "N", "N", "V"]
        assert raw["data"]["points"].shape == (4, 12, 3 * 200)
        assert raw["data"]["analogs"].shape == (1, 5, 3 * 2000)
        # the files hold the simulated trial (C3D stores 32-bit floats)
        np.testing.assert_allclose(raw["data"]["points"][:3], trial.points_mm, atol=1e-3)
        np.testing.assert_allclose(raw["data"]["analogs"][0], trial.analogs, atol=1e-4)


def test_sync_pulses_mark_every_programmed_stride():
    _, an = sim(strides=5)
    sync = an["SYNC"]
    rising = np.flatnonzero(np.diff(np.r_[0.0, sync]) > 2.5)
    assert rising.tolist() == [0, 2000, 4000, 6000, 8000]
    assert set(np.unique(sync)) == {0.0, 5.0}
    assert np.count_nonzero(sync == 5.0) == 5 * 20


def test_noise_has_the_stated_levels():
    (mk0, an0), (mk1, an1) = sim(), sim(quiet=False)
    markers = np.concatenate([mk1[m] - mk0[m] for m in RIG_MARKERS]) * 1000.0
    cells = np.array([an1[c] - an0[c] for c in CELLS])
    assert markers.std() == pytest.approx(MARKER_NOISE_MM, rel=0.03)
    assert cells.std(axis=1) == pytest.approx([CELL_NOISE_N] * 4, rel=0.05)
    assert np.abs(cells.mean(axis=1)).max() < 0.03
    np.testing.assert_array_equal(an1["SYNC"], an0["SYNC"])


def test_joint_markers_and_hexapod_geometry():
    mk, _ = sim(spring=3400.0)
    hip, knee, ankle = centre(mk, "HIP"), centre(mk, "KNEE"), centre(mk, "ANK")
    np.testing.assert_allclose(np.ptp(hip, axis=0), 0.0, atol=1e-9)  # hip fixed
    np.testing.assert_allclose(ankle[:, 0], hip[:, 0], atol=1e-9)  # ankle below the hip
    np.testing.assert_allclose(np.linalg.norm(knee - hip, axis=1), L1, atol=1e-9)
    np.testing.assert_allclose(np.linalg.norm(ankle - knee, axis=1), L2, atol=1e-9)
    assert np.all(knee[:, 0] > hip[:, 0])  # the knee flexes anteriorly (+X)
    z = np.array([mk[m][:, 2] for m in RIG_MARKERS if m.endswith("_LAT")])
    assert np.all(z > 0)  # lateral is +Z


def test_ramps_start_at_mean_posture_and_trajectory_is_shared():
    mk_a, _ = sim(spring=3400.0, strides=4)
    mk_b, _ = sim(spring=21700.0, strides=4)
    cycle = np.deg2rad(np.loadtxt(CYCLE, delimiter=",", skiprows=1)[:, 1])
    theta = phantom_angle(mk_a)
    assert theta[0] == pytest.approx(cycle.mean(), abs=1e-5)
    assert theta[-1] == pytest.approx(cycle.mean(), abs=2e-3)
    np.testing.assert_allclose(theta, phantom_angle(mk_b), atol=1e-12)  # same hexapod program


def test_strides_vary_peaks_by_four_degrees_at_fixed_timing():
    strides = 40
    mk, _ = sim(spring=3400.0, strides=strides)
    theta = np.rad2deg(phantom_angle(mk)).reshape(strides, 200)[1:-1]
    cycle = np.loadtxt(CYCLE, delimiter=",", skiprows=1)[:, 1]
    swing_peak = theta[:, 130:170].max(axis=1) - cycle[1300:1700].max()
    stance_valley = theta[:, 70:110].min(axis=1) - cycle[700:1100].min()
    deviations = np.r_[swing_peak, stance_valley]
    assert 3.0 < deviations.std() < 5.2
    assert abs(deviations.mean()) < 1.5
    assert np.all(np.abs(theta[:, 130:170].argmax(axis=1) + 130 - 150) <= 4)  # ±40 ms of 75 %


# --- rigid exoskeleton ---------------------------------------------------------------------


def test_rigid_spring_follows_eq_2_1_and_eq_2_2():
    mk_a, an_a = sim(spring=21700.0, strides=4)
    _, an_b = sim(spring=3400.0, strides=4)
    theta = phantom_angle(mk_a)
    np.testing.assert_allclose(exo_angle(mk_a), theta, atol=1e-9)  # rigid: exo = phantom
    u = since_engagement(theta)
    window = engaged_frames(len(theta), 0.0, 0.69) & (u >= 0)
    free = engaged_frames(len(theta), 0.81, 1.99)
    for an, k in ((an_a, 21700.0), (an_b, 3400.0)):
        spring = at_frames(an, "LC_SPRING")
        np.testing.assert_allclose(spring[window] - F0, k * R * RATIO * u[window], atol=1e-6)
        np.testing.assert_allclose(spring[free], F0, atol=1e-9)  # pretension, clutch free
    # The two trials share the motion, so their ankle forces differ only through the knee
    # moment: ΔM = −ΔF_y·(x_ankle − x_knee) (shank statics of the moment alone).
    expected = (k_theta(21700.0) - k_theta(3400.0)) * u
    np.testing.assert_allclose(d_moment(mk_a, an_a, an_b)[window], expected[window], atol=1e-6)
    np.testing.assert_allclose(d_moment(mk_a, an_a, an_b)[free], 0.0, atol=1e-6)


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
    np.testing.assert_allclose(exo.spring_length[slack], LEN0 - F0 / k)


def test_the_tensioner_only_pulls():
    # Slack spring: the tensioner alone gives M = −n(r·F0 + k_t·n·u), a negative stiffness, until
    # its torque r·F0 + k_t·n·u reaches 0; like the chain, it cannot push, so M stays 0 beyond.
    k, scale = 9200.0, 12.0
    kt = KT * scale
    _, theta = single_stride(lambda t: 0.5 - 0.05 * t)
    exo = labsim.exoskeleton_response(theta, 4000.0, k, {"tensioner.value": {"scale": scale}})
    u = theta - theta[0]
    slack = u < -F0 / (k * R * RATIO)
    pulling = slack & (u > -R * F0 / (kt * RATIO))
    beyond = u < -R * F0 / (kt * RATIO)
    assert pulling.any() and beyond.any()
    np.testing.assert_allclose(exo.moment[pulling], -RATIO * (R * F0 + kt * RATIO * u[pulling]))
    np.testing.assert_allclose(exo.moment[beyond], 0.0, atol=1e-12)
    np.testing.assert_allclose(exo.moment[~slack], k_theta(k, kt=kt) * u[~slack], atol=1e-9)


# --- leg dynamics --------------------------------------------------------------------------


def independent_positions(
    theta: np.ndarray, l1: float = L1, l2: float = L2, offset: float = 0.0, c1=C1, c2=C2
) -> dict[str, np.ndarray]:
    """Joint and COM positions (hip at the origin) for an ankle on the line x = offset below it.

    The knee sits on the anterior side of the hip–ankle line, by the triangle's cosine law.
    """
    d = np.sqrt(l1**2 + l2**2 + 2 * l1 * l2 * np.cos(theta))
    ankle = np.stack([np.full_like(d, offset), -np.sqrt(d**2 - offset**2)], axis=1)
    along = ankle / d[:, None]
    normal = np.stack([-along[:, 1], along[:, 0]], axis=1)  # anterior of the hip–ankle line
    a = (l1**2 - l2**2 + d**2) / (2 * d)
    knee = a[:, None] * along + np.sqrt(l1**2 - a**2)[:, None] * normal
    return {
        "knee": knee,
        "ankle": ankle,
        "com1": c1 / l1 * knee,
        "com2": knee + c2 / l2 * (ankle - knee),
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
    got_fx, got_fy = labsim.ankle_forces(still, np.zeros(1))
    assert got_fy[0] == pytest.approx(fy, rel=1e-12)
    assert got_fx[0] == pytest.approx(fx, rel=1e-12)
    assert 0 < fy < (M1 + M2) * 9.81


LEGS = {
    "rig": {},
    "shank_mass": {"shank_mass.value": {"scale": 1.4}},
    "every_segment": {
        **{f"{s}.value": {"scale": f} for s, f in (("thigh_mass", 0.7), ("thigh_com", 1.3))},
        **{f"{s}.value": {"scale": f} for s, f in (("thigh_inertia", 1.4), ("shank_com", 0.8))},
        **{f"{s}.value": {"scale": f} for s, f in (("shank_mass", 1.2), ("shank_inertia", 0.6))},
    },
    "lengths_offset_hip": {
        "segment_lengths.value": {"scale": 1.1},
        "ankle_path.offset": {"offset_mm": -45.0},
        "hip.viscous": {"c_Nms_per_rad": 0.4},
        "hip.coulomb": {"friction_Nm": 0.5},
        "hip.elastic": {"k_Nm_per_rad": 4.0},
    },
}


@pytest.mark.parametrize("case", sorted(LEGS))
def test_ankle_force_balances_power(case):
    # F_y·ẏ_ankle − M·θ̇ + M_hip·φ̇1 = d(T + V)/dt, with the real segments, the ankle on the
    # line x = o (ẋ_ankle = 0) and M_hip = −(c φ̇1 + τ sign φ̇1 + k φ1); energies from
    # independently computed positions.
    violations = labsim.checked_violations(LEGS[case])
    segments = [f"{s}_{v}" for s in ("thigh", "shank") for v in ("mass", "com", "inertia")]
    scale = {
        key: violations.get(f"{key}.value", {"scale": 1.0})["scale"]
        for key in [*segments, "segment_lengths"]
    }
    l1, l2 = L1 * scale["segment_lengths"], L2 * scale["segment_lengths"]
    m1, m2 = M1 * scale["thigh_mass"], M2 * scale["shank_mass"]
    i1, i2 = I1 * scale["thigh_inertia"], I2 * scale["shank_inertia"]
    c1, c2 = C1 * scale["thigh_com"], C2 * scale["shank_com"]
    offset = violations.get("ankle_path.offset", {"offset_mm": 0.0})["offset_mm"] / 1000
    hip_c = violations.get("hip.viscous", {"c_Nms_per_rad": 0.0})["c_Nms_per_rad"]
    hip_tau = violations.get("hip.coulomb", {"friction_Nm": 0.0})["friction_Nm"]
    hip_k = violations.get("hip.elastic", {"k_Nm_per_rad": 0.0})["k_Nm_per_rad"]
    fs = 2000.0
    t = np.arange(round(3.0 * fs)) / fs
    w1, w2 = 2 * np.pi * 0.9, 2 * np.pi * 2.3
    theta = 0.8 + 0.35 * np.sin(w1 * t) + 0.1 * np.sin(w2 * t)
    omega = 0.35 * w1 * np.cos(w1 * t) + 0.1 * w2 * np.cos(w2 * t)
    alpha = -0.35 * w1**2 * np.sin(w1 * t) - 0.1 * w2**2 * np.sin(w2 * t)
    moment = 6.0 * np.sin(2 * np.pi * 0.7 * t)
    leg = labsim.real_leg(violations)
    assert leg == labsim.Leg(l1, l2, m1, m2, c1, c2, i1, i2, offset)
    fx, fy = labsim.ankle_forces(
        labsim.KneeMotion(theta, omega, alpha), moment, leg, hip_c, hip_tau, hip_k
    )
    pos = independent_positions(theta, l1, l2, offset, c1, c2)
    vel = {key: np.gradient(p, 1 / fs, axis=0) for key, p in pos.items()}
    phi1 = np.arctan2(pos["knee"][:, 0], -pos["knee"][:, 1])
    rel = pos["ankle"] - pos["knee"]
    phi2 = np.arctan2(rel[:, 0], -rel[:, 1])
    w_thigh, w_shank = np.gradient(phi1, 1 / fs), np.gradient(phi2, 1 / fs)
    kinetic = 0.5 * (
        m1 * (vel["com1"] ** 2).sum(axis=1)
        + m2 * (vel["com2"] ** 2).sum(axis=1)
        + i1 * w_thigh**2
        + i2 * w_shank**2
    )
    energy = kinetic + 9.81 * (m1 * pos["com1"][:, 1] + m2 * pos["com2"][:, 1])
    hip_power = -(hip_c * w_thigh + hip_tau * np.sign(w_thigh) + hip_k * phi1) * w_thigh
    np.testing.assert_allclose(vel["ankle"][:, 0], 0.0, atol=1e-12)
    y_rate = vel["ankle"][:, 1]
    ok = np.abs(y_rate) > 0.05
    ok[:5] = ok[-5:] = False
    expected = (np.gradient(energy, 1 / fs) + moment * omega - hip_power)[ok] / y_rate[ok]
    np.testing.assert_allclose(fy[ok], expected, rtol=1e-4, atol=0.01)
    assert np.all(np.isfinite(fx))


def planar_cross(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    return a[:, 0] * b[:, 1] - a[:, 1] * b[:, 0]


class Kinematics:
    """Joint paths of a quiet recording as cubic splines of its 100 Hz markers, read at 1 kHz."""

    def __init__(self, mk):
        frames = np.arange(len(mk["PH_HIP_MED"])) / 100.0
        self.t = np.arange(len(frames) * 10) / 1000.0
        inside = self.t <= frames[-1]
        self.t = self.t[inside]
        self.path = {j: CubicSpline(frames, centre(mk, j)) for j in ("HIP", "KNEE", "ANK")}

    def at(self, joint: str, order: int = 0) -> np.ndarray:
        return self.path[joint](self.t, order)

    def angles(self) -> tuple[np.ndarray, np.ndarray]:
        """Thigh angle φ1 (counter-clockwise from −Y) and knee flexion θ (rad)."""
        hip, knee, ankle = self.at("HIP"), self.at("KNEE"), self.at("ANK")
        thigh = knee - hip
        return np.arctan2(thigh[:, 0], -thigh[:, 1]), flexion(thigh, ankle - knee)

    def energy(self, m1=M1, m2=M2, c1=C1, c2=C2, i1=I1, i2=I2) -> np.ndarray:
        """T + V of the leg with the given segment values, from the joint paths."""
        hip, knee, ankle = self.at("HIP"), self.at("KNEE"), self.at("ANK")
        dhip, dknee, dankle = self.at("HIP", 1), self.at("KNEE", 1), self.at("ANK", 1)
        thigh, shank = knee - hip, ankle - knee
        l1, l2 = np.linalg.norm(thigh, axis=1)[:, None], np.linalg.norm(shank, axis=1)[:, None]
        com1, com2 = hip + c1 * thigh / l1, knee + c2 * shank / l2
        w1 = planar_cross(thigh, dknee - dhip) / l1[:, 0] ** 2
        w2 = planar_cross(shank, dankle - dknee) / l2[:, 0] ** 2
        v1 = dhip + c1 / l1 * (dknee - dhip)  # a point at fixed distance on a rigid segment
        v2 = dknee + c2 / l2 * (dankle - dknee)
        kinetic = 0.5 * (m1 * (v1**2).sum(1) + m2 * (v2**2).sum(1) + i1 * w1**2 + i2 * w2**2)
        return kinetic + 9.81 * (m1 * com1[:, 1] + m2 * com2[:, 1])


def ankle_work(kin: Kinematics, an) -> np.ndarray:
    """W(t) = ∫ F_y dy_ankle (J), the hexapod's work on the leg through the ankle cells."""
    power = ankle_sum(an)[: kin.t.size] * kin.at("ANK", 1)[:, 1]
    return np.concatenate([[0.0], np.cumsum(0.5 * (power[1:] + power[:-1]) / 1000.0)])


def cumulative(rate: np.ndarray) -> np.ndarray:
    return np.concatenate([[0.0], np.cumsum(0.5 * (rate[1:] + rate[:-1]) / 1000.0)])


LEG_ENERGY = {  # violation → the extra work the hexapod does on the leg
    "knee.elastic": {"k_Nm_per_rad": 1.5},
    "knee.viscous": {"c_Nms_per_rad": 0.15},
    "knee.coulomb": {"friction_Nm": 0.3},
    "hip.viscous": {"c_Nms_per_rad": 0.5},
    "hip.coulomb": {"friction_Nm": 0.6},
    "hip.elastic": {"k_Nm_per_rad": 5.0},
    "thigh_mass.value": {"scale": 1.4},
    "thigh_com.value": {"scale": 0.6},
    "thigh_inertia.value": {"scale": 1.4},
    "shank_mass.value": {"scale": 0.6},
    "shank_com.value": {"scale": 1.4},
    "shank_inertia.value": {"scale": 1.4},
    "segment_lengths.value": {"scale": 1.12},
    "ankle_path.offset": {"offset_mm": 50.0},
}


@pytest.mark.parametrize("key", sorted(LEG_ENERGY))
def test_leg_violations_do_the_work_their_law_says(key):
    # Power on the leg: F_y·ẏ_A − M·θ̇ − M_k·θ̇ + M_hip·φ̇1 = dE/dt (ẋ_A = 0), M_hip = −k·φ1
    # for the hip's stiffness (its energy ½k·φ1² is the hexapod's extra work). The exoskeleton's
    # M and θ are the same with and without the violation, so the hexapod's extra work is the
    # leg's extra energy plus what the phantom's own knee and hip take.
    base = sim(strides=3)
    bad = sim({key: LEG_ENERGY[key]}, strides=3)
    kin0, kin1 = Kinematics(base[0]), Kinematics(bad[0])
    extra = ankle_work(kin1, bad[1]) - ankle_work(kin0, base[1])
    phi1, theta = kin1.angles()
    dphi1, dtheta = np.gradient(phi1, 1e-3), np.gradient(theta, 1e-3)
    (value,) = LEG_ENERGY[key].values()
    segment = {"thigh_mass": "m1", "thigh_com": "c1", "thigh_inertia": "i1"}
    segment |= {"shank_mass": "m2", "shank_com": "c2", "shank_inertia": "i2"}
    nominal = {"m1": M1, "m2": M2, "c1": C1, "c2": C2, "i1": I1, "i2": I2}
    if key == "knee.elastic":
        expected = 0.5 * value * (theta**2 - theta[0] ** 2)
    elif key == "knee.viscous":
        expected = cumulative(value * dtheta**2)
    elif key == "knee.coulomb":
        expected = cumulative(value * np.abs(dtheta))
    elif key == "hip.viscous":
        expected = cumulative(value * dphi1**2)
    elif key == "hip.coulomb":
        expected = cumulative(value * np.abs(dphi1))
    elif key == "hip.elastic":
        expected = 0.5 * value * (phi1**2 - phi1[0] ** 2)
    elif key.split(".")[0] in segment:
        name = segment[key.split(".")[0]]
        energy = kin1.energy(**{name: nominal[name] * value})
        expected = energy - energy[0] - (kin0.energy() - kin0.energy()[0])
    else:  # the geometry changes: each recording with its own markers
        expected = kin1.energy() - kin1.energy()[0] - (kin0.energy() - kin0.energy()[0])
    assert np.ptp(expected) > 1e-3  # the violation does measurable work
    np.testing.assert_allclose(extra, expected, atol=2e-3 * np.ptp(expected) + 2e-5)


@pytest.mark.parametrize(
    ("key", "law"),
    [
        ("knee.elastic", lambda theta, omega: 1.5 * theta),
        ("knee.viscous", lambda theta, omega: 0.15 * omega),
        ("knee.coulomb", lambda theta, omega: 0.3 * np.sign(omega)),
    ],
)
def test_phantom_knee_adds_a_hinge_moment(key, law):
    (value,) = LEG_ENERGY[key].values()
    base = sim()
    mk, an = sim({key: {labsim.VIOLATIONS[key][0]: value}})
    theta = phantom_angle(mk)
    omega = np.gradient(theta, 0.01)
    moving = np.abs(omega) > 0.05
    np.testing.assert_allclose(
        d_moment(mk, an, base[1])[moving], law(theta, omega)[moving], rtol=0.02, atol=2e-3
    )


# --- markers -------------------------------------------------------------------------------


def test_segment_lengths_and_ankle_path_move_the_joints():
    mk, _ = sim({"segment_lengths.value": {"scale": 0.9}, "ankle_path.offset": {"offset_mm": 30.0}})
    hip, knee, ankle = centre(mk, "HIP"), centre(mk, "KNEE"), centre(mk, "ANK")
    np.testing.assert_allclose(np.linalg.norm(knee - hip, axis=1), 0.9 * L1, atol=1e-9)
    np.testing.assert_allclose(np.linalg.norm(ankle - knee, axis=1), 0.9 * L2, atol=1e-9)
    np.testing.assert_allclose(ankle[:, 0] - hip[:, 0], 0.030, atol=1e-9)  # the line x = o
    base, _ = sim()
    np.testing.assert_allclose(phantom_angle(mk), phantom_angle(base), atol=1e-9)  # same θ
    np.testing.assert_allclose(exo_angle(mk), phantom_angle(mk), atol=1e-9)
    # the bars and the spring keep their places on the exoskeleton
    for m in (*BAR_MARKERS, "EX_SPRING_A"):
        np.testing.assert_allclose(
            np.linalg.norm(mk[m] - mk["PH_KNEE_LAT"], axis=1),
            np.linalg.norm(base[m] - base["PH_KNEE_LAT"], axis=1),
            atol=1e-9,
        )


@pytest.mark.parametrize("angle", [0.1, -0.05])
def test_bars_offset_turns_the_thigh_bar(angle):
    mk, _ = sim({"bars.offset": {"angle_rad": angle}})
    base, _ = sim()
    np.testing.assert_allclose(exo_angle(mk), phantom_angle(mk) + angle, atol=1e-9)
    thigh = xy(mk, "EX_THIGH_DIST") - xy(mk, "EX_THIGH_PROX")
    segment = centre(mk, "KNEE") - centre(mk, "HIP")
    # turned anteriorly (counter-clockwise seen from +Z) for a > 0
    np.testing.assert_allclose(flexion(segment, thigh), -angle, atol=1e-9)
    # the spring turns with the bar it is mounted on: same length, same place on the bar
    np.testing.assert_allclose(spring_stretch(mk), spring_stretch(base), atol=1e-12)
    for m in ("EX_SPRING_A", "EX_SPRING_B"):
        np.testing.assert_allclose(
            np.linalg.norm(mk[m] - mk["EX_THIGH_PROX"], axis=1),
            np.linalg.norm(base[m] - base["EX_THIGH_PROX"], axis=1),
            atol=1e-9,
        )


@pytest.mark.parametrize("offset_mm", [25.0, -12.0])
def test_knee_markers_sit_off_the_axis_on_the_thigh(offset_mm):
    mk, _ = sim({"knee_markers.offset": {"offset_mm": offset_mm}})
    theta = phantom_angle(sim()[0])  # the programmed knee angle (the markers now misread it)
    pos = independent_positions(theta)
    hip, ankle = centre(mk, "HIP"), centre(mk, "ANK")
    np.testing.assert_allclose(ankle - hip, pos["ankle"], atol=1e-9)
    knee = hip + pos["knee"]  # the joint's axis, from the hip, the ankle and the lengths
    thigh = (knee - hip) / L1
    anterior = np.stack([-thigh[:, 1], thigh[:, 0]], axis=1)
    np.testing.assert_allclose(centre(mk, "KNEE"), knee + offset_mm / 1000 * anterior, atol=1e-9)
    z = mk["PH_KNEE_LAT"][:, 2] - mk["PH_KNEE_MED"][:, 2]
    np.testing.assert_allclose(z, 0.1, atol=1e-12)  # still medial and lateral of the knee


# --- series chain --------------------------------------------------------------------------


def sinus_stride(fs=4000.0, seconds=0.7, peak=0.25):
    return single_stride(lambda t: 0.5 + peak * np.sin(np.pi * t / 0.7), fs, seconds)


def test_interface_and_frame_in_series():
    k, ki, kf = 9200.0, 60.0, 250.0
    series = 1 / (1 / ki + 1 / kf + 1 / k_theta(k))
    violations = {
        "interface.elastic": {"k_interface_Nm_per_rad": ki},
        "frame.elastic": {"k_frame_Nm_per_rad": kf},
    }
    _, theta = sinus_stride()
    exo = labsim.exoskeleton_response(theta, 4000.0, k, violations)
    u = theta - theta[0]
    np.testing.assert_allclose(exo.moment, series * u, rtol=1e-9, atol=1e-12)
    np.testing.assert_allclose(exo.interface, exo.moment / ki, rtol=1e-9, atol=1e-12)
    np.testing.assert_allclose(exo.frame, exo.moment / kf, rtol=1e-9, atol=1e-12)
    np.testing.assert_allclose(exo.tension - F0, k * R * RATIO * exo.moment / k_theta(k), rtol=1e-9)
    # The same law read from the recorded channels alone.
    mk, an = sim(violations, spring=k)
    phantom = phantom_angle(mk)
    u = since_engagement(phantom)
    moment = k_theta(k) * (at_frames(an, "LC_SPRING") - F0) / (k * R * RATIO)
    window = engaged_frames(len(u), 0.02, 0.68) & (u > 0.0)
    np.testing.assert_allclose(moment[window], series * u[window], rtol=1e-3, atol=2e-3)
    interface = phantom - exo_angle(mk)
    np.testing.assert_allclose(ki * interface[window], moment[window], rtol=1e-3, atol=2e-3)
    free = engaged_frames(len(u), 0.81, 1.99)
    np.testing.assert_allclose(interface[free], 0.0, atol=1e-9)


@pytest.mark.parametrize("element", ["interface", "frame"])
def test_stiffening_is_cubic(element):
    ki, beta = (50.0, 8.0) if element == "interface" else (200.0, 3000.0)
    key = "k_interface_Nm_per_rad" if element == "interface" else "k_frame_Nm_per_rad"
    violations = {
        f"{element}.elastic": {key: ki},
        f"{element}.stiffening": {"stiffening_per_rad2": beta},
    }
    _, theta = single_stride(lambda t: 0.5 + 0.4 * np.sin(np.pi * t / 0.7))
    exo = labsim.exoskeleton_response(theta, 4000.0, 13600.0, violations)
    x = exo.interface if element == "interface" else exo.frame
    assert np.abs(x).max() > 0.01
    np.testing.assert_allclose(exo.moment, ki * (x + beta * x**3), rtol=1e-9, atol=1e-12)
    np.testing.assert_allclose(theta - theta[0], x + exo.moment / k_theta(13600.0), rtol=1e-9)


@pytest.mark.parametrize(("element", "k", "c"), [("interface", 60.0, 0.8), ("frame", 400.0, 15.0)])
def test_damping_is_kelvin_voigt(element, k, c):
    names = {"interface": ("k_interface_Nm_per_rad", "c_interface_Nms_per_rad")}
    names["frame"] = ("k_frame_Nm_per_rad", "c_frame_Nms_per_rad")
    violations = {
        f"{element}.elastic": {names[element][0]: k},
        f"{element}.viscous": {names[element][1]: c},
    }
    fs = 4000.0
    t, theta = sinus_stride(fs, 2.0)
    exo = labsim.exoskeleton_response(theta, fs, 9200.0, violations)
    x = exo.interface if element == "interface" else exo.frame
    rate = np.gradient(x, 1 / fs)
    inside = (t > 0.01) & (t < 0.69)
    residual = exo.moment - k * x - c * rate
    assert np.abs(residual[inside]).max() < 1e-2 * np.abs(c * rate[inside]).max()
    loop = np.sum(0.5 * (exo.moment[1:] + exo.moment[:-1]) * np.diff(x))  # ∮ M dx, a stride
    dissipated = np.sum(c * rate**2) / fs  # ∫ c ẋ² dt
    assert loop == pytest.approx(dissipated, rel=2e-3) and loop > 0
    assert abs(x[-1]) < 1e-9  # the free element relaxes to x = 0
    # implicit Euler: M = k x + c (x − x_prev)·fs on every sample
    step_rate = np.concatenate([[0.0], np.diff(x) * fs])
    np.testing.assert_allclose(exo.moment, k * x + c * step_rate, atol=1e-9)


def triangle_stride(peak: float, fs: float = 4000.0):
    """Flexion up by `peak` over 0.35 s then back down over 0.35 s."""
    return single_stride(lambda t: 0.5 + peak * (1 - np.abs(t - 0.35) / 0.35), fs)


def branch_moment(u, moment, level):
    """Moment where u crosses `level` on the way up and on the way down."""
    top = np.argmax(u)
    up = np.interp(level, u[: top + 1], moment[: top + 1])
    down = np.interp(level, u[top:][::-1], moment[top:][::-1])
    return up, down


def test_spring_side_friction_hysteresis_is_two_tau_wide():
    k, tau = 13600.0, 0.4
    _, theta = triangle_stride(0.2)
    u = theta - theta[0]
    exo = labsim.exoskeleton_response(theta, 4000.0, k, {"spring.coulomb": {"friction_Nm": tau}})
    up, down = branch_moment(u, exo.moment, 0.1)
    assert up - down == pytest.approx(2 * tau, rel=1e-9)
    assert up == pytest.approx(k_theta(k) * 0.1 + tau, rel=1e-9)
    np.testing.assert_allclose(exo.tension - F0, k * R * RATIO * u, atol=1e-9)  # kinematic
    # In series with a compliant frame the spring side sticks after each reversal; while it
    # slides M = M_s(s) ± τ, so the M–u loop narrows to 2τ / (1 + k_θ / k_f).
    kf = 150.0
    violations = {
        "spring.coulomb": {"friction_Nm": tau},
        "frame.elastic": {"k_frame_Nm_per_rad": kf},
    }
    exo = labsim.exoskeleton_response(theta, 4000.0, k, violations)
    up, down = branch_moment(u, exo.moment, 0.1)
    assert up - down == pytest.approx(2 * tau / (1 + k_theta(k) / kf), rel=1e-6)
    excess = exo.moment - k_theta(k) * exo.spring_side
    assert np.all(np.abs(excess) <= tau + 1e-9)
    sliding = np.abs(np.diff(exo.spring_side)) > 0
    np.testing.assert_allclose(np.abs(excess[1:][sliding]), tau, rtol=1e-9)


def test_interface_friction_hysteresis_narrows_with_the_spring():
    # Friction τ in parallel with the interface's spring k_i, in series with the spring side:
    # the interface sticks while |M − k_i δ| ≤ τ and slides at M = k_i δ ± τ, so the M–u loop
    # is 2τ·k_θ/(k_i + k_θ) wide and the interface takes ∮ M dδ = τ Σ|Δδ|.
    k, ki, tau = 13600.0, 80.0, 0.5
    violations = {
        "interface.elastic": {"k_interface_Nm_per_rad": ki},
        "interface.coulomb": {"friction_Nm": tau},
    }
    _, theta = triangle_stride(0.2)
    u = theta - theta[0]
    exo = labsim.exoskeleton_response(theta, 4000.0, k, violations)
    up, down = branch_moment(u, exo.moment, 0.1)
    kt = k_theta(k)
    assert up - down == pytest.approx(2 * tau * kt / (ki + kt), rel=1e-6)
    excess = exo.moment - ki * exo.interface
    assert np.all(np.abs(excess) <= tau + 1e-9)
    step = np.diff(exo.interface)
    sliding = np.abs(step) > 1e-13
    np.testing.assert_allclose(excess[1:][sliding], tau * np.sign(step[sliding]), rtol=1e-9)
    # the work put in through the knee = the elastic energy left + τ Σ|Δδ| lost in the interface
    work = np.sum(0.5 * (exo.moment[1:] + exo.moment[:-1]) * np.diff(u))
    stored = 0.5 * ki * exo.interface[-1] ** 2 + 0.5 * kt * exo.spring_side[-1] ** 2
    lost = tau * np.abs(step).sum()
    assert work == pytest.approx(stored + lost, rel=1e-3) and lost > 0.1 * work
    np.testing.assert_allclose(u, exo.interface + exo.spring_side, atol=1e-12)


def long_strides(strides: int = 8, fs: float = 2000.0):
    """θ over several 2 s strides from a trial's first sample: a bump in each engaged window."""
    t = np.arange(round(strides * 2.0 * fs)) / fs
    phase = np.mod(t, 2.0)
    return t, 0.5 + 0.3 * np.sin(np.pi * np.minimum(phase, 0.7) / 0.7) ** 2


@pytest.mark.parametrize("rho", [0.015, -0.04])
def test_drifting_element_stiffness_is_linear_in_time(rho):
    t, theta = long_strides()
    for element, k in (("interface", 60.0), ("frame", 500.0)):
        key = "k_interface_Nm_per_rad" if element == "interface" else "k_frame_Nm_per_rad"
        violations = {
            f"{element}.elastic": {key: k},
            f"{element}.drifting": {"drift_per_s": rho},
        }
        exo = labsim.exoskeleton_response(theta, 2000.0, 9200.0, violations)
        x = exo.interface if element == "interface" else exo.frame
        assert np.abs(exo.moment).max() > 1.0
        np.testing.assert_allclose(exo.moment, k * (1 + rho * t) * x, rtol=1e-9, atol=1e-12)


@pytest.mark.parametrize("rho", [0.015, -0.02])
def test_drifting_spring_rate_from_its_recording(rho):
    k = 9200.0
    mk, an = sim({"spring.drifting": {"drift_per_s": rho}}, spring=k, strides=6)
    x = spring_stretch(mk)
    t = np.arange(x.size) / 100.0
    taut = x > 2e-3
    rate = (at_frames(an, "LC_SPRING")[taut] - F0) / x[taut]
    np.testing.assert_allclose(rate, k * (1 + rho * t[taut]), rtol=1e-6)
    free = engaged_frames(x.size, 0.81, 1.99)
    np.testing.assert_allclose(at_frames(an, "LC_SPRING")[free], F0, atol=1e-9)  # pretension


def test_viscous_spring_dissipates_its_damping_work():
    k, c = 13600.0, 60.0
    fs = 4000.0
    _, theta = sinus_stride(fs, 2.0)
    exo = labsim.exoskeleton_response(theta, fs, k, {"spring.viscous": {"c_spring_Ns_per_m": c}})
    x = R * RATIO * exo.spring_side
    taut = exo.tension > 0
    x_rate = np.concatenate([[0.0], np.diff(x) * fs])  # implicit Euler
    np.testing.assert_allclose(exo.tension[taut], (F0 + k * x + c * x_rate)[taut], atol=1e-9)
    engaged = np.arange(x.size) < round(0.7 * fs)  # the release then ramps M and s down
    side = R * RATIO * (exo.tension - F0) - KT * RATIO**2 * exo.spring_side
    np.testing.assert_allclose(exo.moment[engaged], side[engaged], atol=1e-9)
    work = np.sum(0.5 * (exo.tension[1:] + exo.tension[:-1]) * np.diff(x))  # ∮ F dx, a stride
    assert x[-1] == 0.0 and work == pytest.approx(np.sum(c * x_rate**2) / fs, rel=5e-3)


@pytest.mark.parametrize(
    ("key", "value", "k_scale", "r_scale", "n_scale", "kt_scale"),
    [
        ("spring.value", 1.15, 1.15, 1.0, 1.0, 1.0),
        ("pulley_radius.value", 0.9, 1.0, 0.9, 1.0, 1.0),
        ("chain_ratio.value", 1.12, 1.0, 1.0, 1.12, 1.0),
        ("tensioner.value", 8.0, 1.0, 1.0, 1.0, 8.0),
    ],
)
def test_transmission_values_scale_force_stretch_and_moment(
    key, value, k_scale, r_scale, n_scale, kt_scale
):
    k = 13600.0
    base = sim(spring=k)
    mk, an = sim({key: {"scale": value}}, spring=k)
    u = since_engagement(phantom_angle(mk))
    window = engaged_frames(len(u), 0.0, 0.69) & (u >= 0)
    rn = R * r_scale * RATIO * n_scale
    np.testing.assert_allclose(spring_stretch(mk)[window], rn * u[window], atol=1e-9)
    spring = at_frames(an, "LC_SPRING")
    np.testing.assert_allclose(spring[window] - F0, k * k_scale * rn * u[window], atol=1e-6)
    real = k_theta(k * k_scale, R * r_scale, RATIO * n_scale, KT * kt_scale)
    expected = (real - k_theta(k)) * u
    np.testing.assert_allclose(d_moment(mk, an, base[1])[window], expected[window], atol=1e-6)


def test_stiffening_spring_reads_on_its_length():
    k, a = 13600.0, 20.0
    mk, an = sim({"spring.stiffening": {"quadratic_per_m": a}}, spring=k)
    x = spring_stretch(mk)
    taut = x > 0
    force = at_frames(an, "LC_SPRING")
    expected = k * x[taut] * (1 + a * x[taut])
    np.testing.assert_allclose(force[taut] - F0, expected, rtol=1e-9, atol=1e-9)
    slack = force == 0.0
    if slack.any():  # slack at the root of F0 + k·x·(1 − a·x) = 0 below the pretension
        x_slack = (1 - np.sqrt(1 + 4 * a * F0 / k)) / (2 * a)
        np.testing.assert_allclose(x[slack], x_slack, atol=1e-9)


def test_play_delays_the_spring_loading():
    k, play = 6100.0, 0.03
    _, theta = sinus_stride()
    u = theta - theta[0]
    for violations, series in (
        ({}, k_theta(k)),
        (
            {"interface.elastic": {"k_interface_Nm_per_rad": 80.0}},
            1 / (1 / 80.0 + 1 / k_theta(k)),
        ),
    ):
        violations = {**violations, "transmission.play": {"play_rad": play}}
        exo = labsim.exoskeleton_response(theta, 4000.0, k, violations)
        np.testing.assert_allclose(exo.moment, series * np.maximum(u - play, 0.0), atol=1e-9)
        early = u < play
        np.testing.assert_allclose(exo.tension[early], F0)
        np.testing.assert_allclose(exo.spring_side[~early], exo.moment[~early] / k_theta(k))


@pytest.mark.parametrize("k_i", [None, 80.0])
def test_strap_play_is_a_dead_band_in_the_interface(k_i):
    # The bars turn freely within ±p/2 about the segments; the straps carry a moment only at an
    # end of the band (M > 0 at +p/2, M < 0 at −p/2). From the first engagement (the bars
    # centred) the chain loads once the knee has taken up p/2: M = K·max(u − p/2, 0) up and down
    # (the band dissipates nothing), K the series stiffness.
    k, play = 9200.0, 0.03
    violations = {"interface.play": {"play_rad": play}}
    series = k_theta(k)
    if k_i:
        violations["interface.elastic"] = {"k_interface_Nm_per_rad": k_i}
        series = 1 / (1 / k_i + 1 / k_theta(k))
    _, theta = triangle_stride(0.2)
    u = theta - theta[0]
    exo = labsim.exoskeleton_response(theta, 4000.0, k, violations)
    band = exo.interface - (exo.moment / k_i if k_i else 0.0)
    assert np.all(np.abs(band) <= play / 2 + 1e-12)
    loaded = np.abs(exo.moment) > 1e-9
    assert loaded.any() and not loaded.all()
    np.testing.assert_allclose(band[loaded], play / 2 * np.sign(exo.moment[loaded]), atol=1e-12)
    np.testing.assert_allclose(exo.moment, series * np.maximum(u - play / 2, 0.0), atol=1e-9)
    # The recording shows it: the bars sit p/2 off the segments wherever the spring pulls.
    mk, an = sim(violations, spring=k)
    offset = (
        phantom_angle(mk)
        - exo_angle(mk)
        - (k_theta(k) * (at_frames(an, "LC_SPRING") - F0) / (k * R * RATIO) / k_i if k_i else 0.0)
    )
    assert np.all(np.abs(offset) <= play / 2 + 1e-6)
    pulling = at_frames(an, "LC_SPRING") > F0 + 1.0
    np.testing.assert_allclose(offset[pulling], play / 2, atol=1e-6)


def test_clutch_delay_moves_the_engagement():
    k, delay = 9200.0, 0.05
    fs = 4000.0
    t, theta = sinus_stride(fs)
    exo = labsim.exoskeleton_response(theta, fs, k, {"clutch.delay": {"delay_s": delay}})
    before = t < delay
    np.testing.assert_allclose(exo.moment[before], 0.0)
    np.testing.assert_allclose(exo.tension[before], F0)
    start = np.argmax(~before)
    after = ~before & (theta >= theta[start])  # taut spring
    np.testing.assert_allclose(exo.moment[after], k_theta(k) * (theta[after] - theta[start]))


CHAIN = {
    "interface.elastic": {"k_interface_Nm_per_rad": 70.0},
    "interface.stiffening": {"stiffening_per_rad2": 300.0},
    "interface.viscous": {"c_interface_Nms_per_rad": 0.4},
    "interface.coulomb": {"friction_Nm": 0.2},
    "interface.drifting": {"drift_per_s": 0.01},
    "frame.elastic": {"k_frame_Nm_per_rad": 300.0},
    "frame.stiffening": {"stiffening_per_rad2": 5000.0},
    "frame.viscous": {"c_frame_Nms_per_rad": 5.0},
    "frame.drifting": {"drift_per_s": -0.01},
    "spring.value": {"scale": 0.9},
    "spring.stiffening": {"quadratic_per_m": 10.0},
    "spring.viscous": {"c_spring_Ns_per_m": 40.0},
    "spring.coulomb": {"friction_Nm": 0.3},
    "spring.drifting": {"drift_per_s": 0.008},
    "transmission.play": {"play_rad": 0.01},
    "pulley_radius.value": {"scale": 1.1},
    "chain_ratio.value": {"scale": 0.95},
    "tensioner.value": {"scale": 10.0},
}


def test_every_chain_law_together_stays_consistent():
    k = 18000.0
    fs = 4000.0
    t, theta = long_strides(4, fs)
    exo = labsim.exoskeleton_response(theta, fs, k, CHAIN)
    d, e, m, s = exo.interface, exo.frame, exo.moment, exo.spring_side
    step = np.concatenate([[0.0], np.diff(d) * fs])
    elastic_i = 70.0 * (1 + 0.01 * t) * (d + 300.0 * d**3)
    friction = m - elastic_i - 0.4 * step
    assert np.all(np.abs(friction) <= 0.2 + 1e-9)
    moving = np.abs(step) > 1e-9
    np.testing.assert_allclose(np.abs(friction[moving]), 0.2, rtol=1e-7)
    e_step = np.concatenate([[0.0], np.diff(e) * fs])
    frame = 300.0 * (1 - 0.01 * t) * (e + 5000.0 * e**3) + 5.0 * e_step
    np.testing.assert_allclose(m, frame, atol=1e-8)
    phase = np.mod(t, 2.0)
    engaged = (phase > 0.0) & (phase < 0.7)
    assert np.all(m[engaged] >= 0)  # the chain with play only pulls
    taut = engaged & (m > 0)
    u = theta - theta[np.floor(t / 2.0).astype(int) * round(2.0 * fs)]
    u_e = (d + e)[np.floor(t / 2.0).astype(int) * round(2.0 * fs)]
    np.testing.assert_allclose((u + u_e - d - e - s)[taut], 0.01, atol=1e-9)  # the play
    r, n, kt = 1.1 * R, 0.95 * RATIO, 10.0 * KT
    x = r * n * s
    x_rate = np.concatenate([[0.0], np.diff(x) * fs])
    k_t = 0.9 * k * (1 + 0.008 * t)
    spring = F0 + k_t * x * (1 + 10.0 * np.abs(x)) + 40.0 * x_rate
    tense = exo.tension > 0
    np.testing.assert_allclose(exo.tension[tense], spring[tense], atol=1e-7)
    side = r * n * (exo.tension - F0) - kt * n**2 * s
    assert np.all(np.abs(m - side)[taut] <= 0.3 + 1e-7)  # the spring side's friction


# --- channels ------------------------------------------------------------------------------


@pytest.mark.parametrize("cell", CELLS)
def test_gain_offset_and_drift_have_their_stated_size(cell):
    faults = {
        f"{cell}.gain": {"gain": 1.2},
        f"{cell}.offset": {"offset_N": 4.0},
        f"{cell}.drift": {"drift_N_per_s": -0.3},
    }
    (_, an0), (_, an1) = sim(), sim(faults)
    t = np.arange(an0[cell].size) / 1000.0
    np.testing.assert_allclose(an1[cell], 1.2 * an0[cell] + 4.0 - 0.3 * t, atol=1e-9)
    for other in set(CELLS) - {cell}:
        np.testing.assert_array_equal(an1[other], an0[other])
    shares = np.array([an0[c] for c in ANKLES])
    np.testing.assert_allclose(
        shares / shares.sum(axis=0), [[0.30], [0.33], [0.37]] * np.ones_like(shares), atol=1e-9
    )


def lag_samples(delayed: np.ndarray, reference: np.ndarray, max_lag: int = 80) -> int:
    """The lag (samples) that best aligns two signals' slopes, by cross-correlation."""
    a, b = np.diff(delayed), np.diff(reference)
    lags = np.arange(-max_lag, max_lag + 1)
    score = [
        np.dot(a[max_lag + k : a.size - max_lag + k], b[max_lag : b.size - max_lag]) for k in lags
    ]
    return int(lags[np.argmax(score)])


@pytest.mark.parametrize("cell", CELLS)
def test_a_cell_delay_lags_that_channel_alone(cell):
    delay = 0.012
    (_, an0), (_, an1) = sim(), sim({f"{cell}.delay": {"delay_s": delay}})
    assert lag_samples(an1[cell], an0[cell]) == 12
    np.testing.assert_allclose(an1[cell][12:], an0[cell][:-12], atol=1e-9)
    np.testing.assert_allclose(an1[cell][:12], an0[cell][0], atol=1e-9)  # at rest before
    for other in set(labsim.CHANNELS) - {cell}:
        np.testing.assert_array_equal(an1[other], an0[other])
    # a fraction of a sample reads the force between the samples
    (_, an2) = sim({f"{cell}.delay": {"delay_s": 0.01225}})
    between = 0.75 * an0[cell][1:-12] + 0.25 * an0[cell][:-13]
    assert np.median(np.abs(an2[cell][13:] - between)) < 1e-3
    assert np.abs(an2[cell][13:] - between).max() < 0.5  # at the clutch's kinks


@pytest.mark.parametrize("cell", CELLS)
def test_crosstalk_adds_a_share_of_the_other_true_force(cell):
    share = -0.08
    (_, an0), (_, an1) = sim(), sim({f"{cell}.crosstalk": {"share": share}})
    other = an0["LC_SPRING"] if cell in ANKLES else ankle_sum(an0)
    np.testing.assert_allclose(an1[cell] - an0[cell], share * other, atol=1e-9)


@pytest.mark.parametrize("delay", [0.025, -0.013])
def test_the_analog_clock_lags_every_analog_channel(delay):
    lag = round(delay * 1000)
    (_, an0), (_, an1) = sim(strides=4), sim({"clocks.delay": {"analog_delay_s": delay}}, strides=4)
    for c in CELLS:
        assert lag_samples(an1[c], an0[c]) == lag
        if lag > 0:
            np.testing.assert_allclose(an1[c][lag:], an0[c][:-lag], atol=1e-9)
        else:
            np.testing.assert_allclose(an1[c][:lag], an0[c][-lag:], atol=1e-9)
    rising = np.flatnonzero(np.diff(np.r_[0.0, an1["SYNC"]]) > 2.5)
    programmed = np.arange(4) * 2000 + lag
    if lag < 0:  # a lead: the first pulse is cut by the recording's start
        assert an1["SYNC"][: 20 + lag].tolist() == [5.0] * (20 + lag)
        programmed[0] = 0
    assert rising.tolist() == programmed.tolist()


@pytest.mark.parametrize("rate", [0.002, -0.0015])
def test_the_analog_clock_rate_stretches_every_analog_channel(rate):
    # The analog sample stamped t holds its value at t·(1 − ε): at the analog rate itself
    # (substeps = 1) that is the unshifted channel read at k·(1 − ε); SYNC's pulses follow.
    base = sim(strides=4, substeps=1)[1]
    an = sim({"clocks.drift": {"rate_error": rate}}, strides=4, substeps=1)[1]
    k = np.arange(base["LC_SPRING"].size)
    for c in CELLS:
        np.testing.assert_allclose(an[c], np.interp(k * (1 - rate), k, base[c]), atol=1e-9)
    rising = np.flatnonzero(np.diff(np.r_[0.0, an["SYNC"]]) > 2.5)
    programmed = np.ceil(np.arange(4) * 2000 / (1 - rate) - 1e-9).astype(int)
    assert rising.tolist() == programmed[programmed < k.size].tolist()


@pytest.mark.parametrize("q", [0.4, -0.3])
def test_nonlinear_cells_record_force_times_one_plus_q_force(q):
    (_, an0), (_, an1) = sim(), sim({"cell_linearity.nonlinearity": {"quadratic_per_kN": q}})
    for c in CELLS:
        expected = an0[c] * (1 + q * np.abs(an0[c]) / 1000.0)
        np.testing.assert_allclose(an1[c], expected, rtol=1e-12, atol=1e-12)
    np.testing.assert_array_equal(an1["SYNC"], an0["SYNC"])


@pytest.mark.parametrize("tilt", [0.12, 0.3])
def test_tilted_cells_record_a_share_of_the_horizontal_force(tilt):
    (mk, an0) = sim()
    (_, plus), (_, minus) = (
        sim({"cell_direction.tilt": {"tilt_rad": tilt}}),
        sim({"cell_direction.tilt": {"tilt_rad": -tilt}}),
    )
    fy = (ankle_sum(plus) + ankle_sum(minus)) / (2 * np.cos(tilt))
    fx = (ankle_sum(plus) - ankle_sum(minus)) / (2 * np.sin(tilt))
    np.testing.assert_allclose(fy, ankle_sum(an0), atol=1e-9)
    for c, share in zip(ANKLES, (0.30, 0.33, 0.37), strict=True):
        np.testing.assert_allclose(plus[c], share * (fy * np.cos(tilt) + fx * np.sin(tilt)))
    # At rest (the first sample) the hip balance gives F_x = g (m1 x1 + m2 x2) / d by hand.
    hip, knee, ankle = centre(mk, "HIP")[0], centre(mk, "KNEE")[0], centre(mk, "ANK")[0]
    com1 = C1 / L1 * (knee - hip)
    com2 = knee - hip + C2 / L2 * (ankle - knee)
    expected = 9.81 * (M1 * com1[0] + M2 * com2[0]) / (hip[1] - ankle[1])
    assert fx[0] == pytest.approx(expected, rel=1e-6)
    assert expected > 0  # the knee and the masses sit anterior: the hexapod pulls forward


# --- several at once, determinism and validation ----------------------------------------------


def test_every_violation_at_once_gives_a_plausible_recording():
    rng = np.random.default_rng(3)
    violations = {}
    for key, row in TABLE.items():
        low, high = row["sizes"]
        size = rng.uniform(low, high)
        if np.isinf(row["neutral"]):
            value = size
        elif row["either_sign"]:
            value = row["neutral"] + rng.choice([-1.0, 1.0]) * size
        else:
            value = size
        violations[key] = {row["parameter"]: float(value)}
    for spring in (3400.0, 21700.0):
        mk, an = sim(violations, spring=spring, strides=4, quiet=False)
        assert all(np.isfinite(v).all() for v in (*mk.values(), *an.values()))
        assert all(np.abs(an[c]).max() < 5000 for c in CELLS)  # N
        assert np.abs(np.concatenate(list(mk.values()))).max() < 3.0  # m, the capture volume


def test_random_chain_combinations_stay_in_step():
    # Random subsets of the chain's laws at random table sizes: the kinematic chain closes.
    rng = np.random.default_rng(11)
    fs = 4000.0
    t, theta = long_strides(3, fs)
    keys = [k for k in TABLE if k.split(".")[0] in ("interface", "frame", "spring")] + [
        "transmission.play",
        "tensioner.value",
    ]
    for _ in range(12):
        chosen = [k for k in keys if rng.random() < 0.5]
        chosen += [need for k in chosen for need in TABLE[k]["needs"] if need not in chosen]
        violations = {}
        for key in chosen:
            row = TABLE[key]
            value = rng.uniform(*row["sizes"])
            if row["either_sign"]:
                value = row["neutral"] + rng.choice([-1.0, 1.0]) * value
            violations[key] = {row["parameter"]: float(value)}
        exo = labsim.exoskeleton_response(theta, fs, float(rng.uniform(3400, 21700)), violations)
        for series in exo:
            assert np.isfinite(series).all(), violations
        start = np.floor(t / 2.0).astype(int) * round(2.0 * fs)
        u = theta - theta[start] + (exo.interface + exo.frame)[start]
        gap = u - exo.interface - exo.frame - exo.spring_side
        play = violations.get("transmission.play", {"play_rad": 0.0})["play_rad"]
        engaged = (np.mod(t, 2.0) > 0) & (np.mod(t, 2.0) < 0.7)
        taut = engaged & (exo.moment != 0)
        np.testing.assert_allclose(gap[taut], play, atol=1e-9, err_msg=str(violations))
        assert np.all(gap[engaged] <= play + 1e-9)


def between_study(violations: dict, seed: int = 11):
    return labsim.simulate_study(
        cycle_csv=CYCLE,
        springs_N_per_m=[9200.0, 13600.0, 21700.0, 6100.0],
        strides=3,
        ramp_strides=1,
        violations=violations,
        seed=seed,
        **QUIET,
    )


def test_straps_re_fastened_between_trials_change_the_interface_stiffness():
    # Trial i's interface stiffness is k·(1 + s·z_i), z_i drawn per trial and reported; the
    # recording alone gives it back as M/δ (the spring cell's moment over the bars' lag).
    k_i, spread = 70.0, 0.25
    violations = {
        "interface.elastic": {"k_interface_Nm_per_rad": k_i},
        "straps_between.between": {"spread": spread},
    }
    trials = between_study(violations)
    z = [trial.between["straps_between.between"]["z"] for trial in trials]
    assert len(set(z)) == len(z) and max(map(abs, z)) <= 3.0
    for trial, z_i in zip(trials, z, strict=True):
        reported = trial.between["straps_between.between"]["k_interface_Nm_per_rad"]
        assert reported == pytest.approx(k_i * (1 + spread * z_i), rel=1e-12)
        mk = {m: trial.points_mm[:, i, :].T / 1000.0 for i, m in enumerate(labsim.MARKERS)}
        spring = trial.analogs[labsim.CHANNELS.index("LC_SPRING")][::10]
        k = trial.spring_N_per_m
        moment = k_theta(k) * (spring - F0) / (k * R * RATIO)
        interface = phantom_angle(mk) - exo_angle(mk)
        window = engaged_frames(len(spring), 0.05, 0.65) & (moment > 1.0)
        assert np.median(moment[window] / interface[window]) == pytest.approx(reported, rel=1e-3)
    again, other = between_study(violations), between_study(violations, seed=12)
    assert [t.between for t in again] == [t.between for t in trials]
    assert [t.between for t in other] != [t.between for t in trials]


def test_the_spring_cell_re_zeroed_between_trials_shifts_it_alone():
    spread = 3.0
    base = between_study({})
    trials = between_study({"cells_zero_between.between": {"spread_N": spread}})
    spring = labsim.CHANNELS.index("LC_SPRING")
    for trial, plain in zip(trials, base, strict=True):
        drawn = trial.between["cells_zero_between.between"]
        assert drawn["offset_N"] == pytest.approx(spread * drawn["z"], rel=1e-12)
        shift = trial.analogs - plain.analogs
        np.testing.assert_allclose(shift[spring], drawn["offset_N"], atol=1e-9)
        np.testing.assert_array_equal(np.delete(shift, spring, axis=0), 0.0)
        np.testing.assert_array_equal(trial.points_mm, plain.points_mm)
        assert plain.between == {}


def test_between_trial_draws_are_standard_normal_within_three():
    from exobench.phantom.validation.labsim.study import between_draws

    violations = {"cells_zero_between.between": {"spread_N": 1.0}}
    z = np.array(between_draws(violations, 4000, seed=5)["cells_zero_between.between"])
    assert abs(z.mean()) < 0.06 and z.std() == pytest.approx(1.0, abs=0.04)
    assert np.abs(z).max() <= 3.0
    assert between_draws({}, 4, seed=5) == {}


def test_same_seed_gives_same_bytes(tmp_path):
    kwargs = {
        "springs_N_per_m": [3400.0, 6100.0],
        "strides": 3,
        "occlusions_per_marker": 1.5,
        "violations": {"interface.elastic": {"k_interface_Nm_per_rad": 90.0}},
    }
    a = study(tmp_path / "a", **kwargs)
    b = study(tmp_path / "b", **kwargs)
    c = study(tmp_path / "c", seed=8, **kwargs)
    for name in ("manifest.csv", "k3400.c3d", "k6100.c3d"):
        assert filecmp.cmp(a.parent / name, b.parent / name, shallow=False)
    assert not filecmp.cmp(a.parent / "k3400.c3d", c.parent / "k3400.c3d", shallow=False)


def test_occlusions_are_nan_gaps():
    mk, an = sim(strides=3, occlusions_per_marker=2.0)
    gaps = np.array([np.isnan(mk[m]) for m in RIG_MARKERS])  # (12, frames, 3)
    assert gaps.any()
    assert (gaps.all(axis=2) == gaps.any(axis=2)).all()  # all three coordinates at once
    assert all(np.isfinite(v).all() for v in an.values())


@pytest.mark.parametrize(
    "violations",
    [
        {"interface.viscous": {"c_interface_Nms_per_rad": 0.3}},  # needs interface.elastic
        {"frame.elastic": {"k_frame": 100.0}},  # wrong parameter name
        {"frame.elastic": {"k_frame_Nm_per_rad": 100.0, "extra": 1.0}},
        {"backlash.play": {"play_rad": 0.1}},  # unknown term
        {"frame_compliance": {"k_frame_Nm_per_rad": 100.0}},  # an old effect name
        {"LC_SYNC.gain": {"gain": 1.1}},
        {"interface.elastic": {"k_interface_Nm_per_rad": -40.0}},
        {"interface.elastic": {"k_interface_Nm_per_rad": float("inf")}},
        {"spring.coulomb": {"friction_Nm": -0.1}},
        {"knee.viscous": {"c_Nms_per_rad": -0.1}},
        {"LC_ANKLE_2.gain": {"gain": 0.0}},
        {"LC_SPRING.delay": {"delay_s": -0.01}},
        {"clutch.delay": {"delay_s": -0.01}},
        {"shank_mass.value": {"scale": 0.0}},
        {"spring.value": {"scale": float("nan")}},
        {"spring.drifting": {"drift_per_s": -0.2}},  # k(t) ≤ 0 within the 8 s trial
        {"tensioner.value": {"scale": 1000.0}},  # the tensioner overpowers the spring
        {"ankle_path.offset": {"offset_mm": 700.0}},  # out of the leg's reach
        {"cell_direction.tilt": {"tilt_rad": True}},
        {"interface.play": {"play_rad": -0.01}},
        {"hip.elastic": {"k_Nm_per_rad": -1.0}},
        {"clocks.drift": {"rate_error": 0.05}},
        {"straps_between.between": {"spread": 0.2}},  # needs interface.elastic
        {  # k·(1 + s·z) ≤ 0 for a draw within ±3
            "interface.elastic": {"k_interface_Nm_per_rad": 60.0},
            "straps_between.between": {"spread": 0.4},
        },
        {"cells_zero_between.between": {"spread_N": -1.0}},
    ],
)
def test_bad_violations_are_refused(violations):
    with pytest.raises(ValueError):
        sim(violations, strides=4)
