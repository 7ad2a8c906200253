"""Which angle sensor moved between trials: the encoder, the motion capture or the cable.

Three readings of the brace angle meet in every trial with a spring that pulls: the encoder θ_e,
motion capture (mapped onto the encoder by the trial's alignment, whose zero gives the offset
o_em = θ_e − θ_m) and the cable, θ_c = (θ_motor − b_w(τ)) / A where the measured torque τ holds
the cable taut (eqs. 5.6–5.8 solved for the brace angle with the lab's calibration b per
direction, blended by the controller's velocity estimate), whose offset o_ec = θ_e − θ_c is
the median over those samples. Against the session's medians each trial departs by Δ_em and
Δ_ec; the sensor that moved is the one whose two pairings depart together:

- encoder: Δ_em and Δ_ec both beyond the threshold and within it of each other (a count drop
  before the trial);
- motion capture: Δ_em beyond, Δ_ec within (its zero moved: re-zeroed);
- cable: Δ_ec beyond, Δ_em within (its zero-torque stretch D moved: re-tensioned);
- undecided otherwise: Δ_em beyond with no cable reading (no spring, or too little taut time),
  with a calibration redone per trial (a refit of D against the encoder absorbs a drop before
  the trial, so an encoder that moved and a motion capture that moved look alike), or with the
  pairings departing by different amounts (more than one sensor moved).
"""

from __future__ import annotations

from collections.abc import Mapping

import numpy as np

from exobench.emulator.chain.controller import direction_weight

MIN_SESSION_TRIALS = 3  # fewer trials give no session median to depart from
CALIBRATIONS = ("session", "per_trial")


def cable_angle_deg(motor_deg, torque_Nm, omega_deg_per_s, transmission: Mapping,
                    blend_deg_per_s: float) -> np.ndarray:  # fmt: skip
    """The brace angle the cable implies: θ_c = (θ_motor − w·b_ext(τ) − (1 − w)·b_flx(τ)) / A,
    b(τ) = B·τ² + C·τ + D, w eq. (5.8)'s extension weight, A = r_brace / r_motor."""
    ratio = transmission["brace_pulley_radius_m"] / transmission["motor_pulley_radius_m"]
    w = direction_weight(np.asarray(omega_deg_per_s, float), blend_deg_per_s)
    torque_Nm = np.asarray(torque_Nm, float)

    def offset(c):
        return (c["B"] * torque_Nm + c["C"]) * torque_Nm + c["D"]

    blended = w * offset(transmission["extension"]) + (1.0 - w) * offset(transmission["flexion"])
    return (np.asarray(motor_deg, float) - blended) / ratio


def cable_reading(encoder_deg, motor_deg, torque_Nm, omega_deg_per_s, rate_Hz: float,
                  transmission: Mapping, settings: Mapping) -> dict:  # fmt: skip
    """A trial's encoder against the cable: median of θ_e − θ_c over the samples whose torque is
    at least ``taut_torque_Nm`` (None with fewer than ``min_taut_s`` of them)."""
    taut = np.asarray(torque_Nm, float) >= float(settings["taut_torque_Nm"])
    seconds = float(taut.sum()) / rate_Hz
    if seconds < float(settings["min_taut_s"]):
        return {"encoder_minus_cable_deg": None, "taut_s": seconds}
    implied = cable_angle_deg(np.asarray(motor_deg)[taut], np.asarray(torque_Nm)[taut],
                              np.asarray(omega_deg_per_s)[taut], transmission,
                              float(settings["direction_blend_deg_per_s"]))  # fmt: skip
    offset = float(np.median(np.asarray(encoder_deg, float)[taut] - implied))
    return {"encoder_minus_cable_deg": offset, "taut_s": seconds}


def moved(delta_em: float, delta_ec: float | None, threshold_deg: float, calibration: str) -> str:
    """The sensor whose zero moved, from a trial's departures from the session (module
    docstring): "none", "encoder", "mocap", "cable" or "undecided"."""
    em = abs(delta_em) >= threshold_deg
    if delta_ec is None:
        return "undecided" if em else "none"
    ec = abs(delta_ec) >= threshold_deg
    if em and ec:
        return "encoder" if abs(delta_em - delta_ec) < threshold_deg else "undecided"
    if em:
        return "mocap" if calibration == "session" else "undecided"
    return "cable" if ec else "none"


def _median(values) -> float | None:
    values = [v for v in values if v is not None]
    return float(np.median(values)) if len(values) >= MIN_SESSION_TRIALS else None


def session(records: Mapping[str, Mapping], threshold_deg: float, calibration: str) -> dict:
    """Per trial, which sensor's zero moved against the session (:func:`moved`): an encoder
    that moved had a count drop before the trial (a fault from its start); a motion capture,
    cable or undecided trial is no encoder fault. With fewer than ``MIN_SESSION_TRIALS`` trials
    nothing is decided. Returns the updated records, the session's medians and the trials by
    what moved."""
    if calibration not in CALIBRATIONS:
        raise KeyError(f"unknown calibration '{calibration}' (known: {list(CALIBRATIONS)})")
    em = {t: r["alignment"]["encoder_offset_deg"] for t, r in records.items()}
    ec = {t: r.get("cable", {}).get("encoder_minus_cable_deg") for t, r in records.items()}
    checked = len(em) >= MIN_SESSION_TRIALS
    median_em = _median(em.values()) if checked else None
    median_ec = _median(ec.values()) if checked else None
    updated, by = {}, {k: [] for k in ("encoder", "mocap", "cable", "undecided")}
    for trial, record in records.items():
        d_em = em[trial] - median_em if checked else 0.0
        d_ec = ec[trial] - median_ec if ec[trial] is not None and median_ec is not None else None
        which = moved(d_em, d_ec, threshold_deg, calibration) if checked else "none"
        record = {**record, "encoder_offset_deg": d_em,
                  "cable_offset_deg": d_ec, "zero_moved": which}  # fmt: skip
        if which == "encoder":
            record["encoder_fault"] = True
            record["fault_kinds"] = ["drop_before_trial", *record["fault_kinds"]]
            record["fault_time_s"] = record["start_s"]
        if which in by:
            by[which].append(trial)
        updated[trial] = record
    return {"trials": updated, "session_encoder_offset_deg": median_em,
            "session_cable_offset_deg": median_ec, "offset_checked": checked,
            "calibration": calibration, "zero_moved": by}  # fmt: skip
