"""Which angle sensor moved between trials: the encoder, the motion capture or the cable.

Three readings of the brace angle meet in every trial with a spring that pulls: the encoder θ_e,
motion capture (mapped onto the encoder by the trial's alignment, whose zero gives the offset
o_em = θ_e − θ_m) and the cable, θ_c = (θ_motor − b_w(τ)) / A where the measured torque τ holds
the cable taut (eqs. 5.6–5.8 solved for the brace angle with the lab's calibration b per
direction, blended by the controller's velocity estimate), whose offset o_ec = θ_e − θ_c is
the median over those samples. θ_c rests on the motor's own angle and the stated calibration, so
a refit of the controller's D (Heer §5.3) moves the motor's set point, not this reading. Each
trial departs by Δ_em from the session's median and by Δ_ec from the cable readings of the trials
whose encoder agrees with motion capture (:func:`cable_reference`; threshold T):

- a calibration that holds for the session makes the cable the reference: the encoder moved by
  e = Δ_ec and motion capture by m = Δ_ec − Δ_em, each named when it reaches T (the encoder's
  only when negative: counts lost, the encoder reads the knee more extended; a positive e is the
  session's median carried by dropped trials, undecided), both in one trial if both did; where
  encoder and motion capture agree (|Δ_em| < T/2) but the cable reading moved, the cable did (its
  zero-torque stretch D, or the torque sensor's zero, which moves θ_c by C/A per N·m); a Δ_em of
  T or more that neither move reaches T for is read by the rule below;
- a calibration redone per trial lets the cable change between trials, so one sensor is named
  where Δ_ec fits its hypothesis within T/2: the encoder (Δ_ec ≈ Δ_em, negative) or motion
  capture (Δ_ec ≈ 0); otherwise, and wherever a trial has no cable reading (no spring, or too
  little taut time), |Δ_em| ≥ T is undecided between the two.
"""

from __future__ import annotations

from collections.abc import Mapping

import numpy as np

from exobench.emulator.chain.controller import cable_offset_deg, direction_weight, pulley_ratio

MIN_SESSION_TRIALS = 3  # fewer trials give no session median to depart from
CALIBRATIONS = ("session", "per_trial")


def cable_angle_deg(motor_deg, torque_Nm, omega_deg_per_s, transmission: Mapping,
                    blend_deg_per_s: float) -> np.ndarray:  # fmt: skip
    """The brace angle the cable implies: θ_c = (θ_motor − w·b_ext(τ) − (1 − w)·b_flx(τ)) / A,
    b(τ) = B·τ² + C·τ + D, w eq. (5.8)'s extension weight, A = r_brace / r_motor."""
    w = direction_weight(np.asarray(omega_deg_per_s, float), blend_deg_per_s)
    torque_Nm = np.asarray(torque_Nm, float)
    blended = w * cable_offset_deg(torque_Nm, transmission["extension"]) + (
        1.0 - w
    ) * cable_offset_deg(torque_Nm, transmission["flexion"])
    return (np.asarray(motor_deg, float) - blended) / pulley_ratio(transmission)


def cable_reading(encoder_deg, motor_deg, torque_Nm, omega_deg_per_s, rate_Hz: float,
                  settings: Mapping) -> dict:  # fmt: skip
    """A trial's encoder against the cable: median of θ_e − θ_c over the samples whose torque is
    at least ``taut_torque_Nm`` (None with fewer than ``min_taut_s`` of them), the calibration
    ``settings["transmission"]``'s."""
    taut = np.asarray(torque_Nm, float) >= float(settings["taut_torque_Nm"])
    seconds = float(taut.sum()) / rate_Hz
    if seconds < float(settings["min_taut_s"]):
        return {"encoder_minus_cable_deg": None, "taut_s": seconds}
    implied = cable_angle_deg(np.asarray(motor_deg)[taut], np.asarray(torque_Nm)[taut],
                              np.asarray(omega_deg_per_s)[taut], settings["transmission"],
                              float(settings["direction_blend_deg_per_s"]))  # fmt: skip
    offset = float(np.median(np.asarray(encoder_deg, float)[taut] - implied))
    return {"encoder_minus_cable_deg": offset, "taut_s": seconds}


def moved(delta_em: float, delta_ec: float | None, threshold_deg: float,
          calibration: str) -> tuple[str, ...]:  # fmt: skip
    """The sensors whose zero moved, from a trial's departures from the session (module
    docstring): some of "encoder", "mocap", "cable", or ("undecided",); () when none did."""
    em, near = abs(delta_em) >= threshold_deg, 0.5 * threshold_deg
    if delta_ec is None:
        return ("undecided",) if em else ()
    if calibration == "session":
        if abs(delta_em) < near and abs(delta_ec) >= threshold_deg:
            return ("cable",)  # encoder and motion capture agree: the cable moved
        if delta_ec >= threshold_deg:
            return ("undecided",)  # an encoder reading high: not a drop
        named = ("encoder",) if delta_ec <= -threshold_deg else ()
        named += ("mocap",) if abs(delta_ec - delta_em) >= threshold_deg else ()
        if named:
            return named
    return nearer(delta_em, delta_ec, near) if em else ()


def nearer(delta_em: float, delta_ec: float, near: float) -> tuple[str, ...]:
    """The one sensor whose hypothesis the cable reading fits within ``near``: the encoder
    (Δ_ec ≈ Δ_em, reading low) or motion capture (Δ_ec ≈ 0); else ("undecided",)."""
    if abs(delta_ec - delta_em) < near and delta_em < 0.0:
        return ("encoder",)
    return ("mocap",) if abs(delta_ec) < near else ("undecided",)


def _median(values) -> float | None:
    """The median of the values given (None left out); None for fewer than
    ``MIN_SESSION_TRIALS``."""
    values = [v for v in values if v is not None]
    return float(np.median(values)) if len(values) >= MIN_SESSION_TRIALS else None


def cable_reference(em: Mapping[str, float], ec: Mapping[str, float | None], median_em: float,
                    threshold_deg: float) -> float | None:  # fmt: skip
    """The session's encoder − cable: the median over the cable readings of the trials whose
    encoder agrees with motion capture (|Δ_em| < T), else over every cable reading when there are
    ``MIN_SESSION_TRIALS``; None otherwise (the cable cannot decide)."""
    agreeing = [
        c for t, c in ec.items() if c is not None and abs(em[t] - median_em) < threshold_deg
    ]
    return float(np.median(agreeing)) if agreeing else _median(ec.values())


def session(records: Mapping[str, Mapping], threshold_deg: float, calibration: str) -> dict:
    """Per trial, which sensors' zeros moved against the session (:func:`moved`): an encoder
    that moved had a count drop before the trial (a fault from its start, of its size); motion
    capture, the cable or an undecided trial is no encoder fault. With fewer than
    ``MIN_SESSION_TRIALS`` trials nothing is decided. Returns the updated records, the session's
    medians and the trials by what moved."""
    if calibration not in CALIBRATIONS:
        raise KeyError(f"unknown calibration '{calibration}' (known: {list(CALIBRATIONS)})")
    em = {t: r["alignment"]["encoder_offset_deg"] for t, r in records.items()}
    ec = {t: r.get("cable", {}).get("encoder_minus_cable_deg") for t, r in records.items()}
    median_em, median_ec = _median(em.values()), _median(ec.values())
    checked = median_em is not None
    reference = cable_reference(em, ec, median_em, threshold_deg) if checked else None
    updated, by = {}, {k: [] for k in ("encoder", "mocap", "cable", "undecided")}
    for trial, record in records.items():
        d_em = em[trial] - median_em if checked else 0.0
        d_ec = ec[trial] - reference if ec[trial] is not None and reference is not None else None
        which = moved(d_em, d_ec, threshold_deg, calibration) if checked else ()
        record = {**record, "encoder_offset_deg": d_em,
                  "cable_offset_deg": d_ec, "zero_moved": list(which)}  # fmt: skip
        if "encoder" in which:  # its size: against the cable where that is the reference
            record["encoder_moved_deg"] = d_ec if calibration == "session" else d_em
            record["encoder_fault"] = True
            record["fault_kinds"] = ["drop_before_trial", *record["fault_kinds"]]
            record["fault_time_s"] = record["start_s"]
        for sensor in which:
            by[sensor].append(trial)
        updated[trial] = record
    return {"trials": updated, "session_encoder_offset_deg": median_em,
            "session_cable_offset_deg": median_ec, "offset_checked": checked,
            "calibration": calibration, "zero_moved": by}  # fmt: skip
