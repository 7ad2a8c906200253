"""Emulator twin and analysis: energy integration, events, encoder fault detection, budget."""

from __future__ import annotations

import numpy as np
import pandas as pd
import pytest

from emulator_helpers import DEFAULT, analysis_settings, emulator_config, random_seed
from exobench import selection
from exobench.emulator.chain import analysis, controller, crosscheck, energy, events, triangulation
from exobench.emulator.model import discrepancy
from exobench.emulator.recordings import acquire
from exobench.emulator.rig import BRACE_RATE_HZ, spring_torque
from exobench.emulator.study import budget
from exobench.emulator.twin import gait, twin
from exobench.emulator.validation import twin_arm as validation

DEFAULT_EFFECTS = (
    "cuff_compliance",
    "transmission_friction",
    "encoder_count_drop",
    "mocap_alignment",
    "soft_tissue_artefact",
)


def test_energy_integration_matches_the_closed_form_on_a_ramp():
    rng = np.random.default_rng(3)
    kappa = float(rng.uniform(0.5, 4.0))
    start, end = float(rng.uniform(45, 65)), float(rng.uniform(0, 15))
    equilibrium = 40.0
    angle = np.linspace(start, end, 4001)  # a ramp through the equilibrium
    torque = spring_torque(kappa, equilibrium, angle)
    engaged = np.ones_like(angle, dtype=bool)
    stored = energy.interval_energy_J(torque, angle, engaged).sum()
    assert stored == pytest.approx(float(energy.closed_form_J(kappa, equilibrium - end)), rel=1e-6)


def test_energy_is_zero_while_the_clutch_is_open():
    angle = np.linspace(60, 0, 101)
    torque = np.full_like(angle, 2.0)
    assert energy.interval_energy_J(torque, angle, np.zeros(101, dtype=bool)).sum() == 0.0


def test_twin_and_analysis_sum_the_same_energy_per_step():
    """The twin's truth (its own sum) and the analysis's energy per step, written apart, agree on
    random torque, angle and clutch; on a ramp through the equilibrium the twin's steps add up to
    the closed form."""
    rng = np.random.default_rng(random_seed("energy per step"))
    torque, angle = rng.normal(size=3000), np.cumsum(rng.normal(size=3000))
    engaged = rng.random(3000) < 0.6
    intervals = energy.interval_energy_J(torque, angle, engaged)
    for strikes in (
        np.sort(rng.choice(3000, size=6, replace=False)),
        np.array([0, 2999]),  # the first and the last sample
        np.array([5, 2999, 2999]),  # an empty last step
        np.array([1200]),  # no whole step
        np.array([], int),
    ):
        truth = twin.stored_energy_per_step_J(torque, angle, engaged, strikes)
        analysed = energy.per_step(intervals, strikes)
        assert truth.shape == analysed.shape == (max(strikes.size - 1, 0),)
        np.testing.assert_allclose(truth, analysed, rtol=0, atol=1e-12)
    ramp = np.linspace(60.0, 5.0, 4001)
    steps = twin.stored_energy_per_step_J(
        spring_torque(2.0, 40.0, ramp), ramp, np.ones(4001, bool), np.array([0, 1500, 4000])
    )
    assert steps.size == 2
    assert steps.sum() == pytest.approx(float(energy.closed_form_J(2.0, 35.0)), rel=1e-6)


def _simulate(seed, speed=0.8, stiffness=3.5, **effects):
    cfg = emulator_config(**effects)
    name = twin.trial_name(speed, stiffness)
    return cfg, twin.simulate(speed, stiffness, cfg, np.random.default_rng(seed), name)


def test_heel_strikes_lie_on_the_recorded_time_line():
    """A heel strike after the last sample closes no recorded step (the twin once failed on one
    in the last millisecond of a trial); sampled at 10 Hz, the last 0.1 s of a 3 s trial holds
    one in about one draw in eleven."""
    shape = gait.shape_for(DEFAULT["emulator"]["gait"]["shapes"], 0.8)
    variability = DEFAULT["emulator"]["gait"]["variability"]
    for seed in range(100):
        rng = np.random.default_rng(seed)
        t, _, strikes, _ = gait.trajectory(shape, 3.0, 10.0, variability, rng)
        assert 0.0 <= strikes.min() and strikes.max() <= t[-1], seed


def test_offline_clutch_matches_the_controller_that_produced_the_recording():
    cfg, rec = _simulate(4, encoder_count_drop=False)
    angle = rec.brace["brace_angle_deg"].to_numpy()
    omega = events.brace_velocity(angle, cfg["controller"]["velocity_cutoff_Hz"], BRACE_RATE_HZ)
    engaged = events.detect(angle, omega).engaged
    desired = rec.brace["desired_torque_Nm"].to_numpy()
    # the controller only asked for torque while its clutch was engaged
    assert engaged[desired > 0].all()
    # and while engaged below the equilibrium it always asked for torque
    below = engaged & (angle < cfg["controller"]["equilibrium_deg"] - 0.5)
    assert (desired[below] > 0).all()


def test_a_latched_arm_rebuilt_offline_matches_a_lab_controller_that_latches():
    from exobench.emulator.validation import labsim

    (trial,) = labsim.simulate_study(
        speeds_m_per_s=[1.2], stiffnesses_Nm_per_rad=[3.5], duration_s=8.0,
        violations={}, seed=4, reading=labsim.Reading(engage_rule="latched"),
        torque_noise_Nm=0.0, mocap_noise_deg=0.0,
    )  # fmt: skip
    angle, desired = trial.brace[:, 1], trial.brace[:, 3]
    omega = events.brace_velocity(angle, DEFAULT["emulator"]["controller"]["velocity_cutoff_Hz"],
                                  BRACE_RATE_HZ)  # fmt: skip
    latched = events.clutch(angle, omega, latched=True)
    table61 = events.clutch(angle, omega)
    # from the recording's first pass of 40° (its arm latched in the loop's warm-up before),
    # the lab's controller asked for torque only while the latched clutch was engaged, and
    # while engaged below the equilibrium always did; Table 6.1 misses its loading peaks
    seen = np.arange(angle.size) >= np.argmax(angle > 40.0)
    assert latched[seen & (desired > 0)].all()
    below = latched & (angle < DEFAULT["emulator"]["controller"]["equilibrium_deg"] - 0.5)
    assert (desired[seen & below] > 0).all()
    assert (table61 <= latched).all() and (desired[seen & ~table61] > 0).sum() > 1000


def test_the_twins_lowpass_is_scipys_butterworth():
    """The twin designs its controller's low-pass itself; the analysis uses scipy's. The brace
    torque the twin records and the one the engine predicts pass the same filter, settled on
    their first sample (a constant passes unchanged)."""
    from scipy.signal import butter

    for cutoff in (1.0, 6.0, 25.0, 200.0):
        b, a = twin.lowpass(cutoff, 1000.0)
        expected_b, expected_a = butter(2, cutoff, fs=1000.0)
        np.testing.assert_allclose(b, expected_b, rtol=1e-12)
        np.testing.assert_allclose(a, expected_a, rtol=1e-12, atol=1e-15)
    for cutoff in (0.0, 500.0, 600.0):
        with pytest.raises(ValueError, match="cut-off"):
            twin.lowpass(cutoff, 1000.0)
    rng = np.random.default_rng(random_seed("torque filter"))
    torque = np.cumsum(rng.normal(size=(3, 500)), axis=1)
    cutoff = float(rng.uniform(5.0, 100.0))
    engine = controller.recorded_torque_Nm(torque, cutoff, 1000.0)
    for row, predicted in zip(torque, engine, strict=True):
        np.testing.assert_allclose(twin.recorded_torque_Nm(row, cutoff), predicted, atol=1e-9)
    np.testing.assert_allclose(twin.recorded_torque_Nm(np.full(50, 1.5), cutoff), 1.5)
    np.testing.assert_array_equal(twin.recorded_torque_Nm(torque[0], None), torque[0])


def test_online_and_offline_events_agree_sample_for_sample():
    """The events the twin's controller flagged online (its own compiled rules) are the ones
    the analysis finds offline in the recorded angle."""
    cfg, rec = _simulate(5, encoder_count_drop=False)
    angle = rec.brace["brace_angle_deg"].to_numpy()
    omega = events.brace_velocity(angle, cfg["controller"]["velocity_cutoff_Hz"], BRACE_RATE_HZ)
    offline = events.detect(angle, omega)
    online = rec.truth["controller_event_samples"]
    assert len(online["heel_strike"]) > 10
    for kind in ("peak_flexion", "peak_extension", "heel_strike"):
        np.testing.assert_array_equal(getattr(offline, kind), online[kind], err_msg=kind)


def test_heel_strikes_are_found_for_every_true_step():
    cfg, rec = _simulate(6)
    samples, _, _ = analysis.analyse("t", rec.brace, rec.mocap, 3.5, analysis_settings(cfg))
    detected = samples["t_s"].to_numpy()[samples["heel_strike"].to_numpy()]
    accuracy = analysis.event_accuracy(
        detected, np.asarray(rec.truth["heel_strikes_s"]), cfg["analysis"]["match_window_s"]
    )
    assert accuracy["n_matched"] == accuracy["n_in_span"] > 15
    assert accuracy["n_true"] - accuracy["n_in_span"] <= 2  # at most the two cut strides
    assert accuracy["max_abs_error_ms"] < 60.0


def _trial_with_drops(rng, sizes, times):
    """A trial at a random speed and spring with count drops of these sizes at these times."""
    speed, stiffness = float(rng.choice([0.8, 1.2])), float(rng.choice([1.0, 2.0, 3.5]))
    cfg = emulator_config()
    name = twin.trial_name(speed, stiffness)
    cfg["effects"]["encoder_count_drop"].update(trials=[name], size_deg=sizes, time_s=times)
    return cfg, name, stiffness, twin.simulate(speed, stiffness, cfg, rng, name)


@pytest.mark.parametrize("layout", ["first_second", "last_second", "two_inside", "close_pair"])
def test_count_drops_anywhere_are_found_sized_timed_and_their_steps_corrected(layout):
    rng = np.random.default_rng(random_seed(f"count drops, {layout}"))
    duration = 30.0
    inside = sorted(rng.uniform(2.0, duration - 2.0, 2).tolist())
    times = {
        "first_second": [float(rng.uniform(0.2, 1.0)), inside[0]],
        "last_second": [inside[0], float(rng.uniform(duration - 1.0, duration - 0.2))],
        "two_inside": inside,
        # closer than the 100 Hz fit can split: the 1 kHz encoder's jumps tell them apart
        "close_pair": [inside[0], inside[0] + float(rng.uniform(0.005, crosscheck.MIN_SIDE_S))],
    }[layout]
    sizes = rng.uniform(2.5, 8.0, 2).tolist()  # the documented range: 2.5° to 8°
    cfg, name, stiffness, rec = _trial_with_drops(rng, sizes, times)
    samples, steps, qc = analysis.analyse(
        name, rec.brace, rec.mocap, stiffness, analysis_settings(cfg)
    )
    assert qc["encoder_fault"] is True
    found = qc["count_drops"]
    assert len(found) == 2
    for drop, size, onset in zip(found, sizes, times, strict=True):
        assert drop["time_s"] == pytest.approx(onset, abs=0.005)
        assert -drop["size_deg"] == pytest.approx(size, abs=0.2)
    # a step holding a drop is marked and corrected: the measured torque over the encoder angle
    # with the true drops put back
    marked = steps["encoder_drop_deg"] != 0
    assert marked.any()
    assert (steps.loc[marked, "correction"] != "").all()
    assert (steps.loc[~marked, "correction"] == "").all()
    t = rec.brace["time_s"].to_numpy()
    lost = (t[:, None] >= np.asarray(rec.truth["encoder_fault_times_s"])[None, :]) @ np.asarray(
        rec.truth["encoder_count_drops_deg"]
    )
    stored = energy.interval_energy_J(
        rec.brace["brace_torque_Nm"].to_numpy(),
        rec.brace["brace_angle_deg"].to_numpy() + lost,
        rec.brace["desired_torque_Nm"].to_numpy() != 0,
    )
    truth = energy.per_step(stored, np.flatnonzero(samples["heel_strike"].to_numpy()))
    np.testing.assert_allclose(steps["energy_J"], truth, rtol=0.01, atol=0.002)


def test_a_one_sample_glitch_beside_a_drop_is_not_a_second_drop():
    """A spike of the drop's sign next to a drop: the encoder comes back the next sample, so it
    leaves no shift and the drop stands alone, timed and sized as without the spike."""
    rng = np.random.default_rng(random_seed("drop beside a glitch"))
    onset, size = float(rng.uniform(5.0, 25.0)), float(rng.uniform(2.5, 8.0))
    glitch = float(rng.uniform(0.4, 0.9)) * size
    cfg, name, stiffness, rec = _trial_with_drops(rng, [size], [onset])
    brace = rec.brace.copy()
    t = brace["time_s"].to_numpy()
    spike = int(np.searchsorted(t, onset + float(rng.choice([-1, 1])) * rng.uniform(0.02, 0.06)))
    brace.loc[spike, "brace_angle_deg"] -= glitch
    _, _, qc = analysis.analyse(name, brace, rec.mocap, stiffness, analysis_settings(cfg))
    (drop,) = qc["count_drops"]
    assert drop["time_s"] == pytest.approx(onset, abs=0.005)
    assert -drop["size_deg"] == pytest.approx(size, abs=0.2)


@pytest.mark.parametrize("seed", [31, 32])
def test_a_clean_trial_raises_no_fault(seed):
    cfg, rec = _simulate(seed, speed=1.2, stiffness=3.5, encoder_count_drop=False)
    _, _, qc = analysis.analyse("clean", rec.brace, rec.mocap, 3.5, analysis_settings(cfg))
    assert qc["encoder_fault"] is False
    assert qc["fault_time_s"] is None
    assert qc["count_drops"] == []


@pytest.mark.parametrize("artefact", [False, True])
def test_mocap_zero_gain_and_clock_are_estimated_not_taken_for_an_encoder_fault(artefact):
    rng = np.random.default_rng(random_seed(f"alignment, artefact {artefact}"))
    zero = float(rng.choice([-1, 1]) * rng.uniform(1.0, 3.0))
    gain, clock = (
        float(rng.uniform(0.93, 1.0)),
        float(rng.choice([-1, 1]) * rng.uniform(0.01, 0.03)),
    )
    cfg = emulator_config(encoder_count_drop=False, soft_tissue_artefact=artefact)
    cfg["effects"]["mocap_alignment"].update(zero_deg=zero, gain=gain, clock_offset_s=clock)
    speed, stiffness = float(rng.choice([0.8, 1.2])), float(rng.choice([0.0, 2.0, 3.5]))
    rec = twin.simulate(speed, stiffness, cfg, rng, "aligned")
    _, _, qc = analysis.analyse("aligned", rec.brace, rec.mocap, stiffness, analysis_settings(cfg))
    assert qc["encoder_fault"] is False
    assert qc["count_drops"] == []
    found = qc["alignment"]
    # zero and gain: within twice their 95 % half-width (about 4 SE) of the values set; the
    # clock: a soft-tissue artefact in step with the gait pulls the increments' lag
    for estimate, key in (
        ("mocap_zero_deg", "mocap_zero_ci95_deg"),
        ("mocap_gain", "mocap_gain_ci95"),
    ):
        low, high = found[key]
        assert abs(found[estimate] - rec.truth[estimate]) <= high - low
    tolerance = {"clock": 0.008} if artefact else {"clock": 0.004}
    assert found["clock_offset_s"] == pytest.approx(
        rec.truth["mocap_clock_offset_s"], abs=tolerance["clock"]
    )


def test_the_session_tells_a_drop_before_the_trial_from_the_mocap_zero():
    rng = np.random.default_rng(random_seed("session offset"))
    cfg = emulator_config()
    cfg["effects"]["mocap_alignment"]["zero_deg"] = float(rng.uniform(-3.0, 3.0))
    conditions = [(0.8, 2.0), (0.8, 3.5), (1.2, 2.0), (1.2, 3.5)]
    dropped = twin.trial_name(*conditions[int(rng.integers(len(conditions)))])
    size = float(rng.uniform(2.5, 8.0))
    cfg["effects"]["encoder_count_drop"].update(trials=[dropped], size_deg=size, time_s=0.0)
    cfg["protocol"]["duration_s"] = 15.0
    records = {}
    for i, (speed, stiffness) in enumerate(conditions):
        name = twin.trial_name(speed, stiffness)
        rec = twin.simulate(speed, stiffness, cfg, np.random.default_rng([i, 7]), name)
        records[name] = analysis.analyse(
            name, rec.brace, rec.mocap, stiffness, analysis_settings(cfg)
        )[2]
    session = triangulation.session(records, cfg["analysis"]["fault_threshold_deg"], "per_trial")
    assert session["offset_checked"] is True
    flagged = [t for t, r in session["trials"].items() if r["encoder_fault"]]
    assert flagged == [dropped]
    record = session["trials"][dropped]
    assert record["fault_kinds"] == ["drop_before_trial"]
    assert -record["encoder_offset_deg"] == pytest.approx(size, abs=0.3)


@pytest.mark.parametrize("source", ["desired_torque", "clutch_flag"])
def test_energy_follows_the_recorded_activity_of_a_controller_departing_from_table_6_1(
    source, tmp_path
):
    rng = np.random.default_rng(random_seed(f"departing controller, {source}"))
    speed, stiffness = float(rng.choice([0.8, 1.2])), float(rng.uniform(1.0, 3.5))
    cfg = emulator_config(encoder_count_drop=False)
    rec = twin.simulate(speed, stiffness, cfg, rng, "departing")
    brace = rec.brace.copy()
    angle = brace["brace_angle_deg"].to_numpy()
    omega = events.brace_velocity(angle, cfg["controller"]["velocity_cutoff_Hz"], BRACE_RATE_HZ)
    spec = events.detect(angle, omega).engaged
    # this controller engages `early` samples before Table 6.1 and releases `late` samples after
    # it, into the next stance; its cable then follows the spring law
    early, late = int(rng.integers(20, 80)), int(rng.integers(40, 120))
    edges = np.diff(spec.astype(int), prepend=0, append=0)
    active = np.zeros_like(spec)
    for on, off in zip(np.flatnonzero(edges == 1), np.flatnonzero(edges == -1), strict=True):
        active[max(on - early, 0) : off + late] = True
    desired = spring_torque(stiffness, 40.0, angle) * active
    measured = brace["brace_torque_Nm"].to_numpy()
    brace["desired_torque_Nm"] = desired
    brace["brace_torque_Nm"] = np.where(spec, measured, desired + measured * ~active)
    if source == "clutch_flag":
        brace["clutch_engaged"] = active.astype(int)
    path = tmp_path / "departing_brace.csv"
    brace.to_csv(path, index=False)
    read = acquire.read_brace(
        path,
        float(cfg["protocol"]["duration_s"]),
        max_gap_fraction=0.0,
        rate_range_Hz=cfg["analysis"]["brace_rate_range_Hz"],
    )
    samples, steps, qc = analysis.analyse(
        "departing", read, rec.mocap, stiffness, analysis_settings(cfg)
    )
    check = qc["table61_crosscheck"]
    assert check["share_of_steps_disagreeing"] > 0.9
    assert check["phases_disagreeing_pct"]
    # around heel strike: the late release (and, with a flag, the early engagement at the end
    # of swing); nowhere in mid-stance
    assert all(low >= 60.0 or low < 30.0 for low, _ in check["phases_disagreeing_pct"])
    hs = np.flatnonzero(samples["heel_strike"].to_numpy())
    torque, recorded = brace["brace_torque_Nm"].to_numpy(), brace["desired_torque_Nm"] != 0
    if source == "clutch_flag":
        recorded = active
    truth = energy.per_step(energy.interval_energy_J(torque, angle, np.asarray(recorded)), hs)
    by_spec = energy.per_step(energy.interval_energy_J(torque, angle, spec), hs)
    np.testing.assert_allclose(steps["energy_J"], truth, rtol=0.02)
    assert not np.allclose(by_spec, truth, rtol=0.02)  # Table 6.1's windows would miss it


def test_measured_energy_follows_the_twin_truth():
    """The analysis measures what the files hold (the twin's own sum over its recorded torque);
    the 20 Hz low-pass of that torque (Heer §5.2) lags a knee extending in late swing, so the
    energy recorded falls short of the energy the cable delivered, and without the filter it
    would not."""
    cfg, rec = _simulate(7, speed=1.2, stiffness=2.0)
    _, steps, _ = analysis.analyse("t", rec.brace, rec.mocap, 2.0, analysis_settings(cfg))
    recorded = np.mean(rec.truth["recorded_energy_per_step_J"])
    delivered = np.mean(rec.truth["true_energy_per_step_J"])
    assert steps["energy_J"].mean() == pytest.approx(recorded, rel=0.01)
    assert recorded < 0.9 * delivered
    cfg["controller"]["torque_filter_Hz"] = None
    unfiltered = twin.simulate(1.2, 2.0, cfg, np.random.default_rng(7), "t")
    assert np.mean(unfiltered.truth["recorded_energy_per_step_J"]) == pytest.approx(
        delivered, rel=0.03
    )


def test_thermal_equations_are_inverse_and_reproduce_the_seed_chain():
    rng = np.random.default_rng(9)
    resistance, alpha, thermal = rng.uniform(0.1, 1.0), 0.00393, rng.uniform(0.5, 6.0)
    limit = budget.max_current_A(130.0, resistance, alpha, thermal)
    assert budget.winding_rise_K(limit, resistance, alpha, thermal) == pytest.approx(130.0)
    cfg = emulator_config()
    chain = budget.check(cfg["budget"], cfg["transmission"], np.array([1.0]))
    motor = cfg["budget"]["motor"]
    expected_motor = chain["max_continuous_current_A"]["heat_sink"] * (
        motor["torque_constant_Nm_per_A"] * motor["efficiency"]
    )
    assert chain["motor_torque_at_max_current_Nm"] == pytest.approx(expected_motor)
    assert chain["cable_tension_at_max_current_N"] == pytest.approx(
        chain["gearhead_torque_at_max_current_Nm"] / cfg["transmission"]["motor_pulley_radius_m"]
    )


FAST_ENGINE = {"folds": 3, "bootstrap": 0, "max_effects": 3, "screen": 3, "null_draws": 100}


def _engine(cfg, seed):
    settings = analysis_settings(cfg)
    trials = {}
    for i, (speed, stiffness) in enumerate([(0.8, 2.0), (0.8, 3.5), (1.2, 2.0), (1.2, 3.5)]):
        name = twin.trial_name(speed, stiffness)
        rec = twin.simulate(speed, stiffness, cfg, np.random.default_rng([seed, i]), name)
        trials[name] = (
            stiffness,
            *analysis.analyse(name, rec.brace, rec.mocap, stiffness, settings),
        )
    qc = triangulation.session(
        {n: v[3] for n, v in trials.items()}, settings["fault_threshold_deg"], "per_trial"
    )
    parts = [
        (name, stiffness, samples, qc["trials"][name])
        for name, (stiffness, samples, _, _) in trials.items()
    ]
    data, scales = discrepancy.observations(
        parts,
        settings["equilibrium_deg"],
        settings["direction_blend_deg_per_s"],
        cfg["transmission"],
        FAST_ENGINE["folds"],
        cfg["controller"]["torque_filter_Hz"],
    )
    return discrepancy.analyse(data, scales, FAST_ENGINE, seed, "test")


def _selected_value(report, effect, parameter):
    entry = {e["effect"]: e for e in report["effects_found"] + report["tentative"]}[effect]
    return entry["parameters"][parameter]


@pytest.mark.parametrize(
    ("effect", "twin_parameter", "parameter", "low", "high", "seed"),
    [
        ("cuff_compliance", "compliance_deg_per_Nm", "compliance_deg_per_Nm", 0.8, 2.0, 41),
        ("transmission_friction", "friction_fraction", "friction_fraction", 0.05, 0.2, 43),
    ],
)
def test_discrepancy_engine_selects_a_hidden_effect_and_sizes_it(
    effect, twin_parameter, parameter, low, high, seed
):
    magnitude = float(np.random.default_rng(seed).uniform(low, high))
    cfg = emulator_config(**{**dict.fromkeys(DEFAULT_EFFECTS, False), effect: True})
    cfg["effects"][effect][twin_parameter] = magnitude
    cfg["protocol"]["duration_s"] = 15.0
    report = _engine(cfg, seed)
    assert effect in report["selected"], report["cause"]
    assert _selected_value(report, effect, parameter) == pytest.approx(magnitude, rel=0.2)


def test_discrepancy_engine_finds_nothing_without_effects():
    cfg = emulator_config(**dict.fromkeys(DEFAULT_EFFECTS, False))
    cfg["protocol"]["duration_s"] = 15.0
    report = _engine(cfg, random_seed("clean twin, engine"))
    assert report["selected"] == [], report["cause"]
    assert not report["unexplained"]["flag"], report["cause"]


def test_cuff_lag_at_window_samples_matches_a_fine_step_solution():
    rng = np.random.default_rng(random_seed("cuff lag"))
    tau, step = float(rng.uniform(0.005, 0.08)), 0.01
    fine = 1e-5
    t = np.arange(0.0, 0.6, fine)
    frequency = rng.uniform(0.5, 3.0)
    force = np.sin(np.pi * frequency * t) ** 2  # from rest, smooth, like swing torque
    lagged = np.zeros_like(t)
    for k in range(1, t.size):  # τ·y' = x − y, Euler at 10 µs
        lagged[k] = lagged[k - 1] + fine / tau * (force[k - 1] - lagged[k - 1])
    every = round(step / fine)
    coarse = discrepancy.effects.cuff_lag(force[None, ::every], tau, step)[0]
    np.testing.assert_allclose(coarse, lagged[::every], atol=0.01)


def test_the_engine_predicts_the_twins_late_clutch_release_to_the_sample(tmp_path):
    rng = np.random.default_rng(random_seed("late clutch release"))
    delay = int(rng.integers(3, 100)) / 1000.0  # whole controller samples
    base = validation.base_config(DEFAULT["emulator"])
    base["protocol"] = {"speeds_m_per_s": [1.2], "stiffnesses_Nm_per_rad": [3.5],
                        "duration_s": 10.0}  # fmt: skip
    case = {"hidden": {"clutch_late_release": {"release_delay_s": delay}},
            "drop": {"trial": "none", "time_s": 0.0}}  # fmt: skip
    cfg = validation.twin_config(base, case)
    seed = int(rng.integers(2**31))
    parts = validation.chain_parts(validation.recordings(tmp_path, cfg, case, seed), cfg, seed)
    data, scales = discrepancy.observations(
        parts,
        40.0,
        cfg["controller"]["direction_blend_deg_per_s"],
        cfg["transmission"],
        2,
        cfg["controller"]["torque_filter_Hz"],
    )
    problem = discrepancy.problem()

    def misfit(effects, value):
        res = selection.residuals(problem, data, effects, {"release_delay_s": value}, scales)
        return float(np.sqrt(np.mean(res["desired_impulse"] ** 2)))

    late = ["clutch_late_release"]
    assert misfit(late, delay) < 0.5  # within the impulse's resolution
    assert misfit(late, delay + 0.001) > 10.0 and misfit(late, delay - 0.001) > 10.0
    assert misfit([], 0.0) > 10.0  # Table 6.1's own release misses it
    fitted, _ = selection.fit(problem, data, late, scales)
    assert fitted["release_delay_s"] == pytest.approx(delay, abs=1e-5)


def test_the_twins_csv_text_is_pandas_text():
    # the twin formats finite float frames a row at a time; the text must be pandas' own
    rng = np.random.default_rng(random_seed("csv"))
    values = rng.normal(0.0, 1.0, (500, 4)) * 10.0 ** rng.integers(-8, 4, (500, 4))
    values[:3] = [[-0.0, -1e-9, 1e9, 0.5e-6]] * 3  # signed zeros, rounding ties, large values
    frame = pd.DataFrame(values, columns=["time_s", "a_deg", "b_Nm", "c_deg"])
    assert twin._csv(frame) == frame.to_csv(index=False, lineterminator="\n", float_format="%.6f")
    frame.iloc[7, 2] = np.nan  # a gap, a nullable column, a quoted name: pandas writes them
    mixed = frame.astype({"b_Nm": "Float64"}).rename(columns={"c_deg": "c, deg"})
    for other in (frame, mixed):
        text = other.to_csv(index=False, lineterminator="\n", float_format="%.6f")
        assert twin._csv(other) == text


def test_stages_kept_between_evaluations_equal_those_computed_afresh():
    # solve keeps the last stages per set of observations (a fit's Jacobian moves one parameter
    # at a time): a kept stage never stands in for other observations or another value
    seed = random_seed("kept stages")
    rng = np.random.default_rng(seed)
    cfg = emulator_config()
    cfg["protocol"]["duration_s"] = 10.0
    # a drop during the trial: the rows that reach it are recomputed at 1 kHz
    cfg["effects"]["encoder_count_drop"].update(size_deg=5.0, time_s=float(rng.uniform(3.0, 7.0)))
    settings = analysis_settings(cfg)
    name = twin.trial_name(1.2, 3.5)
    rec = twin.simulate(1.2, 3.5, cfg, rng, name)
    samples, _, record = analysis.analyse(name, rec.brace, rec.mocap, 3.5, settings)
    qc = triangulation.session({name: record}, settings["fault_threshold_deg"], "per_trial")
    data, scales = discrepancy.observations(
        [(name, 3.5, samples, qc["trials"][name])], settings["equilibrium_deg"],
        settings["direction_blend_deg_per_s"], cfg["transmission"], 2,
        cfg["controller"]["torque_filter_Hz"],
    )  # fmt: skip
    problem = discrepancy.problem()
    effects = ("mocap_clock", "encoder_count_drop", "transmission_friction", "clutch_late_release")
    # every other row: two sets of observations of the same shape, other samples, each with rows
    # that reach the drop
    half = data.units // 2
    halves = [data.take(np.arange(k, 2 * half, 2)) for k in (0, 1)]
    assert all(h.arrays["drop_rows"].any() for h in halves)
    draws = [{"clock_offset_s": rng.uniform(-0.03, 0.03), "drop_deg": rng.uniform(-8.0, 8.0),
              "friction_fraction": rng.uniform(-0.2, 0.2),
              "release_delay_s": rng.uniform(0.001, 0.05)} for _ in range(3)]  # fmt: skip
    # the same values on other observations of equal shape, a repeat, one parameter moved, all
    # with the stages kept; then each afresh
    calls = [(d, draws[0]) for d in (data, *halves)] + [(halves[1], draws[0])]
    calls += [(halves[1], {**draws[0], key: draws[1][key]}) for key in draws[1]]
    calls += [(halves[0], draws[2]), (halves[1], draws[2])]
    kept = [selection.residuals(problem, d, effects, values, scales) for d, values in calls]
    for (observations, values), before in zip(calls, kept, strict=True):
        discrepancy.effects._MEMO.clear()
        fresh = selection.residuals(problem, observations, effects, values, scales)
        for obs in fresh:
            np.testing.assert_array_equal(before[obs], fresh[obs], err_msg=f"seed {seed}: {obs}")
