"""Which angle sensor moved between trials (the encoder, the motion capture or the cable), and
the count drops within a trial that the cable sees below motion capture's noise
(:func:`cable_drops`).

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

from exobench.emulator.chain import crosscheck
from exobench.emulator.chain.controller import cable_offset_deg, direction_weight, pulley_ratio

MIN_SESSION_TRIALS = 3  # fewer trials give no session median to depart from
MIN_STRIDES = 3  # fewer strides with a taut cable give no noise to test a step against
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


def taut(torque_Nm, settings: Mapping) -> np.ndarray:
    """The samples whose measured torque is at least ``taut_torque_Nm`` (the cable taut)."""
    return np.asarray(torque_Nm, float) >= float(settings["taut_torque_Nm"])


def readable(held: np.ndarray, rate_Hz: float, settings: Mapping) -> bool:
    """Whether the cable was taut long enough to read the brace angle: ``min_taut_s``."""
    return float(held.sum()) / rate_Hz >= float(settings["min_taut_s"])


def cable_reading(encoder_deg, implied_deg, held, rate_Hz: float, settings: Mapping) -> dict:
    """A trial's encoder against the cable: median of θ_e − θ_c over the :func:`taut` samples
    ``held`` (None when not :func:`readable`), and how long the cable was taut."""
    seconds = float(held.sum()) / rate_Hz
    if not readable(held, rate_Hz, settings):
        return {"encoder_minus_cable_deg": None, "taut_s": seconds}
    offset = float(np.median(np.asarray(encoder_deg, float)[held] - implied_deg[held]))
    return {"encoder_minus_cable_deg": offset, "taut_s": seconds}


def cable_drops(t, corrected_deg, implied_deg, held, heel_strikes, settings: Mapping,
                known_s) -> list[dict]:  # fmt: skip
    """Count drops within a trial that the cable sees and motion capture missed, on the encoder
    ``corrected_deg`` for the drops found so far (at ``known_s``): steps between whole strides
    (heel strike to heel strike) in the medians m_k of θ_e − θ_c over each one's taut samples
    (``held``), found as the motion-capture search finds its own (:func:`crosscheck.best_step`,
    one stride on either side), at least T (``fault_threshold_deg``) and ``drop_threshold_sd`` ×
    the medians' noise (robust SD of their successive differences / √2); each is a drop where
    the encoder jumps in one sample, between the first taut sample of the stride before and the
    last of the stride after, by T or more and within T/2 of the step, the knee's motion taken
    out, and keeps the shift (:func:`crosscheck.jumps`), away from the drops ``known_s``. Time
    and size from the jump, as the motion-capture search's; beside them the step and the
    threshold it passed. A drop before the first whole stride's taut samples moves every m_k
    alike: none within the trial (the session's reading sees it, before the trial)."""
    threshold = float(settings["fault_threshold_deg"])
    stride = np.searchsorted(t[heel_strikes], t, side="right")
    held = held & (stride > 0) & (stride < len(heel_strikes))  # whole strides only
    ids, first = np.unique(stride[held], return_index=True)
    if ids.size < MIN_STRIDES:
        return []
    samples = np.flatnonzero(held)
    medians = np.array([np.median(p) for p in np.split((corrected_deg - implied_deg)[held],
                                                       first[1:])])  # fmt: skip
    times = np.array([np.mean(x) for x in np.split(t[held], first[1:])])
    ends = samples[np.append(first[1:], samples.size) - 1]  # each stride's last taut sample
    x, onsets = np.ones((ids.size, 1)), []
    while len(onsets) < crosscheck.MAX_DROPS:
        coef = np.linalg.lstsq(x, medians, rcond=None)[0]
        noise = crosscheck.robust_sd(np.diff(medians - x @ coef)) / np.sqrt(2.0)
        floor = max(threshold, float(settings["drop_threshold_sd"]) * noise)
        k, _ = crosscheck.best_step(x, medians, times, floor, onsets, side=0.0)
        if k is None:
            break
        onsets.append(k)
        x = np.column_stack([x, np.arange(ids.size) >= k])
    steps = np.linalg.lstsq(x, medians, rcond=None)[0][1:]
    drops = []
    for k, step in zip(onsets, steps, strict=True):
        at = np.arange(samples[first[k - 1]], ends[k])
        sign = float(np.sign(step))
        sizes, shifts = crosscheck.jumps(corrected_deg, at, sign)
        i = int(np.argmax(sizes))
        time = float(t[at[i] + 1])
        near = any(abs(time - s) < crosscheck.MIN_SIDE_S for s in known_s)
        matched = abs(sizes[i] - abs(step)) <= 0.5 * threshold
        if sizes[i] >= threshold and shifts[i] >= threshold and matched and not near:
            drops.append({"time_s": time, "size_deg": sign * float(sizes[i]),
                          "size_from_cable_deg": float(step),
                          "cable_threshold_deg": float(floor)})  # fmt: skip
    return sorted(drops, key=lambda d: d["time_s"])


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
