"""Which angle sensor moved between trials (issue 54, item 3): the encoder, motion capture and the
brace angle the cable implies. The generator's re-zeroed motion capture is drawn from a printed
seed and read only in the final assertions."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest

from emulator_helpers import DEFAULT, random_seed
from exobench.emulator.chain import triangulation
from exobench.emulator.model import checks
from exobench.emulator.validation import labsim, openworld

BLOCK = DEFAULT["emulator"]
THRESHOLD = BLOCK["analysis"]["fault_threshold_deg"]


@pytest.mark.parametrize(
    ("delta_em", "delta_ec", "calibration", "which"),
    [
        (-5.0, -5.2, "session", "encoder"),  # both pairings of the encoder depart alike
        (-5.0, -5.2, "per_trial", "encoder"),
        (2.0, 0.1, "session", "mocap"),  # the encoder agrees with the cable
        (2.0, 0.1, "per_trial", "undecided"),  # a refit D may have absorbed a drop
        (0.2, 2.0, "session", "cable"),  # encoder and motion capture agree
        (2.0, None, "session", "undecided"),  # no cable reading: two readings cannot tell
        (-4.0, 2.0, "session", "undecided"),  # both depart, differently: more than one moved
        (0.3, None, "session", "none"),
        (0.3, -0.2, "session", "none"),
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


def _rezeroed_lab(tmp_path: Path, calibration: str, name: str):
    """A lab whose motion capture is re-zeroed before every trial (its zero drawn by the
    generator), calibrated as ``calibration`` says: the chain's parts, the direct checks and the
    zeros the generator drew."""
    seed = random_seed(name)
    reading = labsim.Reading(mocap_rezeroed=True, calibration=calibration)
    manifest = labsim.write_study(tmp_path, speeds_m_per_s=[0.8, 1.2],
                                  stiffnesses_Nm_per_rad=[2.0, 3.5], duration_s=12.0,
                                  violations={}, seed=seed, reading=reading)  # fmt: skip
    cfg = openworld.settings(BLOCK, 12.0, reading.lab_config())
    parts = openworld.chain_parts(manifest, cfg, seed)
    table = checks.checks(parts, openworld.check_settings(cfg)).set_index("assumption")
    truth = {p["trial"]: json.loads((tmp_path / "truth" / f"{p['trial']}.json").read_text())
             for p in parts}  # fmt: skip
    zeros = {t: r["reading_drawn"]["mocap_zero_deg"] for t, r in truth.items()}
    return parts, table, zeros


@pytest.mark.parametrize("index", range(2))
def test_a_re_zeroed_motion_capture_with_a_session_calibration_is_named_not_the_encoder(
    tmp_path, index
):
    parts, table, zeros = _rezeroed_lab(tmp_path, "session", f"rezeroed-session-{index}")
    moved = {p["trial"]: p["qc"]["zero_moved"] for p in parts}
    assert not any("drop_before_trial" in p["qc"]["fault_kinds"] for p in parts)
    assert table.loc["encoder", "decision"] == "holds"
    assert set(moved.values()) <= {"none", "mocap"}
    # the trials whose drawn zero lies well apart from the session's are named, in the row of
    # motion capture's zero and in the session QC
    middle = np.median(list(zeros.values()))
    apart = [t for t, z in zeros.items() if abs(z - middle) >= THRESHOLD + 0.5]
    assert all(moved[t] == "mocap" for t in apart)
    detail = table.loc["mocap_zero_between", "detail"]
    assert table.loc["mocap_zero_between", "decision"] == "violated"
    named = [t for t, m in moved.items() if m == "mocap"]
    assert all(t in detail.split("re-zeroed before", 1)[1] for t in named)


def test_with_a_calibration_redone_per_trial_the_ambiguity_is_named_and_no_fault_called(
    tmp_path,
):
    parts, table, zeros = _rezeroed_lab(tmp_path, "per_trial", "rezeroed-per-trial")
    moved = {p["trial"]: p["qc"]["zero_moved"] for p in parts}
    assert not any(p["qc"]["encoder_fault"] for p in parts)
    assert set(moved.values()) <= {"none", "undecided"}
    undecided = [t for t, m in moved.items() if m == "undecided"]
    row = table.loc["encoder"]
    assert row["decision"] == ("undecided" if undecided else "holds")
    assert all(t in row["detail"] for t in undecided)
    middle = np.median(list(zeros.values()))
    assert all(moved[t] == "undecided" for t, z in zeros.items()
               if abs(z - middle) >= THRESHOLD + 0.5)  # fmt: skip
