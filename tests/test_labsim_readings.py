"""A lab's reading of the thesis in the independent emulator generator, from first principles:
the definitions of each reading (rules, velocity estimate, motor, cable, channels) and physics."""

import dataclasses
import functools
import hashlib
import itertools
import json
import math
from pathlib import Path

import numpy as np
import pytest
from scipy import signal

from exobench.emulator.validation import labsim
from exobench.emulator.validation.labsim import NOMINAL, Reading, draw_reading
from test_emulator_labsim import calibration_torque

# The rig as docs/rig.md §3 and config/config.yaml's emulator block give it.
A = 0.044 / 0.048
FLEXION, EXTENSION = (-0.3, 7.0, 1.0), (-0.3, 6.5, 0.0)
EQ_DEG, KAPPA = 40.0, 3.5
QUIET = {"torque_noise_Nm": 0.0, "mocap_noise_deg": 0.0}
SETTLED = 500  # samples after which a filter rebuilt from rest matches the controller's


@functools.cache
def sim(reading=None, *, stiffness=KAPPA, duration=6.0, quiet=True, seed=5):
    """One simulated trial at 0.8 m/s (cached)."""
    return labsim.simulate_study(
        speeds_m_per_s=[0.8],
        stiffnesses_Nm_per_rad=[stiffness],
        duration_s=duration,
        violations={},
        seed=seed,
        reading=reading,
        **(QUIET if quiet else {}),
    )[0]


def velocity(angle: np.ndarray, cutoff_hz: float = 6.0, order: int = 2) -> np.ndarray:
    """ω: the causal Butterworth of the encoder's backward difference × 1 kHz (from rest)."""
    raw = np.diff(angle, prepend=angle[0]) * 1000.0
    return signal.lfilter(*signal.butter(order, cutoff_hz, fs=1000.0), raw)


def rises_through(rate: np.ndarray, level: float) -> np.ndarray:
    """Samples i where ω_i−1 < level ≤ ω_i."""
    return np.flatnonzero((rate[:-1] < level) & (rate[1:] >= level)) + 1


def falls_through(rate: np.ndarray, level: float) -> np.ndarray:
    """Samples i where ω_i−1 > level ≥ ω_i."""
    return np.flatnonzero((rate[:-1] > level) & (rate[1:] <= level)) + 1


def edges(engaged: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The first sample of each engagement and the first sample after it (inside the record)."""
    step = np.diff(engaged.astype(int))
    return np.flatnonzero(step == 1) + 1, np.flatnonzero(step == -1) + 1


def engaged_from_desired(desired: np.ndarray) -> np.ndarray:
    """Where the controller asks for torque (the spring pulls below θ_eq while engaged)."""
    return desired > 0.0


def set_point(brace: np.ndarray, flexion=FLEXION, extension=EXTENSION) -> np.ndarray:
    """The motor's set point A·θ_e + b(τ_des), b blended by the 6 Hz velocity (eq. 5.8)."""
    angle, desired = brace[:, 1], brace[:, 3]
    w = np.clip((velocity(angle) + 25.0) / 50.0, 0.0, 1.0)
    b_flx, b_ext = ((q[0] * desired + q[1]) * desired + q[2] for q in (flexion, extension))
    return A * angle + w * b_flx + (1 - w) * b_ext


# --- NOMINAL is today's generator ----------------------------------------------------------------

NOMINAL_STUDY = {
    "speeds_m_per_s": [0.8, 1.2],
    "stiffnesses_Nm_per_rad": [3.5],
    "duration_s": 3.0,
    "violations": {
        "encoder.step": {"drop_deg": 3.0},
        "mocap.harmonic": {"amplitude_deg": 1.0},
        "cable.coulomb": {"friction_fraction": 0.08},
        "mocap_zero_between.between": {"spread_deg": 1.0},
    },
    "seed": 11,
}
# SHA-256 of each file the generator wrote for NOMINAL_STUDY before it knew of readings.
TODAY = {
    "manifest.csv": "9eaef3c4ce8052839a7cc2dd069ce0857543de701b43c32d7d1a280cb80cd48e",
    "truth/v08_k35.json": "cdee03c4b6202d2bc05ad4a365fdff083235028bb73d2aa7b03f5b1ce4466e6e",
    "truth/v12_k35.json": "1f123b0bb3bddc468a89692835ed346553ecee0dc77108596d663ed1e7747637",
    "v08_k35_brace.csv": "a92f6e876adf610d026a6f143e7f67a7024f4f2ed089996f1170504206aa7b69",
    "v08_k35_mocap.csv": "44521153f7a5575589d7c171621f5604c51d1ecf8107cc2c0e53450dce653a10",
    "v12_k35_brace.csv": "d45a0926897247baa6eb61cb645e5be8927b1f4ee28272b213505336d4ecb921",
    "v12_k35_mocap.csv": "b9c2f360b486c797ccd0a4cd15cc57af6b8bb4a804163d494b8906e4c39488f9",
}


def digests(folder: Path) -> dict[str, str]:
    """SHA-256 of every file under folder, by its path there."""
    return {
        p.relative_to(folder).as_posix(): hashlib.sha256(p.read_bytes()).hexdigest()
        for p in sorted(folder.rglob("*"))
        if p.is_file()
    }


def test_nominal_writes_today_s_files_byte_for_byte(tmp_path):
    labsim.write_study(tmp_path / "none", **NOMINAL_STUDY)
    labsim.write_study(tmp_path / "nominal", reading=NOMINAL, **NOMINAL_STUDY)
    assert digests(tmp_path / "none") == TODAY
    given = digests(tmp_path / "nominal")
    assert {k: v for k, v in given.items() if "truth" not in k} == {
        k: v for k, v in TODAY.items() if "truth" not in k
    }
    # a given reading is in the truth besides what it held before, nothing else changes
    for name in ("v08_k35", "v12_k35"):
        before = json.loads((tmp_path / "none" / "truth" / f"{name}.json").read_text())
        after = json.loads((tmp_path / "nominal" / "truth" / f"{name}.json").read_text())
        assert after.pop("reading") == json.loads(json.dumps(NOMINAL.as_dict()))
        assert after.pop("reading_drawn") == {}
        assert after == before
    assert Reading() == NOMINAL


# --- the controller's rules ---------------------------------------------------------------------


def rebuilt_heel_strikes(angle: np.ndarray, rate: np.ndarray) -> np.ndarray:
    """Table 5.1 (knee): after a peak flexion beyond 40° (ω_i−1 ≥ 0 > ω_i) the peak extension
    below 20° (ω_i−1 ≤ 0 < ω_i), then the heel strike at the first ω_i < ω_i−1."""
    flexions = np.flatnonzero((rate[:-1] >= 0) & (rate[1:] < 0) & (angle[1:] > 40.0)) + 1
    extensions = np.flatnonzero((rate[:-1] <= 0) & (rate[1:] > 0) & (angle[1:] < 20.0)) + 1
    falls = np.flatnonzero(rate[1:] < rate[:-1]) + 1
    strikes = []
    for peak in flexions:
        after = extensions[extensions > peak]
        if after.size and (falls > after[0]).any():
            strikes.append(falls[falls > after[0]][0])
    return np.unique(strikes)


@pytest.mark.parametrize("delay_s", [0.0, 0.02])
def test_release_at_heel_strike(delay_s):
    # The clutch releases d after Table 5.1's heel strike: the desired torque (the spring's, > 0
    # below θ_eq while engaged) falls to 0 there, not at the peak extension before it.
    trial = sim(Reading(release_rule="heel_strike", release_delay_s=delay_s))
    angle, desired = trial.brace[:, 1], trial.brace[:, 3]
    rate = velocity(angle)
    strikes = rebuilt_heel_strikes(angle, rate)
    strikes = strikes[strikes > SETTLED]
    assert strikes.size >= 4
    truth = np.round(np.array(trial.truth["controller"]["heel_strikes_s"]) * 1000).astype(int)
    assert set(strikes) <= set(truth)
    _, off = edges(engaged_from_desired(desired))
    delay = round(delay_s * 1000)
    np.testing.assert_array_equal(off[off > SETTLED + delay], strikes + delay)
    # Table 5.1's peak extension before each (ω's last rise through 0): the spring still pulls
    rises = rises_through(rate, 0.0)
    peaks = np.array([rises[rises < strike][-1] for strike in strikes])
    assert np.all(angle[peaks] < 20.0) and np.all(strikes > peaks)
    assert np.all(desired[peaks] > 0.5) and np.all(desired[peaks + 1] > 0.5)


def test_release_30_ms_after_peak_extension():
    # Table 6.1's release (ω_i−1 < 0 ≤ ω_i) taking effect 30 ms later: the spring keeps pulling
    # for 30 samples past the velocity's sign change, then the desired torque is 0.
    trial = sim(Reading(release_delay_s=0.03))
    angle, desired = trial.brace[:, 1], trial.brace[:, 3]
    peaks = rises_through(velocity(angle), 0.0)
    peaks = peaks[(peaks > SETTLED) & (desired[peaks] > 0)]  # the engaged ones
    assert peaks.size >= 4
    _, off = edges(engaged_from_desired(desired))
    np.testing.assert_array_equal(off[off > SETTLED], peaks + 30)
    for peak in peaks:
        assert np.all(desired[peak : peak + 30] > 0.5) and desired[peak + 30] == 0.0
    base = sim()
    _, base_off = edges(engaged_from_desired(base.brace[:, 3]))
    np.testing.assert_array_equal(base_off[base_off > SETTLED], peaks)


def test_release_where_the_extension_velocity_falls_below_its_threshold():
    # velocity_threshold: release once ω rises above −v_th, before the peak extension.
    v_th = 30.0
    trial = sim(Reading(release_rule="velocity_threshold", release_threshold_deg_per_s=v_th))
    angle, desired = trial.brace[:, 1], trial.brace[:, 3]
    rate = velocity(angle)
    crossings = rises_through(rate, -v_th)
    crossings = crossings[(crossings > SETTLED) & (angle[crossings] < 20.0)]
    _, off = edges(engaged_from_desired(desired))
    off = off[off > SETTLED]
    assert off.size >= 4
    assert np.isin(off, crossings).all()  # each release where ω rose through −v_th
    peaks = rises_through(rate, 0.0)
    assert all(0 < peaks[peaks > o][0] - o < 60 for o in off)  # ahead of the peak extension


def test_latched_engagement_engages_in_stance_too():
    # latched: θ_e > 40° once met stays met, so the clutch also engages at the loading peak of
    # stance (ω from + to − at a knee well below 40°); Table 6.1 (θ_e > 40°) never does.
    trial, base = sim(Reading(engage_rule="latched")), sim()
    angle, desired = trial.brace[:, 1], trial.brace[:, 3]
    heel = np.array(trial.truth["heel_strikes_s"])
    stances = [
        slice(round(1000 * (h + 0.1 * (n - h))), round(1000 * (h + 0.55 * (n - h))))
        for h, n in itertools.pairwise(heel)
    ]
    assert len(stances) >= 3
    for stance in stances:
        assert desired[stance].max() > 0.5  # the spring pulls in stance
        assert np.all(base.brace[stance, 3] == 0.0)
    on, _ = edges(engaged_from_desired(desired))
    onsets = falls_through(velocity(angle), 0.0)
    in_stance = [o for o in on if o > SETTLED and angle[o] < 30.0]
    assert len(in_stance) >= 3
    for o in in_stance:  # the engagement at the loading peak: ω's fall through 0 where θ < 40°
        assert o in onsets and angle[o] < EQ_DEG


def test_velocity_estimates_follow_their_definitions():
    # The controller's ω from the encoder: a first-order Butterworth of the backward difference,
    # or the unfiltered centred difference (θ_e,i − θ_e,i−10)/10 ms about sample i − 5.
    first = sim(Reading(velocity_order=1, velocity_cutoff_Hz=8.0))
    rate = velocity(first.brace[:, 1], 8.0, order=1)
    np.testing.assert_allclose(first.state.rate_deg_per_s[SETTLED:], rate[SETTLED:], atol=1e-6)
    centred = sim(Reading(velocity_estimate="centred_difference"))
    angle = centred.brace[:, 1]
    np.testing.assert_allclose(
        centred.state.rate_deg_per_s[10:], (angle[10:] - angle[:-10]) / 0.01, atol=1e-9
    )
    assert Reading(velocity_estimate="centred_difference").lab_config()["controller"] == {
        "torque_filter_Hz": 20.0,
        "velocity_cutoff_Hz": None,
    }


# --- motor and cable ------------------------------------------------------------------------


@pytest.mark.parametrize("tc", [0.002, 0.02])
def test_the_motor_lags_its_set_point_by_its_time_constant(tc):
    # The motor's reading m follows the set point s = A·θ_e + b(τ_des) one sample late as a first
    # order lag: m_i = m_i−1 + (1 − e^(−h/T))·(s_i−1 − m_i−1); cross-correlated, m is most like s
    # about T before. The delivered torque lags the desired one: at each release (τ_des steps to
    # 0 with the brace near its peak extension) it falls to 1/e within about T.
    trial = sim(Reading(motor_time_constant_s=tc))
    motor, setpoint = trial.brace[:, 4], set_point(trial.brace)
    alpha = 1.0 - math.exp(-1e-3 / tc)
    np.testing.assert_allclose(
        motor[SETTLED + 1 :],
        motor[SETTLED:-1] + alpha * (setpoint[SETTLED:-1] - motor[SETTLED:-1]),
        atol=1e-6,
    )
    m, s = motor[SETTLED:], setpoint[SETTLED:]
    lags = np.arange(60)
    xcorr = [np.corrcoef(m[k:], s[: s.size - k])[0, 1] for k in lags]
    assert abs(lags[np.argmax(xcorr)] - tc * 1000) <= 1.5
    torque, desired = trial.state.torque_Nm, trial.brace[:, 3]
    _, off = edges(engaged_from_desired(desired))
    falls = [np.argmax(torque[o:] < torque[o - 1] / math.e) for o in off]
    assert len(falls) >= 4
    assert all(0.6 * tc * 1000 <= k <= tc * 1000 + 1.5 for k in falls), falls


def test_friction_bias_lowers_the_delivered_torque_while_the_cable_pulls():
    # τ = max(0, τ_cable − τ_f) while the cable pulls: rigid cuffs keep the brace on the knee, so
    # the motor moves the same and the delivered torque is lower by min(τ_cable, τ_f).
    bias = 0.1
    trial, base = sim(Reading(friction_bias_Nm=bias)), sim()
    np.testing.assert_array_equal(trial.state.motor_deg, base.state.motor_deg)
    tau = base.state.torque_Nm
    np.testing.assert_allclose(trial.state.torque_Nm, np.maximum(tau - bias, 0.0), atol=1e-12)
    loaded = tau > 0.5
    assert loaded.sum() > 500
    lowered = base.brace[:, 2] - trial.brace[:, 2]  # the recorded (20 Hz) channel
    steady = np.convolve(loaded, np.ones(100), mode="same") == 100
    assert np.median(lowered[steady]) == pytest.approx(bias, abs=0.005)


def lab_calibration() -> Reading:
    """NOMINAL but for the first drawn reading whose cable law is not the nominal one."""
    rng = np.random.default_rng(0)
    while (drawn := draw_reading(rng)).flexion == FLEXION:
        pass
    return dataclasses.replace(NOMINAL, flexion=drawn.flexion, extension=drawn.extension)


def test_the_lab_s_calibration_is_the_real_cable_law():
    reading = lab_calibration()
    flexion, extension = reading.flexion, reading.extension
    assert flexion != FLEXION and extension != EXTENSION
    assert reading.lab_config()["transmission"] == {
        "flexion": dict(zip("BCD", flexion, strict=True)),
        "extension": dict(zip("BCD", extension, strict=True)),
    }
    assert reading.lab_config()["transmission_calibrated"] == "session"
    trial = sim(reading)
    state = trial.state
    # the rig: b⁻¹ of the stretch θ_m − A·θ_b on the lab's calibration, not on the nominal one
    rate = np.diff(state.brace_deg) * 1000.0
    stretch = state.motor_deg[1:] - A * state.brace_deg[1:]
    np.testing.assert_allclose(
        state.torque_Nm[1:], calibration_torque(stretch, rate, flexion, extension), atol=1e-9
    )
    assert np.abs(state.torque_Nm[1:] - calibration_torque(stretch, rate)).max() > 0.1
    # the recording: the motor follows A·θ_e + b(τ_des) on the lab's calibration, and the
    # measured torque is the 20 Hz filter of its inverse at the recorded angles
    motor, setpoint = trial.brace[:, 4], set_point(trial.brace, flexion, extension)
    alpha = 1.0 - math.exp(-1.0 / 2.0)
    np.testing.assert_allclose(
        motor[SETTLED + 1 :],
        motor[SETTLED:-1] + alpha * (setpoint[SETTLED:-1] - motor[SETTLED:-1]),
        atol=1e-6,
    )
    angle = trial.brace[:, 1]
    recorded_rate = np.gradient(angle, 1e-3)
    estimate = calibration_torque(motor - A * angle, recorded_rate, flexion, extension)
    filtered = signal.lfilter(*signal.butter(2, 20.0, fs=1000.0), estimate)
    plain = np.convolve(np.abs(recorded_rate) > 60.0, np.ones(80), mode="full")[: angle.size] == 80
    plain[:SETTLED] = False
    assert plain.sum() > 1500
    np.testing.assert_allclose(trial.brace[plain, 2], filtered[plain], atol=0.01)


def test_a_calibration_redone_per_trial_is_drawn_about_the_session_s():
    reading = dataclasses.replace(lab_calibration(), calibration="per_trial")
    trials = labsim.simulate_study(
        speeds_m_per_s=[0.8],
        stiffnesses_Nm_per_rad=[2.0, 3.5],
        duration_s=3.0,
        violations={},
        seed=3,
        reading=reading,
        **QUIET,
    )
    laws = []
    for trial in trials:
        assert trial.truth["reading"]["calibration"] == "per_trial"
        law = trial.truth["reading_drawn"]["transmission"]
        for way, session in (("flexion", reading.flexion), ("extension", reading.extension)):
            b, c, d = (law[way][k] for k in "BCD")
            assert abs(b / session[0] - 1) <= 0.05 and abs(c / session[1] - 1) <= 0.02
            assert abs(d - session[2]) <= 0.25
        flexion, extension = (tuple(law[w][k] for k in "BCD") for w in ("flexion", "extension"))
        state = trial.state
        rate = np.diff(state.brace_deg) * 1000.0
        stretch = state.motor_deg[1:] - A * state.brace_deg[1:]
        tau = calibration_torque(stretch, rate, flexion, extension)
        np.testing.assert_allclose(state.torque_Nm[1:], tau, atol=1e-9)
        laws.append((flexion, extension))
    assert laws[0] != laws[1]
    # the lab states the session's calibration and that it redoes it per trial
    config = reading.lab_config()
    assert config["transmission_calibrated"] == "per_trial"
    assert config["transmission"]["flexion"] == dict(zip("BCD", reading.flexion, strict=True))


# --- the channels -----------------------------------------------------------------------------


@pytest.mark.parametrize("counts", [2000, 4096, 10000])
def test_the_encoder_reads_whole_counts_of_its_turn(counts, tmp_path):
    step = 360.0 / counts
    reading = Reading(encoder_counts_per_turn=counts)
    trial = sim(reading)
    angle = trial.brace[:, 1]
    np.testing.assert_allclose(angle / step, np.round(angle / step), atol=1e-9)
    np.testing.assert_allclose(angle, step * np.round(trial.state.brace_deg / step), atol=1e-12)
    assert np.abs(np.diff(angle)).min(initial=np.inf, where=np.diff(angle) != 0) == pytest.approx(
        step
    )
    # the file prints three decimals: the counts stay whole to within half a thousandth of a degree
    labsim.write_study(
        tmp_path,
        speeds_m_per_s=[0.8],
        stiffnesses_Nm_per_rad=[KAPPA],
        duration_s=2.0,
        violations={},
        seed=5,
        reading=reading,
    )
    written = np.loadtxt(tmp_path / "v08_k35_brace.csv", delimiter=",", skiprows=1)[:, 1]
    assert np.abs(written / step - np.round(written / step)).max() <= 0.0005 / step + 1e-9


def lag_one(x: np.ndarray) -> float:
    """Lag-1 autocorrelation."""
    return float(np.corrcoef(x[1:], x[:-1])[0, 1])


def test_an_unfiltered_torque_channel_carries_white_noise():
    # The channel's noise: the noisy recording less the same trial without noise (a flat signal).
    # Unfiltered it is the load cell's white noise (lag-1 autocorrelation ≈ 0, SD σ); behind the
    # 20 Hz Butterworth it is coloured: lag-1 autocorrelation Σh_k·h_k+1 / Σh_k², SD σ·‖h‖.
    sd = 0.03
    open_ = Reading(torque_filter_Hz=None, load_cell_sd_Nm=sd)
    filtered = Reading(load_cell_sd_Nm=sd)
    white = sim(open_, quiet=False).brace[:, 2] - sim(open_).brace[:, 2]
    coloured = sim(filtered, quiet=False).brace[:, 2] - sim(filtered).brace[:, 2]
    assert abs(lag_one(white)) < 0.05
    assert white.std() == pytest.approx(sd, rel=0.05)
    h = signal.lfilter(*signal.butter(2, 20.0, fs=1000.0), np.eye(1, 2000)[0])
    assert lag_one(coloured) == pytest.approx(np.dot(h[1:], h[:-1]) / np.dot(h, h), abs=0.01)
    assert lag_one(coloured) > 0.9
    assert coloured.std() == pytest.approx(sd * np.linalg.norm(h), rel=0.08)
    # unfiltered, the quiet channel is the delivered torque itself
    np.testing.assert_array_equal(sim(open_).brace[:, 2], sim(open_).state.torque_Nm)


def test_a_torque_filter_at_another_cut_off():
    trial = sim(Reading(torque_filter_Hz=35.0))
    state_torque = trial.state.torque_Nm
    expected = signal.lfilter(*signal.butter(2, 35.0, fs=1000.0), state_torque)
    np.testing.assert_allclose(trial.brace[SETTLED:, 2], expected[SETTLED:], atol=1e-9)
    assert Reading(torque_filter_Hz=35.0).lab_config()["controller"]["torque_filter_Hz"] == 35.0
    assert Reading(torque_filter_Hz=None).lab_config()["controller"]["torque_filter_Hz"] is None


def test_motion_capture_re_zeroed_per_trial():
    kwargs = {
        "speeds_m_per_s": [0.8],
        "stiffnesses_Nm_per_rad": [0.0, 1.0, 3.5],
        "duration_s": 2.0,
        "violations": {},
        "seed": 7,
        **QUIET,
    }
    trials = labsim.simulate_study(reading=Reading(mocap_rezeroed=True), **kwargs)
    plain = labsim.simulate_study(reading=NOMINAL, **kwargs)
    zeros = []
    for trial, base in zip(trials, plain, strict=True):
        zero = trial.truth["reading_drawn"]["mocap_zero_deg"]
        assert abs(zero) <= 2.5 and trial.truth["reading"]["mocap_rezeroed"] is True
        np.testing.assert_allclose(trial.mocap[:, 1] - base.mocap[:, 1], zero, atol=1e-12)
        np.testing.assert_array_equal(trial.brace, base.brace)  # the encoder is sound
        zeros.append(zero)
    assert len(set(zeros)) == 3


def test_noise_levels_are_the_lab_s():
    reading = Reading(load_cell_sd_Nm=0.04, mocap_sd_deg=1.2, torque_filter_Hz=None)
    noisy, quiet = sim(reading, quiet=False), sim(reading)
    assert (noisy.brace[:, 2] - quiet.brace[:, 2]).std() == pytest.approx(0.04, rel=0.05)
    assert (noisy.mocap[:, 1] - quiet.mocap[:, 1]).std() == pytest.approx(1.2, rel=0.1)
    assert noisy.truth["noise"] == {"torque_sd_Nm": 0.04, "mocap_sd_deg": 1.2}
    assert reading.lab_config()["sensors"] == {"mocap_sd_deg": 1.2, "load_cell_sd_Nm": 0.04}


# --- the draw and the statement -------------------------------------------------------------------


def test_draw_reading_covers_every_variant_of_every_axis():
    rng = np.random.default_rng(1)
    readings = [draw_reading(rng) for _ in range(200)]
    seen = {
        "release_rule": {r.release_rule for r in readings},
        "engage_rule": {r.engage_rule for r in readings},
        "velocity": {(r.velocity_estimate, r.velocity_order) for r in readings},
        "calibration": {r.calibration for r in readings},
        "encoder": {r.encoder_counts_per_turn for r in readings},
        "torque_filter": {
            "none" if r.torque_filter_Hz is None else r.torque_filter_Hz == 20.0 for r in readings
        },
        "mocap_rezeroed": {r.mocap_rezeroed for r in readings},
    }
    assert seen == {
        "release_rule": {"peak_extension", "heel_strike", "velocity_threshold"},
        "engage_rule": {"table_6_1", "latched"},
        "velocity": {("butterworth", 1), ("butterworth", 2), ("centred_difference", 2)},
        "calibration": {"session", "per_trial"},
        "encoder": {2000, 4096, 5000, 10000},
        "torque_filter": {"none", True, False},
        "mocap_rezeroed": {False, True},
    }
    # each continuous axis: NOMINAL's value about a third of the time, else inside its range
    ranges = {
        "release_delay_s": (0.0, 0.05),
        "motor_time_constant_s": (0.002, 0.03),
        "friction_bias_Nm": (0.0, 0.15),
        "load_cell_sd_Nm": (0.005, 0.05),
        "mocap_sd_deg": (0.3, 1.5),
    }
    for name, (low, high) in ranges.items():
        values = np.array([getattr(r, name) for r in readings])
        kept = values == getattr(NOMINAL, name)
        assert 0.2 < kept.mean() < 0.47, name
        assert np.all((values[~kept] >= low) & (values[~kept] <= high)), name
    for r in readings:  # v_th only with its rule, then in its range
        threshold = r.release_threshold_deg_per_s
        assert (
            10.0 <= threshold <= 40.0 if r.release_rule == "velocity_threshold" else not threshold
        )
    cutoffs = [r.velocity_cutoff_Hz for r in readings if r.velocity_estimate == "butterworth"]
    assert all(c == 6.0 or 4.0 <= c <= 10.0 for c in cutoffs) and len(set(cutoffs)) > 20
    filters = [r.torque_filter_Hz for r in readings if r.torque_filter_Hz not in (None, 20.0)]
    assert filters and all(10.0 <= f <= 40.0 for f in filters)
    for r in readings:
        for law, nominal in ((r.flexion, FLEXION), (r.extension, EXTENSION)):
            b, c, d = law
            assert abs(b / nominal[0] - 1) <= 0.3 and abs(c / nominal[1] - 1) <= 0.15
            assert abs(d - nominal[2]) <= 1.0
    assert 0.2 < np.mean([r.flexion == FLEXION for r in readings]) < 0.47
    assert json.loads(json.dumps(readings[0].as_dict())) == readings[0].as_dict()


def test_lab_config_states_what_the_lab_states():
    reading = Reading(
        release_rule="velocity_threshold",
        release_threshold_deg_per_s=20.0,
        release_delay_s=0.01,
        engage_rule="latched",
        velocity_order=1,
        velocity_cutoff_Hz=5.0,
        motor_time_constant_s=0.01,
        friction_bias_Nm=0.05,
        flexion=(-0.2, 7.5, 0.5),
        extension=(-0.35, 6.0, -0.5),
        calibration="per_trial",
        encoder_counts_per_turn=4096,
        torque_filter_Hz=None,
        load_cell_sd_Nm=0.01,
        mocap_sd_deg=1.0,
        mocap_rezeroed=True,
    )
    assert reading.lab_config() == {
        "transmission": {
            "flexion": {"B": -0.2, "C": 7.5, "D": 0.5},
            "extension": {"B": -0.35, "C": 6.0, "D": -0.5},
        },
        "transmission_calibrated": "per_trial",
        "controller": {"torque_filter_Hz": None, "velocity_cutoff_Hz": 5.0},
        "sensors": {"mocap_sd_deg": 1.0, "load_cell_sd_Nm": 0.01},
        "lab": {
            "release_rule": "velocity_threshold",
            "release_threshold_deg_per_s": 20.0,
            "release_delay_s": 0.01,
            "engage_rule": "latched",
            "velocity_estimate": "butterworth",
            "velocity_order": 1,
            "encoder_counts_per_turn": 4096,
            "motor_time_constant_s": 0.01,
            "friction_bias_Nm": 0.05,
            "mocap_rezeroed": True,
        },
    }
    # the nominal statement is the project's own config block
    assert NOMINAL.lab_config()["controller"] == {
        "torque_filter_Hz": 20.0,
        "velocity_cutoff_Hz": 6.0,
    }
    assert NOMINAL.lab_config()["sensors"] == {"mocap_sd_deg": 0.8, "load_cell_sd_Nm": 0.02}


@pytest.mark.parametrize(
    "fields",
    [
        {"release_rule": "toe_off"},
        {"engage_rule": "always"},
        {"velocity_order": 3},
        {"velocity_order": 2.0},
        {"velocity_cutoff_Hz": 0.0},
        {"motor_time_constant_s": 0.0},
        {"friction_bias_Nm": -0.1},
        {"release_delay_s": -0.01},
        {"release_threshold_deg_per_s": 20.0},  # a threshold without its rule
        {"encoder_counts_per_turn": 5000.5},
        {"torque_filter_Hz": 600.0},
        {"load_cell_sd_Nm": -0.01},
        {"flexion": (-0.3, -7.0, 1.0)},  # b must rise: C > 0
        {"calibration": "weekly"},
        {"mocap_rezeroed": "yes"},
        {"mocap_rezeroed": 1},
    ],
)
def test_bad_readings_are_refused(fields):
    with pytest.raises(ValueError):
        Reading(**fields)


def test_every_drawn_reading_gives_a_plausible_recording():
    rng = np.random.default_rng(12)
    for _ in range(4):
        reading = draw_reading(rng)
        trial = labsim.simulate_study(
            speeds_m_per_s=[1.2],
            stiffnesses_Nm_per_rad=[3.5],
            duration_s=4.0,
            violations={},
            seed=2,
            reading=reading,
        )[0]
        assert np.isfinite(trial.brace).all() and np.isfinite(trial.mocap).all()
        assert np.abs(trial.brace[:, 2]).max() < 30 and (trial.brace[:, 3] > 0.5).any()
        assert trial.truth["reading"] == reading.as_dict()
