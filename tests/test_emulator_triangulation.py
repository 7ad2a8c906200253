"""Which angle sensor moved between trials (issue 54, item 3): the encoder, motion capture and the
brace angle the cable implies. The generator's re-zeroed motion capture is drawn from a printed
seed and read only in the final assertions."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pandas as pd
import pytest

from emulator_helpers import DEFAULT, random_seed
from exobench.emulator.chain import triangulation
from exobench.emulator.model import checks
from exobench.emulator.model.effects import ENCODER_COUNT_DEG
from exobench.emulator.validation import labsim, openworld

BLOCK = DEFAULT["emulator"]
THRESHOLD = BLOCK["analysis"]["fault_threshold_deg"]


@pytest.mark.parametrize(
    ("delta_em", "delta_ec", "calibration", "which"),
    [
        (-5.0, -5.2, "session", ("encoder",)),  # both pairings of the encoder depart alike
        (-5.0, -5.2, "per_trial", ("encoder",)),  # a refit D moves the set point, not the reading
        (-5.0, -7.2, "session", ("encoder", "mocap")),  # the cable holds: both moved
        (-5.0, -7.2, "per_trial", ("undecided",)),  # the cable may have moved too
        (5.0, 5.2, "session", ("undecided",)),  # counts gained: the median carries dropped trials
        (2.0, 0.1, "session", ("mocap",)),  # the encoder agrees with the cable
        (2.0, 0.1, "per_trial", ("mocap",)),
        (3.0, 1.49, "per_trial", ("undecided",)),  # near neither hypothesis
        (0.2, 2.0, "session", ("cable",)),  # encoder and motion capture agree
        (0.2, 2.0, "per_trial", ()),  # a cable recalibrated per trial may change
        (2.0, None, "session", ("undecided",)),  # no cable reading: two readings cannot tell
        (-2.0, -1.0, "session", ("undecided",)),  # a departure neither move accounts for
        (2.0, 1.0, "session", ("undecided",)),
        (-1.4, -2.0, "session", ("encoder",)),  # against the cable the encoder lost 2°
        (-0.5, -2.0, "session", ("cable",)),  # encoder and motion capture agree within T/2
        (0.3, None, "session", ()),
        (0.3, -0.2, "session", ()),
    ],
)
def test_the_sensor_that_moved_is_the_one_both_of_whose_pairings_depart(
    delta_em, delta_ec, calibration, which
):
    assert triangulation.moved(delta_em, delta_ec, THRESHOLD, calibration) == which


def test_the_cable_implies_the_brace_angle_the_controller_set_the_motor_for():
    transmission = BLOCK["transmission"]
    rng = np.random.default_rng(5)
    theta = rng.uniform(0.0, 60.0, 500)
    torque = rng.uniform(0.5, 8.0, 500)
    omega = rng.uniform(-80.0, 80.0, 500)
    blend = BLOCK["controller"]["direction_blend_deg_per_s"]
    # eqs. (5.6)–(5.8) as the thesis writes them: each direction's set point, blended linearly
    # between −blend and +blend by the brace's velocity
    ratio = transmission["brace_pulley_radius_m"] / transmission["motor_pulley_radius_m"]
    points = {
        name: ratio * theta + c["B"] * torque**2 + c["C"] * torque + c["D"]
        for name, c in ((n, transmission[n]) for n in ("extension", "flexion"))
    }
    share = np.clip((omega + blend) / (2.0 * blend), 0.0, 1.0)  # of the flexion set point
    motor = share * points["flexion"] + (1.0 - share) * points["extension"]
    implied = triangulation.cable_angle_deg(motor, torque, omega, transmission, blend)
    assert np.allclose(implied, theta, atol=1e-9)


def test_an_unknown_calibration_is_refused():
    with pytest.raises(KeyError, match="monthly"):
        triangulation.session({}, THRESHOLD, "monthly")


def _lab(tmp_path: Path, calibration: str, seed: int, dropped: float = 0.0):
    """A lab whose motion capture is re-zeroed before every trial (its zero drawn by the
    generator), calibrated as ``calibration`` says, its encoder ``dropped`` degrees (whole
    counts) low from the start in one trial drawn from ``seed``: the chain's parts, the direct
    checks, the zeros the generator drew and the trial with the drop."""
    reading = labsim.Reading(mocap_rezeroed=True, calibration=calibration)
    manifest = labsim.write_study(tmp_path, speeds_m_per_s=[0.8, 1.2],
                                  stiffnesses_Nm_per_rad=[1.5, 2.0, 2.5, 3.0, 3.5], duration_s=15.0,
                                  violations={}, seed=seed, reading=reading)  # fmt: skip
    trials = sorted(p.name.removesuffix("_brace.csv") for p in tmp_path.glob("*_brace.csv"))
    hit = trials[int(np.random.default_rng(seed).integers(len(trials)))]
    if dropped:  # counts lost before the recording began: the encoder reads low throughout
        brace = tmp_path / f"{hit}_brace.csv"
        frame = pd.read_csv(brace)
        counts = round(dropped / ENCODER_COUNT_DEG)
        frame["brace_angle_deg"] = (frame["brace_angle_deg"] - counts * ENCODER_COUNT_DEG).round(3)
        frame.to_csv(brace, index=False)
    cfg = openworld.settings(BLOCK, 15.0, reading.lab_config())
    parts = openworld.chain_parts(manifest, cfg, seed)
    table = checks.checks(parts, openworld.check_settings(cfg)).set_index("assumption")
    truth = {p["trial"]: json.loads((tmp_path / "truth" / f"{p['trial']}.json").read_text())
             for p in parts}  # fmt: skip
    zeros = {t: r["reading_drawn"]["mocap_zero_deg"] for t, r in truth.items()}
    return parts, table, zeros, hit


@pytest.mark.parametrize("calibration", ["session", "per_trial"])
def test_a_re_zeroed_motion_capture_is_named_with_its_trials_not_the_encoder(tmp_path, calibration):
    parts, table, zeros, _ = _lab(tmp_path, calibration, random_seed(f"rezeroed-{calibration}"))
    moved = {p["trial"]: p["qc"]["zero_moved"] for p in parts}
    assert not any(p["qc"]["encoder_fault"] for p in parts)
    assert table.loc["encoder", "decision"] == "holds"
    assert all(m in ([], ["mocap"]) for m in moved.values())
    # the trials whose drawn zero lies well apart from the session's are named, in the row of
    # motion capture's zero and in the session QC
    middle = np.median(list(zeros.values()))
    apart = [t for t, z in zeros.items() if abs(z - middle) >= THRESHOLD + 0.5]
    named = [t for t, m in moved.items() if m == ["mocap"]]
    assert named and set(apart) <= set(named)
    assert table.loc["mocap_zero_between", "decision"] == "violated"
    detail = table.loc["mocap_zero_between", "detail"]
    assert all(t in detail.split("re-zeroed before", 1)[1] for t in named)


@pytest.mark.parametrize("calibration", ["session", "per_trial"])
def test_a_drop_before_a_trial_is_told_from_a_re_zeroed_motion_capture(tmp_path, calibration):
    seed = random_seed(f"drop-and-rezeroed-{calibration}")
    size = float(np.random.default_rng([seed, 1]).uniform(3.0, 8.0))
    parts, table, _, hit = _lab(tmp_path, calibration, seed, dropped=size)
    faulty = [p["trial"] for p in parts if "drop_before_trial" in p["qc"]["fault_kinds"]]
    qc = next(p["qc"] for p in parts if p["trial"] == hit)
    if calibration == "session":  # the cable as the reference sizes the encoder's own move
        assert faulty == [hit]
        assert abs(-qc["encoder_moved_deg"] - size) < 0.5 * THRESHOLD
        assert table.loc["encoder", "decision"] == "violated"
    else:  # the dropped trial's motion capture moved too: named only where the cable fits
        assert faulty in ([], [hit]) and qc["zero_moved"] in (["encoder"], ["undecided"])
        assert table.loc["encoder", "decision"] == ("violated" if faulty else "undecided")


def test_the_cable_is_read_against_the_trials_whose_encoder_agrees_with_motion_capture():
    def record(offset, cable):
        return {"alignment": {"encoder_offset_deg": offset}, "fault_kinds": [], "start_s": 0.0,
                "cable": {"encoder_minus_cable_deg": cable}}  # fmt: skip

    # two cable readings, a lab's calibration reading the brace 1° off: the agreeing trial's is
    # the reference
    records = {"a": record(-1.8, None), "b": record(-1.7, None), "c": record(-1.9, -1.0),
               "d": record(-6.8, -6.1)}  # fmt: skip
    session = triangulation.session(records, THRESHOLD, "per_trial")
    assert session["zero_moved"]["encoder"] == ["d"]
    assert session["trials"]["d"]["encoder_fault"] and not session["trials"]["c"]["zero_moved"]
    # no trial agreeing and fewer than three readings: the cable cannot decide
    records = {"a": record(-1.8, None), "b": record(-1.7, None), "c": record(-1.9, None),
               "d": record(-6.8, -6.1), "e": record(2.0, -1.0)}  # fmt: skip
    session = triangulation.session(records, THRESHOLD, "session")
    assert session["zero_moved"]["undecided"] == ["d", "e"] and not session["zero_moved"]["encoder"]


def _study(tmp_path: Path, seed: int, violations: dict, mocap_sd_deg: float):
    """A lab's study (two speeds, two springs, 15 s) with the given violations and motion-capture
    noise: the chain's parts and the generator's truth per trial."""
    reading = labsim.Reading(mocap_sd_deg=mocap_sd_deg)
    manifest = labsim.write_study(tmp_path, speeds_m_per_s=[0.8, 1.2],
                                  stiffnesses_Nm_per_rad=[2.0, 3.0], duration_s=15.0,
                                  violations=violations, seed=seed, reading=reading)  # fmt: skip
    parts = openworld.chain_parts(manifest, openworld.settings(BLOCK, 15.0, reading.lab_config()),
                                  seed)  # fmt: skip
    truth = {p["trial"]: json.loads((tmp_path / "truth" / f"{p['trial']}.json").read_text())
             for p in parts}  # fmt: skip
    return parts, truth


def test_a_count_drop_below_motion_captures_noise_is_located_by_the_cable(tmp_path):
    seed = random_seed("cable-drop")
    size = float(np.random.default_rng([seed, 2]).uniform(2.0, 3.5))
    parts, truth = _study(tmp_path, seed, {"encoder.step": {"drop_deg": size}}, 2.0)
    by_cable = 0
    for part in parts:
        qc, drawn = part["qc"], truth[part["trial"]]["drawn"]["encoder.step"]["time_s"]
        # motion capture's threshold (2.5 × its noise) lies above the drop: the cable finds it,
        # to the sample, sized on the encoder's own jump, and the trial starts sound
        assert qc["alignment"]["drop_threshold_deg"] > size
        assert len(qc["count_drops"]) == 1, qc["count_drops"]
        drop = qc["count_drops"][0]
        assert abs(drop["time_s"] - drawn) <= 0.0015
        assert abs(-drop["size_deg"] - size) <= ENCODER_COUNT_DEG
        assert "drop_before_trial" not in qc["fault_kinds"]
        by_cable += "size_from_cable_deg" in drop
    assert by_cable == len(parts)


@pytest.mark.parametrize(
    "family", ["cable.drifting", "cable.play", "cable_calibration.value", "encoder.gain",
               "encoder.drift", "torque_sensor.drift", "clocks.drift"],
)  # fmt: skip
def test_a_rig_that_departs_elsewhere_locates_no_count_drop(tmp_path, family):
    seed = random_seed(f"cable-no-drop-{family}")
    rng = np.random.default_rng(seed)
    index = next(i for i in range(100) if openworld.draw_case("x", i, np.random.default_rng(
        [seed, i]), [15.0])["fault"] == family)  # fmt: skip
    violations = openworld.draw_case("x", index, rng, [15.0])["violations"]
    while openworld.DROP in violations or family not in violations:
        violations = openworld.draw_case("x", index, rng, [15.0])["violations"]
    print(f"seed {seed}: {violations}")
    parts, _ = _study(tmp_path, seed, violations, 0.8)
    assert not any(p["qc"]["count_drops"] for p in parts)


def _walk(seed: int, drops: dict[float, float], slip: tuple[float, float] = (np.inf, 0.0)):
    """20 s of a knee swinging every 1.1 s at 1 kHz, read three ways: the encoder (whole counts,
    less each drop, {time: size}, from its time on), the cable's brace angle (its own noise, plus
    ``slip`` = (time, size) from that time: a cable that slips, the encoder sound) and where the
    cable is taut (the last 30 % of each stride but its end); the heel strikes' samples."""
    rng = np.random.default_rng(seed)
    t = np.arange(20_000) / 1000.0
    angle = 30.0 + 25.0 * np.sin(2.0 * np.pi * t / 1.1)
    encoder = angle - sum(size * (t >= at) for at, size in drops.items())
    encoder = np.round(encoder / ENCODER_COUNT_DEG) * ENCODER_COUNT_DEG
    cable = angle + 0.05 * rng.standard_normal(t.size) + slip[1] * (t >= slip[0])
    phase = ((t - 0.3) / 1.1) % 1.0
    strikes = np.flatnonzero(np.diff(np.floor((t - 0.3) / 1.1), prepend=-1.0) > 0)[1:]
    return t, encoder, cable, (phase > 0.65) & (phase < 0.95), strikes


@pytest.mark.parametrize("where", ["first", "middle", "last"])
def test_the_cable_finds_a_drop_between_any_two_whole_strides(where):
    seed = random_seed(f"cable-stride-{where}")
    rng = np.random.default_rng(seed)
    # whole stride k runs from 0.3 + 1.1·(k + 1) s, k = 0 … 15; the drop falls between the taut
    # samples of strides k − 1 and k (k = 1: the first that has one before it; 15: the last)
    stride = {"first": 1, "middle": 8, "last": 15}[where]
    at = float(0.3 + 1.1 * (stride + 1) + 1.1 * rng.uniform(-0.04, 0.64))
    size = float(rng.uniform(2.0, 6.0))
    t, encoder, cable, held, strikes = _walk(seed, {at: size})
    found = triangulation.cable_drops(t, encoder, cable, held, strikes, BLOCK["analysis"], [])
    assert len(found) == 1, found
    assert abs(found[0]["time_s"] - at) <= 0.0015
    assert abs(-found[0]["size_deg"] - size) <= 2 * ENCODER_COUNT_DEG


def test_a_drop_beside_one_already_found_is_found_on_the_corrected_encoder():
    seed = random_seed("cable-beside-known")
    rng = np.random.default_rng(seed)
    first, second = 6.5 + rng.uniform(0.0, 1.0), 8.7 + rng.uniform(0.0, 1.0)
    big, small = float(rng.uniform(8.0, 10.0)), float(rng.uniform(2.0, 3.0))
    t, encoder, cable, held, strikes = _walk(seed, {first: big, second: small})
    # the big drop was found by motion capture and is taken out of the encoder
    corrected = encoder + big * (t >= t[np.searchsorted(t, first)])
    known = [float(t[np.searchsorted(t, first)])]
    found = triangulation.cable_drops(t, corrected, cable, held, strikes, BLOCK["analysis"], known)
    assert [round(d["time_s"], 2) for d in found] == [round(second, 2)]
    assert abs(-found[0]["size_deg"] - small) <= 2 * ENCODER_COUNT_DEG


def test_a_cable_that_slips_with_the_encoder_sound_is_no_count_drop():
    seed = random_seed("cable-slip")
    rng = np.random.default_rng(seed)
    slip = (float(rng.uniform(5.0, 15.0)), float(rng.choice([-1.0, 1.0]) * rng.uniform(3.0, 6.0)))
    t, encoder, cable, held, strikes = _walk(seed, {}, slip)
    # the cable's medians do step by the slip (the search has a step to weigh) ...
    before = np.median((encoder - cable)[held & (t < slip[0])])
    after = np.median((encoder - cable)[held & (t >= slip[0])])
    assert abs(after - before + slip[1]) < 0.2
    # ... but the encoder never jumps: no drop
    assert triangulation.cable_drops(t, encoder, cable, held, strikes, BLOCK["analysis"], []) == []
