"""The independent emulator generator: contract, physics and violations from first principles."""

import filecmp
import functools
import itertools
import json
import math
import re
from pathlib import Path

import numpy as np
import pandas as pd
import pytest
from scipy import signal

import assumption_rows
from assumption_rows import relaxations, table_lines
from exobench.emulator.validation import labsim
from exobench.emulator.validation.labsim.sensors import torque_channel

ROOT = Path(__file__).resolve().parents[1]
ASSUMPTIONS = ROOT / "docs/emulator_assumptions.md"
# The rig as docs/rig.md §3 and config/config.yaml's emulator block give it.
A = 0.044 / 0.048
FLEXION, EXTENSION = (-0.3, 7.0, 1.0), (-0.3, 6.5, 0.0)
STEP = 360.0 / 5000
EQ_DEG = 40.0
TORQUE_SD, MOCAP_SD = 0.02, 0.8
BRACE = ["time_s", "brace_angle_deg", "brace_torque_Nm", "desired_torque_Nm", "motor_angle_deg"]
QUIET = {"torque_noise_Nm": 0.0, "mocap_noise_deg": 0.0}


# --- recordings in memory ------------------------------------------------------------------------


def _frozen(value):
    """A hashable copy of nested dicts, lists and tuples (for the cache)."""
    if isinstance(value, dict):
        return tuple(sorted((k, _frozen(v)) for k, v in value.items()))
    if isinstance(value, list | tuple):
        return tuple(_frozen(v) for v in value)
    return value


def _thawed(value):
    """The dicts of _frozen back (tuples of pairs with string keys), the rest as it is."""
    if (
        isinstance(value, tuple)
        and value
        and all(isinstance(v, tuple) and len(v) == 2 and isinstance(v[0], str) for v in value)
    ):
        return {k: _thawed(v) for k, v in value}
    return value


@functools.cache
def _simulated(frozen, speed, stiffness, duration, quiet, seed, extra):
    args = {
        "speeds_m_per_s": [speed],
        "stiffnesses_Nm_per_rad": [stiffness],
        "duration_s": duration,
        "violations": _thawed(frozen) if frozen else {},
        "seed": seed,
        **{key: _thawed(value) for key, value in extra},
    }
    if quiet:
        args.update(QUIET)
    return labsim.simulate_study(**args)[0]


def sim(violations=None, *, speed=0.8, stiffness=3.5, duration=6.0, quiet=True, seed=5, **extra):
    """One simulated trial (cached)."""
    extra = tuple(sorted((k, _frozen(v)) for k, v in extra.items()))
    return _simulated(_frozen(violations or {}), speed, stiffness, duration, quiet, seed, extra)


def columns(trial) -> dict[str, np.ndarray]:
    """The recorded channels by name (the brace file's at 1 kHz, knee_flexion_deg at 100 Hz)."""
    out = dict(zip(BRACE, trial.brace.T, strict=True))
    out["knee_flexion_deg"] = trial.mocap[:, 1]
    return out


def quantized(angle: np.ndarray) -> np.ndarray:
    return STEP * np.round(angle / STEP)


def spring_torque(angle_deg, kappa, eq_deg=EQ_DEG, a=0.0):
    """τ = κ·x·(1 + a·x), x = max(0, θ_eq − θ) in rad (docs/rig.md §3)."""
    x = np.radians(np.maximum(eq_deg - angle_deg, 0.0))
    return kappa * x * (1 + a * x)


def calibration_torque(stretch, rate, flexion=FLEXION, extension=EXTENSION):
    """τ ≥ 0 where b(τ) = stretch, b the calibration of the rate's direction (eq. 5.8's blend)."""
    w = np.clip((rate + 25.0) / 50.0, 0.0, 1.0)
    b, c, d = (w * f + (1 - w) * e for f, e in zip(flexion, extension, strict=True))
    x = stretch - d
    root = np.sqrt(np.maximum(c * c + 4 * b * x, 0.0))
    return np.where(x > 0, 2 * x / (c + root), 0.0)


def rebuilt_clutch(angle_deg: np.ndarray) -> np.ndarray:
    """Table 6.1 on a recorded encoder angle: the 6 Hz Butterworth of its derivative, engage at a
    peak flexion beyond 40° (ω from > 0 to ≤ 0), release at the next peak extension (< 0 to ≥ 0)."""
    rate = signal.lfilter(
        *signal.butter(2, 6.0, fs=1000.0), np.diff(angle_deg, prepend=angle_deg[0]) * 1000
    )
    on, out = False, np.zeros(angle_deg.size, dtype=bool)
    for i in range(1, angle_deg.size):
        if not on and angle_deg[i] > 40.0 and rate[i - 1] > 0 and rate[i] <= 0:
            on = True
        elif on and rate[i - 1] < 0 and rate[i] >= 0:
            on = False
        out[i] = on
    return out


# --- the table of docs/emulator_assumptions.md ---------------------------------------------------

TABLE = relaxations(ASSUMPTIONS)


def least_visible(key: str) -> list[float]:
    """The table's smallest visible sizes of a relaxation, as values (both signs where ±)."""
    return assumption_rows.least_visible(TABLE[key])


def test_the_table_and_the_generator_name_the_same_violations():
    assert len(TABLE) == table_lines(ASSUMPTIONS) == 41
    assert set(TABLE) == set(labsim.VIOLATIONS)
    for key, row in TABLE.items():
        assert labsim.VIOLATIONS[key] == (row["parameter"],), key
        assert labsim.REQUIRES.get(key, ()) == row["needs"], key
    assert set(labsim.BETWEEN) == {key for key in TABLE if key.endswith(".between")}


# --- the contract (docs/rig.md §3) ------------------------------------------------------------


def test_files_follow_the_rig_contract(tmp_path):
    kwargs = {
        "speeds_m_per_s": [0.8, 1.2],
        "stiffnesses_Nm_per_rad": [0.0, 3.5],
        "duration_s": 3.0,
        "violations": {"encoder.step": {"drop_deg": 4.6}},
        "seed": 2,
    }
    manifest = labsim.write_study(tmp_path, **kwargs)
    trials = labsim.simulate_study(**kwargs)
    table = pd.read_csv(manifest)
    assert list(table.columns) == list(labsim.MANIFEST_COLUMNS) == [
        "trial", "file", "mocap_file", "speed_m_per_s", "stiffness_Nm_per_rad", "side",
    ]  # fmt: skip
    assert table["trial"].tolist() == ["v08_k00", "v08_k35", "v12_k00", "v12_k35"]
    assert table["speed_m_per_s"].tolist() == [0.8, 0.8, 1.2, 1.2]
    assert table["stiffness_Nm_per_rad"].tolist() == [0.0, 3.5, 0.0, 3.5]
    assert set(table["side"]) == {"right"}
    for row, trial in zip(table.itertuples(), trials, strict=True):
        brace = pd.read_csv(tmp_path / row.file)
        mocap = pd.read_csv(tmp_path / row.mocap_file)
        assert list(brace.columns) == BRACE
        assert list(mocap.columns) == ["time_s", "knee_flexion_deg"]
        # 1000 Hz and 100 Hz on one clock from 0, covering the duration
        np.testing.assert_array_equal(brace["time_s"], np.arange(3000) / 1000.0)
        np.testing.assert_array_equal(mocap["time_s"], np.arange(300) / 100.0)
        # whole encoder counts, plausible values
        counts = brace["brace_angle_deg"] / STEP
        np.testing.assert_allclose(counts, np.round(counts), atol=1e-6)
        assert brace["brace_angle_deg"].between(-30, 150).all()
        assert mocap["knee_flexion_deg"].between(-30, 150).all()
        assert brace[["brace_torque_Nm", "desired_torque_Nm"]].abs().max().max() < 30
        assert brace["motor_angle_deg"].abs().max() < 360
        # the files hold the simulated arrays (printed below their noise)
        np.testing.assert_allclose(brace.to_numpy(), trial.brace, atol=6e-6)
        np.testing.assert_allclose(mocap.to_numpy(), trial.mocap, atol=6e-5)
        truth = json.loads((tmp_path / "truth" / f"{row.trial}.json").read_text())
        assert truth == json.loads(json.dumps(trial.truth))
        assert truth["trial"] == row.trial and truth["seed"] == 2
        assert truth["violations"] == {"encoder.step": {"drop_deg": 4.6}}
        assert 0.6 <= truth["drawn"]["encoder.step"]["time_s"] <= 2.4  # 20–80 % of the trial
        assert all(0 <= h < 3.0 for h in truth["heel_strikes_s"])


def test_the_encoder_reports_whole_counts_of_the_brace_angle():
    trial = sim()
    np.testing.assert_allclose(trial.brace[:, 1], quantized(trial.state.brace_deg), atol=1e-12)
    # rigid cuffs: the brace is the knee
    np.testing.assert_allclose(trial.state.brace_deg, trial.state.knee_deg, atol=1e-12)


def test_motion_capture_reads_the_knee_every_tenth_sample():
    trial = sim()
    np.testing.assert_allclose(trial.mocap[:, 1], trial.state.knee_deg[::10], atol=1e-9)


def test_noise_has_the_stated_levels():
    quiet, noisy = columns(sim(duration=10.0)), columns(sim(duration=10.0, quiet=False))
    torque = noisy["brace_torque_Nm"] - quiet["brace_torque_Nm"]
    knee = noisy["knee_flexion_deg"] - quiet["knee_flexion_deg"]
    # the load cell's white noise passes the 20 Hz filter: its SD shrinks by the filter's norm
    impulse = signal.lfilter(*signal.butter(2, 20.0, fs=1000.0), np.eye(1, 2000)[0])
    assert torque.std() == pytest.approx(TORQUE_SD * np.linalg.norm(impulse), rel=0.08)
    assert knee.std() == pytest.approx(MOCAP_SD, rel=0.08)
    assert abs(torque.mean()) < 0.002 and abs(knee.mean()) < 0.1
    assert abs(np.corrcoef(knee[1:], knee[:-1])[0, 1]) < 0.05  # white
    for name in ("brace_angle_deg", "desired_torque_Nm", "motor_angle_deg"):
        np.testing.assert_array_equal(noisy[name], quiet[name])


@pytest.mark.parametrize("speed", [0.8, 1.2])
def test_the_gait_walks_like_a_treadmill_walker(speed):
    trial = sim(speed=speed, stiffness=0.0, duration=30.0)
    knee, heel = trial.state.knee_deg, np.array(trial.truth["heel_strikes_s"])
    strides = np.diff(heel)
    assert 0.9 < strides.mean() < 1.4 and 0.005 < strides.std() / strides.mean() < 0.04
    swing, loading, at_strike, late = [], [], [], []
    for start, stop in itertools.pairwise(heel):
        stride = knee[round(start * 1000) : round(stop * 1000)]
        phase = np.linspace(0, 1, stride.size, endpoint=False)
        swing.append(stride.max())
        assert 0.6 < phase[stride.argmax()] < 0.85  # the peak flexion in swing
        loading.append(stride[phase < 0.3].max())  # the loading peak of early stance
        at_strike.append(stride[0])
        late.append(stride[phase > 0.85].min())
    assert 55.0 <= np.mean(swing) <= 65.0 and 50.0 < min(swing) and max(swing) < 70.0
    assert 10.0 < np.mean(loading) < 25.0
    assert np.all(np.array(at_strike) < 8.0)  # heel strike near full extension
    # the peak extension of terminal swing comes just before the next heel strike, a little lower
    rise = np.array(at_strike[1:]) - np.array(late[:-1])
    assert np.all((rise > -0.5) & (rise < 4.0))


# --- the controller and the physics ----------------------------------------------------------


@pytest.mark.parametrize(("speed", "stiffness"), [(0.8, 3.5), (1.2, 2.0)])
def test_desired_torque_is_the_spring_law_while_table_61_engages(speed, stiffness):
    # Rebuilt from the recorded encoder alone: the clutch engages at every peak flexion beyond
    # 40° and releases at the next peak extension; while engaged, τ = κ·max(0, θ_eq − θ).
    brace = columns(sim(speed=speed, stiffness=stiffness, duration=8.0))
    angle, desired = brace["brace_angle_deg"], brace["desired_torque_Nm"]
    engaged = rebuilt_clutch(angle)
    settled = np.arange(angle.size) > 500  # the rebuilt filter starts from rest at 0 s
    expected = np.where(engaged, spring_torque(angle, stiffness), 0.0)
    np.testing.assert_allclose(desired[settled], expected[settled], atol=1e-12)
    assert engaged[settled].any() and (desired > 0.5).any()


def test_table_51_marks_each_stride_s_events_in_order():
    # The controller's real-time events (Table 5.1, knee): a peak flexion beyond 40°, then a peak
    # extension below 20°, then the heel strike at the velocity's next fall; the clutch engages
    # at the same peak flexions (Table 6.1).
    trial = sim(duration=12.0)
    events = trial.truth["controller"]
    times = {k: np.array(events[f"{k}_s"]) for k in ("peak_flexions", "peak_extensions")}
    times["heel_strikes"] = np.array(events["heel_strikes_s"])
    order = sorted((t, k[5]) for k, ts in times.items() for t in ts)  # f(lexion), e(xt.), s(trike)
    kinds = "".join(kind for _, kind in order)
    assert re.fullmatch(r"e?s?(fes)*f?e?", kinds), kinds
    angle = trial.brace[:, 1]
    assert np.all(angle[np.round(times["peak_flexions"] * 1000).astype(int)] > 40.0)
    assert np.all(angle[np.round(times["peak_extensions"] * 1000).astype(int)] < 20.0)
    truth = np.array(trial.truth["heel_strikes_s"])
    found = times["heel_strikes"]
    lags = [found[found >= h][0] - h for h in truth if (found >= h).any()]
    assert len(lags) >= len(truth) - 1 and 0.0 < min(lags) and max(lags) < 0.15
    onsets = [on for on, _ in events["engaged_s"]]
    np.testing.assert_allclose(onsets, times["peak_flexions"][: len(onsets)], atol=1.5e-3)
    np.testing.assert_array_equal(
        [(round(a * 1000), round(b * 1000)) for a, b in events["engaged_s"]],
        intervals(trial.state.engaged),
    )


def engagements(engaged: np.ndarray) -> list[slice]:
    """The engaged intervals, whole ones only."""
    edges = np.diff(engaged.astype(int))
    on, off = np.flatnonzero(edges == 1) + 1, np.flatnonzero(edges == -1) + 1
    return [slice(a, off[off > a][0]) for a in on if (off > a).any()]


def test_the_spring_stores_half_kappa_x_squared_per_engagement():
    # −∫ τ dθ over an engagement of the spring law is ½κ·x² at its release (x = θ_eq − θ, rad):
    # the recorded desired torque against the recorded angle, trapezoids.
    kappa = 3.5
    trial = sim(stiffness=kappa, duration=12.0)
    brace = columns(trial)
    angle, desired = np.radians(brace["brace_angle_deg"]), brace["desired_torque_Nm"]
    energies = []
    for window in engagements(trial.state.engaged):
        theta, tau = angle[window], desired[window]
        energy = -np.sum(0.5 * (tau[1:] + tau[:-1]) * np.diff(theta))
        x_end = np.radians(EQ_DEG) - theta[-1]
        assert energy == pytest.approx(0.5 * kappa * x_end**2, abs=1e-4)
        energies.append(energy)
    assert len(energies) >= 8
    assert 0.4 < np.mean(energies) < 0.9  # Heer: ~0.63 J at 3.5 N·m/rad and 0.8 m/s


def test_the_cable_delivers_its_calibration():
    # The rig's own torque: b⁻¹ of the stretch θ_m − A·θ_b, per direction of the brace's motion.
    trial = sim(duration=8.0)
    state = trial.state
    rate = np.gradient(state.brace_deg, 1e-3)
    stretch = state.motor_deg - A * state.brace_deg
    rate_step = np.diff(state.brace_deg, prepend=state.brace_deg[0]) * 1000.0
    expected = calibration_torque(stretch, rate_step)
    np.testing.assert_allclose(state.torque_Nm[1:], expected[1:], atol=1e-9)  # 0: rate unknown
    # The recording: the 20 Hz filter of the calibration's torque at the recorded motor and
    # encoder angles, away from reversals of the motion (the direction is then plain).
    brace = columns(trial)
    recorded_stretch = brace["motor_angle_deg"] - A * brace["brace_angle_deg"]
    estimate = calibration_torque(recorded_stretch, rate)
    filtered = signal.lfilter(*signal.butter(2, 20.0, fs=1000.0), estimate)
    plain = np.convolve(np.abs(rate) > 60.0, np.ones(80), mode="full")[: rate.size] == 80
    plain[:500] = False
    assert plain.sum() > 2000
    np.testing.assert_allclose(brace["brace_torque_Nm"][plain], filtered[plain], atol=0.01)
    assert np.abs(brace["brace_torque_Nm"]).max() > 1.5


def test_the_torque_channel_is_a_20_hz_butterworth():
    # Step response of the causal second-order Butterworth (ζ = 1/√2, ω = 2π·20 Hz) half a sample
    # ahead (the bilinear map integrates by trapezoids), its −3 dB point at 20 Hz, unit gain.
    t = (np.arange(3000) - 1000) / 1000.0
    step = torque_channel((t >= 0).astype(float), t, {}, 0.0, np.zeros_like(t))
    zeta, w = 1 / math.sqrt(2), 2 * math.pi * 20.0
    wd = w * math.sqrt(1 - zeta**2)
    after = t[t >= 0] + 0.0005
    expected = 1 - np.exp(-zeta * w * after) * (
        np.cos(wd * after) + zeta / math.sqrt(1 - zeta**2) * np.sin(wd * after)
    )
    np.testing.assert_allclose(step[t >= 0], expected, atol=0.004)
    assert step.max() == pytest.approx(1 + math.exp(-math.pi), abs=0.005)  # 4.3 % overshoot
    assert step[-1] == pytest.approx(1.0, abs=1e-9)
    np.testing.assert_array_equal(step[t < 0], 0.0)
    sine = np.sin(2 * np.pi * 20.0 * t)
    out = torque_channel(sine, t, {}, 0.0, np.zeros_like(t))
    assert np.abs(out[t > 0.5]).max() == pytest.approx(1 / math.sqrt(2), abs=0.01)


def test_transparent_walking_asks_and_gets_little_torque():
    # κ = 0: the controller only keeps the cable at its zero-torque length (eq. 5.4).
    brace = columns(sim(stiffness=0.0, duration=8.0, quiet=False))
    np.testing.assert_array_equal(brace["desired_torque_Nm"], 0.0)
    assert np.abs(brace["brace_torque_Nm"]).max() < 0.35
    assert np.sqrt(np.mean(brace["brace_torque_Nm"] ** 2)) < 0.1


# --- each violation: its channels, visibly ------------------------------------------------------

TORQUE_ONLY = {"brace_torque_Nm"}
CONTROL = {"brace_torque_Nm", "desired_torque_Nm", "motor_angle_deg"}
THROUGH_BRACE = {"brace_angle_deg", *CONTROL}
KNEE_SEEN = {"knee_flexion_deg"}


def expected_changes(key: str) -> set[str]:
    """The channels a violation changes, by the rig's physics (rigid cuffs unless it needs them)."""
    row = key.split(".")[0]
    if row in ("cuff", "hinge", "encoder", "straps_between"):
        return THROUGH_BRACE  # the brace's angle feeds the controller: its torque and set point
    if row in ("spring", "clutch_engage", "clutch_release", "velocity_estimate"):
        return CONTROL  # the desired torque moves the set point and the delivered torque
    if row in ("mocap", "clocks", "mocap_zero_between"):
        return KNEE_SEEN
    # the cable, its calibration and ratio, the motor encoder (the servo holds its reading on the
    # set point, the pulley turns reading / g), the torque sensor
    return TORQUE_ONLY


def changed(base, other) -> set[str]:
    a, b = columns(base), columns(other)
    return {name for name in a if not np.array_equal(a[name], b[name])}


# the noise of each measured channel: the torque's and motion capture's, the encoder's counts
NOISE = {
    "brace_torque_Nm": TORQUE_SD,
    "knee_flexion_deg": MOCAP_SD,
    "brace_angle_deg": STEP / 12**0.5,
}


def detection_z(base, other) -> float:
    """Ideal-observer detection of a known change in white noise: z² = Σ (Δ/σ)², all channels."""
    a, b = columns(base), columns(other)
    return float(np.sqrt(sum(np.sum(((b[c] - a[c]) / sd) ** 2) for c, sd in NOISE.items())))


def with_needs(key: str, value: float) -> tuple[dict, dict, dict]:
    """(baseline, violated, extra arguments): needs at their least visible size, the term added;
    a between-trial relaxation in a trial one SD off, a count drop mid-trial."""
    base = {
        need: {TABLE[need]["parameter"]: least_visible(need)[0]} for need in TABLE[key]["needs"]
    }
    extra = {"between_z": {key: [1.0]}} if key in labsim.BETWEEN else {}
    if key == "encoder.step":
        extra["drop_time_s"] = 4.0
    return base, {**base, key: {TABLE[key]["parameter"]: value}}, extra


CASES = [(key, value) for key in TABLE for value in least_visible(key)]


@pytest.mark.parametrize(("key", "value"), CASES, ids=[f"{k}={v:g}" for k, v in CASES])
def test_each_violation_changes_its_channels_visibly(key, value):
    # Eight seconds at 0.8 m/s against 3.5 N·m/rad with the stated noise: the violation at its
    # least visible size changes exactly its channels and an ideal observer sees it (z > 5).
    base_violations, violations, extra = with_needs(key, value)
    base = sim(base_violations, duration=8.0, quiet=False, **extra)
    if key == "clutch_engage.delay":
        # A late engagement changes nothing while the knee is still above θ_eq (the spring asks
        # for nothing there): it shows once d passes the time from Table 6.1's engagement to θ_eq.
        hidden = hidden_engagement_delay(base)
        bad = sim(violations, duration=8.0, quiet=False, **extra)
        assert (changed(base, bad) == set()) == (round(value * 1000) <= round(hidden * 1000))
        violations = {key: {TABLE[key]["parameter"]: max(value, hidden + 0.02)}}
    bad = sim(violations, duration=8.0, quiet=False, **extra)
    assert changed(base, bad) == expected_changes(key)
    z = detection_z(base, bad)
    assert z > 5.0, f"{key} = {value}: detection z = {z:.1f}"


def hidden_engagement_delay(trial) -> float:
    """The shortest time (s) from an engagement to the encoder's first angle below θ_eq."""
    angle = trial.brace[:, 1]
    times = []
    for window in engagements(trial.state.engaged):
        below = np.flatnonzero(angle[window] < EQ_DEG)
        times.append(below[0] / 1000.0)
    return min(times)


# --- each law, from the rig's true signals and the recording -------------------------------------


def cuff_recursion(state, time, c, tc, beta=0.0, friction=0.0, drift=0.0):
    """δ_i from τ_{i−1} (the cuff law): towards c(t)·τ'/(1 + β|τ'|) with exp(−h/T), τ' = τ ∓ τ_s
    once |τ − τ_el(δ)| > τ_s (τ_el(δ) = δ/(c − β|δ|)), else δ sticks; from the first sample's δ."""
    tau = state.torque_Nm
    delta = np.empty(tau.size)
    delta[0] = state.brace_deg[0] - state.knee_deg[0]
    decay = math.exp(-1e-3 / tc)
    for i in range(1, tau.size):
        ct = c * (1 + drift * max(time[i], 0.0))
        carried = delta[i - 1] / (ct - beta * abs(delta[i - 1]))
        excess = tau[i - 1] - carried
        if abs(excess) <= friction:
            delta[i] = delta[i - 1]
            continue
        moving = tau[i - 1] - math.copysign(friction, excess)
        target = ct * moving / (1 + beta * abs(moving))
        delta[i] = target + (delta[i - 1] - target) * decay
    return delta


CUFFS = {
    "elastic": {"cuff.elastic": {"compliance_deg_per_Nm": 1.0}},
    "stiffening": {
        "cuff.elastic": {"compliance_deg_per_Nm": 1.5},
        "cuff.stiffening": {"stiffening_per_Nm": 1.0},
    },
    "friction": {
        "cuff.elastic": {"compliance_deg_per_Nm": 1.0},
        "cuff.coulomb": {"friction_Nm": 0.15},
    },
    "drift": {
        "cuff.elastic": {"compliance_deg_per_Nm": 1.0},
        "cuff.drifting": {"drift_per_s": -0.02},
    },
}


@pytest.mark.parametrize("case", sorted(CUFFS))
def test_the_brace_lags_the_knee_through_its_cuffs(case):
    violations = CUFFS[case]
    trial = sim(violations, cuff_time_constant_s=0.02)
    state, time = trial.state, trial.brace[:, 0]
    params = {
        "c": violations["cuff.elastic"]["compliance_deg_per_Nm"],
        "tc": trial.truth["drawn"]["cuff.elastic"]["time_constant_s"],
        "beta": violations.get("cuff.stiffening", {"stiffening_per_Nm": 0.0})["stiffening_per_Nm"],
        "friction": violations.get("cuff.coulomb", {"friction_Nm": 0.0})["friction_Nm"],
        "drift": violations.get("cuff.drifting", {"drift_per_s": 0.0})["drift_per_s"],
    }
    assert params["tc"] == 0.02
    delta = state.brace_deg - state.knee_deg
    np.testing.assert_allclose(delta, cuff_recursion(state, time, **params), atol=1e-9)
    # under the spring's flexion torque the brace sits further flexed than the knee (it lags it
    # while the knee extends)
    loaded = state.torque_Nm > 1.0
    assert np.all(delta[1:][loaded[:-1]] > 0) and delta.max() > 0.5
    if case == "friction":  # the straps stick: δ holds over runs of samples
        assert np.mean(np.diff(delta) == 0) > 0.2


def test_the_tissue_time_constant_is_drawn_in_its_range_when_not_given():
    violations = {"cuff.elastic": {"compliance_deg_per_Nm": 1.0}}
    drawn = {
        sim(violations, seed=s).truth["drawn"]["cuff.elastic"]["time_constant_s"] for s in (1, 2, 3)
    }
    assert len(drawn) == 3 and all(0.005 <= tc <= 0.05 for tc in drawn)


def test_cuff_play_is_a_dead_band_the_knee_drags_the_brace_through():
    # The brace stays where it is until the knee takes it along at ±p/2, whatever the torque.
    play = 2.0
    state = sim({"cuff.play": {"play_deg": play}}).state
    offset = state.brace_deg - state.knee_deg
    held = np.clip(state.brace_deg[:-1] - state.knee_deg[1:], -play / 2, play / 2)
    np.testing.assert_allclose(offset[1:], held, atol=1e-12)
    moves = np.abs(np.diff(state.brace_deg)) > 1e-12
    np.testing.assert_allclose(np.abs(offset[1:][moves]), play / 2, atol=1e-12)
    inside = np.abs(offset[1:]) < play / 2 - 0.1
    assert inside.any() and (offset > play / 2 - 1e-12).any() and (offset < 1e-12 - play / 2).any()
    assert (inside & (state.torque_Nm[:-1] > 0.5)).any()  # the spring's torque does not press it


@pytest.mark.parametrize("a", [0.08, -0.05])
def test_the_hinge_off_the_knee_axis_turns_the_brace_by_a_sin_theta(a):
    state = sim({"hinge.offset": {"offset_ratio": a}}).state
    expected = state.knee_deg + np.degrees(a * np.sin(np.radians(state.knee_deg)))
    np.testing.assert_allclose(state.brace_deg, expected, atol=1e-12)


def test_the_encoder_reads_gain_drift_and_a_count_drop():
    g, drift, drop, at = 1.03, 0.05, 4.6, 2.5
    violations = {
        "encoder.gain": {"gain": g},
        "encoder.drift": {"drift_deg_per_s": drift},
        "encoder.step": {"drop_deg": drop},
    }
    trial = sim(violations, drop_time_s=at)
    time, reading = trial.brace[:, 0], trial.brace[:, 1]
    expected = quantized(g * trial.state.brace_deg - drift * time - drop * (time >= at))
    np.testing.assert_allclose(reading, expected, atol=1e-12)
    assert trial.truth["drawn"]["encoder.step"] == {"time_s": at}
    drawn = [sim({"encoder.step": {"drop_deg": drop}}, seed=s) for s in (1, 2)]
    times = [t.truth["drawn"]["encoder.step"]["time_s"] for t in drawn]
    assert times[0] != times[1] and all(1.2 <= x <= 4.8 for x in times)  # 20–80 % of 6 s
    jump = np.diff(drawn[0].brace[:, 1] - quantized(drawn[0].state.brace_deg))
    first = math.ceil(times[0] * 1000)  # the first sample at or after the drop's instant
    assert np.flatnonzero(np.abs(jump) > 1.0).tolist() == [first - 1]


def test_the_motor_encoder_gain_turns_the_pulley_reading_over_g():
    g = 1.04
    trial, base = sim({"motor_encoder.gain": {"gain": g}}), sim()
    np.testing.assert_allclose(trial.state.motor_deg, trial.brace[:, 4] / g, atol=1e-12)
    np.testing.assert_array_equal(trial.brace[:, 4], base.brace[:, 4])  # the reading is held


def cable_law(state, flexion=FLEXION, extension=EXTENSION, ratio=A):
    """The calibrated torque at the true stretch, the brace's rate (°/s) and t from sample 1 on."""
    rate = np.diff(state.brace_deg) * 1000.0
    stretch = state.motor_deg[1:] - ratio * state.brace_deg[1:]
    return calibration_torque(stretch, rate, flexion, extension), rate


CABLE = {
    "friction": {"cable.coulomb": {"friction_fraction": 0.1}},
    "damping": {"cable.viscous": {"c_Nms_per_rad": 0.03}},
    "creep": {"cable.drifting": {"drift_per_s": -0.01}},
    "slope": {"cable_calibration.value": {"scale": 1.1}},
    "zero": {"cable_calibration.offset": {"offset_deg": -1.2}},
    "ratio": {"pulley_ratio.value": {"scale": 0.97}},
}


@pytest.mark.parametrize("case", sorted(CABLE))
def test_the_cable_delivers_its_law(case):
    trial = sim(CABLE[case])
    state, time = trial.state, trial.brace[1:, 0]
    flexion, extension, ratio = list(FLEXION), list(EXTENSION), A
    if case == "slope":
        flexion[:2] = [1.1 * x for x in FLEXION[:2]]
        extension[:2] = [1.1 * x for x in EXTENSION[:2]]
    if case == "zero":
        flexion[2], extension[2] = FLEXION[2] - 1.2, EXTENSION[2] - 1.2
    if case == "ratio":
        ratio = 0.97 * A
    tau, rate = cable_law(state, flexion, extension, ratio)
    pulls = tau > 0
    if case == "friction":  # × (1 + f) while the brace extends, × (1 − f) while it flexes
        tau = tau * (1 - 0.1 * np.sign(rate))
    if case == "damping":  # − c·ω (rad/s) while the cable pulls, never below zero
        tau = np.where(pulls, np.maximum(tau - 0.03 * np.radians(rate), 0.0), 0.0)
    if case == "creep":
        tau = tau * (1 - 0.01 * time)
    np.testing.assert_allclose(state.torque_Nm[1:], tau, atol=1e-9)
    assert tau.max() > 1.5


def test_cable_slack_is_a_backlash_on_the_stretch():
    # The cable pulls at the stretch less A·p/2 while the stretch grows; after a reversal the
    # slack is taken up again before it follows: y within ±A·p/2 of the stretch, held between.
    play = 2.0
    state = sim({"cable.play": {"play_deg": play}}).state
    stretch = state.motor_deg - A * state.brace_deg
    half = A * play / 2
    taken = np.empty(stretch.size)
    taken[0] = stretch[0] - half
    for i in range(1, stretch.size):
        taken[i] = min(max(taken[i - 1], stretch[i] - half), stretch[i] + half)
    rate = np.diff(state.brace_deg) * 1000.0
    expected = calibration_torque(taken[1:], rate)
    settled = np.arange(1, stretch.size) > 2000  # the warm-up's slack is met again by then
    np.testing.assert_allclose(state.torque_Nm[1:][settled], expected[settled], atol=1e-9)
    assert (np.abs(taken - stretch) < half - 1e-6).any()  # held inside the band at times


SPRINGS = {
    "rate": ({"spring.value": {"scale": 1.15}}, {"kappa": 3.5 * 1.15}),
    "equilibrium": ({"spring.offset": {"offset_deg": -3.0}}, {"eq_deg": 37.0}),
    "stiffening": ({"spring.stiffening": {"stiffening_per_rad": 0.8}}, {"a": 0.8}),
}


@pytest.mark.parametrize("case", sorted(SPRINGS))
def test_the_controller_asks_for_its_real_spring(case):
    violations, law = SPRINGS[case]
    trial = sim(violations)
    law = {"kappa": 3.5, **law}
    expected = np.where(trial.state.engaged, spring_torque(trial.brace[:, 1], **law), 0.0)
    np.testing.assert_allclose(trial.brace[:, 3], expected, atol=1e-12)


def test_torque_sensor_offset_gain_drift_and_zero_between_trials():
    violations = {
        "torque_sensor.offset": {"torque_offset_Nm": 0.2},
        "torque_sensor.gain": {"gain": 0.95},
        "torque_sensor.drift": {"drift_Nm_per_s": -0.01},
        "torque_zero_between.between": {"spread_Nm": 0.1},
    }
    trial, base = sim(violations, between_z={"torque_zero_between.between": [-1.5]}), sim()
    time = base.brace[:, 0]
    expected = 0.95 * base.brace[:, 2] + 0.2 - 0.01 * time - 0.15
    np.testing.assert_allclose(trial.brace[:, 2], expected, atol=1e-12)
    assert trial.truth["drawn"]["torque_zero_between.between"] == {
        "z": -1.5,
        "offset_Nm": pytest.approx(-0.15),
    }
    np.testing.assert_array_equal(
        np.delete(trial.brace, 2, axis=1), np.delete(base.brace, 2, axis=1)
    )


@pytest.mark.parametrize("delay", [0.012, 0.0125])
def test_torque_sensor_lag_reads_the_filtered_torque_d_late(delay):
    torque = sim()[3][:, 2]
    lagged = sim({"torque_sensor.delay": {"delay_s": delay}})[3][:, 2]
    k = int(delay * 1000)
    w = delay * 1000 - k
    np.testing.assert_allclose(
        lagged[13:], (1 - w) * torque[13 - k : -k] + w * torque[12 - k : -k - 1], atol=1e-12
    )


@pytest.mark.parametrize("q", [0.08, -0.05])
def test_the_torque_channel_filters_the_sensor_s_nonlinear_reading(q):
    trial = sim({"torque_linearity.nonlinearity": {"quadratic_per_Nm": q}})
    tau = trial.state.torque_Nm
    filtered = signal.lfilter(*signal.butter(2, 20.0, fs=1000.0), tau * (1 + q * np.abs(tau)))
    np.testing.assert_allclose(trial.brace[500:, 2], filtered[500:], atol=1e-9)


def test_motion_capture_zero_gain_clock_and_rate():
    zero, g, d, eps, between = 2.0, 0.97, 0.02, 0.001, 0.5
    violations = {
        "mocap.offset": {"zero_deg": zero},
        "mocap.gain": {"gain": g},
        "clocks.delay": {"clock_offset_s": d},
        "clocks.drift": {"rate_error": eps},
        "mocap_zero_between.between": {"spread_deg": between},
    }
    trial = sim(violations, between_z={"mocap_zero_between.between": [2.0]})
    knee = trial.state.knee_deg
    stamps = np.arange(trial.mocap.shape[0]) / 100.0
    shown = stamps * (1 - eps) - d
    inside = shown >= 0
    expected = zero + g * np.interp(shown * 1000.0, np.arange(knee.size), knee) + between * 2.0
    np.testing.assert_allclose(trial.mocap[inside, 1], expected[inside], atol=2e-3)
    np.testing.assert_array_equal(trial.brace, sim().brace)


@pytest.mark.parametrize("amplitude", [1.5, -1.5])
def test_the_soft_tissue_artefact_is_locked_to_the_gait(amplitude):
    trial = sim({"mocap.harmonic": {"amplitude_deg": amplitude}}, duration=8.0)
    base = sim(duration=8.0)
    drawn = trial.truth["drawn"]["mocap.harmonic"]
    k, psi = drawn["harmonic"], drawn["phase_rad"]
    assert k in (1, 2, 3) and 0 <= psi < 2 * np.pi
    heel = np.array(trial.truth["heel_strikes_s"])
    stamps = np.arange(trial.mocap.shape[0]) / 100.0
    inside = (stamps >= heel[0]) & (stamps < heel[-1])
    i = np.searchsorted(heel, stamps[inside], side="right") - 1
    phase = (stamps[inside] - heel[i]) / (heel[i + 1] - heel[i])
    artefact = trial.mocap[inside, 1] - base.mocap[inside, 1]
    np.testing.assert_allclose(artefact, amplitude * np.sin(2 * np.pi * k * phase + psi), atol=1e-9)
    given = sim({"mocap.harmonic": {"amplitude_deg": amplitude}}, duration=8.0, artefact=(3, 1.0))
    assert given.truth["drawn"]["mocap.harmonic"] == {"harmonic": 3, "phase_rad": 1.0}


def intervals(engaged: np.ndarray) -> list[tuple[int, int]]:
    return [(w.start, w.stop) for w in engagements(engaged)]


def test_late_release_and_late_engagement_move_the_clutch_s_edges():
    base = intervals(sim().state.engaged)
    late_release = intervals(sim({"clutch_release.delay": {"release_delay_s": 0.05}}).state.engaged)
    assert late_release == [(on, off + 50) for on, off in base]
    late_engage = intervals(sim({"clutch_engage.delay": {"delay_s": 0.15}}).state.engaged)
    assert late_engage == [(on + 150, off) for on, off in base if on + 150 < off]
    assert len(late_engage) >= len(base) - 1


@pytest.mark.parametrize("lead", [0.03, -0.02])
def test_a_velocity_ahead_of_the_chain_s_moves_both_of_the_clutch_s_edges(lead):
    # the events are timed on the estimate l ahead (the loop run again on its last run's
    # estimate; l < 0: behind): every engagement and release moves l sooner, to the sample
    base = intervals(sim().state.engaged)
    moved = intervals(sim({"velocity_estimate.delay": {"lead_s": lead}}).state.engaged)
    shift = -round(lead * 1000)
    assert moved == [(on + shift, off + shift) for on, off in base]


def test_a_share_of_the_loading_peaks_engages_the_clutch_too():
    # Table 6.1 arms at 40° per step; the relaxation also engages at a share w of the peak
    # flexions below it (the loading response's), once the knee has passed 40°
    base = intervals(sim(duration=8.0).state.engaged)
    every = intervals(sim({"clutch_engage.event": {"loading_share": 1.0}}, duration=8.0)
                      .state.engaged)  # fmt: skip
    angle = sim(duration=8.0).brace[:, 1]
    extra = [(on, off) for on, off in every if (on, off) not in base]
    assert set(base) <= set(every) and len(extra) >= len(base) - 1
    # each extra engagement begins at a peak flexion below 40° (the knee passed 40° in the
    # loop's warm-up before the recording)
    rate = sim(duration=8.0).state.rate_deg_per_s
    assert all(angle[on] < 40.0 and rate[on - 1] > 0.0 >= rate[on] for on, _ in extra)

    # at a share of 0.5 some of the loading peaks engage, each as at a share of 1
    def engaged(share):
        violations = {"clutch_engage.event": {"loading_share": share}} if share else None
        return intervals(sim(violations, duration=8.0, seed=3).state.engaged)

    base, every, half = engaged(0.0), engaged(1.0), engaged(0.5)
    some, extra = set(half) - set(base), set(every) - set(base)
    assert set(base) <= set(half) and some < extra and 0 < len(some)


def test_between_trial_constants_are_drawn_per_trial_and_reported():
    violations = {
        "cuff.elastic": {"compliance_deg_per_Nm": 1.0},
        "straps_between.between": {"spread": 0.4},
        "mocap_zero_between.between": {"spread_deg": 2.0},
        "torque_zero_between.between": {"spread_Nm": 0.1},
        "cable_tension_between.between": {"spread_deg": 0.5},
    }
    kwargs = {
        "speeds_m_per_s": [0.8],
        "stiffnesses_Nm_per_rad": [1.0, 2.0, 3.5],
        "duration_s": 4.0,
        "seed": 9,
        **QUIET,
    }
    trials = labsim.simulate_study(violations=violations, **kwargs)
    plain = labsim.simulate_study(
        violations={"cuff.elastic": {"compliance_deg_per_Nm": 1.0}}, **kwargs
    )
    for key in labsim.BETWEEN:
        z = [trial.truth["drawn"][key]["z"] for trial in trials]
        assert len(set(z)) == 3 and max(map(abs, z)) <= 3.0, key
    for trial, base in zip(trials, plain, strict=True):
        drawn = trial.truth["drawn"]
        z = drawn["straps_between.between"]["z"]
        compliance = drawn["straps_between.between"]["compliance_deg_per_Nm"]
        assert compliance == pytest.approx(max(0.0, 1 + 0.4 * z))
        tc = drawn["cuff.elastic"]["time_constant_s"]
        delta = trial.state.brace_deg - trial.state.knee_deg
        np.testing.assert_allclose(
            delta, cuff_recursion(trial.state, trial.brace[:, 0], compliance, tc), atol=1e-9
        )
        zero = drawn["mocap_zero_between.between"]
        assert zero["zero_deg"] == pytest.approx(2.0 * zero["z"])
        np.testing.assert_allclose(
            trial.mocap[:, 1] - base.mocap[:, 1], zero["zero_deg"], atol=1e-12
        )
        tension = drawn["cable_tension_between.between"]
        shift = [FLEXION[2] + tension["offset_deg"], EXTENSION[2] + tension["offset_deg"]]
        tau, _ = cable_law(trial.state, (*FLEXION[:2], shift[0]), (*EXTENSION[:2], shift[1]))
        np.testing.assert_allclose(trial.state.torque_Nm[1:], tau, atol=1e-9)
        assert drawn["torque_zero_between.between"]["offset_Nm"] == pytest.approx(
            0.1 * drawn["torque_zero_between.between"]["z"]
        )
    again = labsim.simulate_study(violations=violations, **kwargs)
    assert [t.truth for t in again] == [t.truth for t in trials]
    other = labsim.simulate_study(violations=violations, **{**kwargs, "seed": 10})
    assert [t.truth["drawn"] for t in other] != [t.truth["drawn"] for t in trials]


# --- several at once, determinism, refusals ------------------------------------------------------


def test_every_violation_at_once_gives_a_plausible_recording():
    rng = np.random.default_rng(4)
    violations = {}
    for key, row in TABLE.items():
        size = rng.uniform(*row["sizes"])
        sign = rng.choice([-1.0, 1.0]) if row["either_sign"] else 1.0
        violations[key] = {row["parameter"]: float(row["neutral"] + sign * size)}
    trials = labsim.simulate_study(
        speeds_m_per_s=[0.8, 1.2],
        stiffnesses_Nm_per_rad=[3.5],
        duration_s=6.0,
        violations=violations,
        seed=4,
    )
    for trial in trials:
        brace = columns(trial)
        assert all(np.isfinite(v).all() for v in brace.values())
        assert brace["brace_angle_deg"].min() > -30 and brace["brace_angle_deg"].max() < 150
        assert np.abs(brace["brace_torque_Nm"]).max() < 30
        assert np.abs(brace["motor_angle_deg"]).max() < 360
        assert (brace["desired_torque_Nm"] > 0.5).any()


def test_same_seed_gives_same_bytes(tmp_path):
    kwargs = {
        "speeds_m_per_s": [0.8],
        "stiffnesses_Nm_per_rad": [2.0, 3.5],
        "duration_s": 2.0,
        "violations": {"mocap.harmonic": {"amplitude_deg": 1.0}, "encoder.step": {"drop_deg": 3.0}},
    }
    folders = {name: tmp_path / name for name in ("a", "b", "c")}
    for name, folder in folders.items():
        labsim.write_study(folder, seed=8 if name == "c" else 7, **kwargs)
    files = sorted(p.relative_to(folders["a"]) for p in folders["a"].rglob("*") if p.is_file())
    assert len(files) == 1 + 2 * 3
    for name in files:
        assert filecmp.cmp(folders["a"] / name, folders["b"] / name, shallow=False)
    assert not filecmp.cmp(
        folders["a"] / "v08_k35_brace.csv", folders["c"] / "v08_k35_brace.csv", shallow=False
    )


@pytest.mark.parametrize(
    "violations",
    [
        {"cuff.stiffening": {"stiffening_per_Nm": 0.5}},  # needs cuff.elastic
        {"straps_between.between": {"spread": 0.2}},  # needs cuff.elastic
        {"cable.coulomb": {"friction": 0.1}},  # the wrong parameter
        {"cable.coulomb": {"friction_fraction": 0.1, "extra": 1.0}},
        {"cable.backlash": {"play_deg": 1.0}},  # not in the table
        {"cuff_compliance": {"compliance_deg_per_Nm": 1.0}},  # a registry name, not a key
        {"cuff.elastic": {"compliance_deg_per_Nm": -0.5}},
        {"cable.play": {"play_deg": -1.0}},
        {"cable.coulomb": {"friction_fraction": 1.2}},
        {"encoder.gain": {"gain": 0.0}},
        {"mocap.gain": {"gain": float("nan")}},
        {"torque_sensor.delay": {"delay_s": -0.01}},
        {"clutch_release.delay": {"release_delay_s": 0.6}},
        {"clocks.drift": {"rate_error": 0.02}},
        {"cable.drifting": {"drift_per_s": -0.2}},  # the cable's torque factor ≤ 0 within 6 s
        {"hinge.offset": {"offset_ratio": True}},
        {"mocap_zero_between.between": {"spread_deg": -1.0}},
    ],
)
def test_bad_violations_are_refused(violations):
    with pytest.raises(ValueError):
        sim(violations)


@pytest.mark.parametrize(
    "extra",
    [
        {"drop_time_s": 7.0},  # beyond the 6 s trial
        {"cuff_time_constant_s": 0.0},
        {"artefact": (4, 0.0)},
        {"between_z": {"mocap_zero_between.between": [0.5, 1.0]}},  # one trial
    ],
)
def test_bad_extra_arguments_are_refused(extra):
    violations = {
        "encoder.step": {"drop_deg": 2.0},
        "cuff.elastic": {"compliance_deg_per_Nm": 1.0},
        "mocap.harmonic": {"amplitude_deg": 1.0},
        "mocap_zero_between.between": {"spread_deg": 1.0},
    }
    with pytest.raises(ValueError):
        sim(violations, **extra)
