"""Direct checks of the emulator's assumptions: what the recordings show before any fit.

Rows of docs/emulator_assumptions.md that need no model, and the quality checks the chain already
makes, each as one row of :mod:`exobench.selection.checks`:
- the controller against Table 6.1: the share of steps whose recorded spring activity runs past
  Table 6.1's (a late release) or stops short of it (a late engagement);
- the encoder: the count drops the QC located, and its resolution (one count of 5000 per turn);
- the gait events: the heel strikes against the twin's own (when the run has its truth), with
  what makes them late;
- encoder against motion capture while the spring is inactive: the part of their difference
  (after the QC's alignment) locked to the gait, which no noise has;
- the brace torque while the spring is inactive against the cable model's zero;
- the clock: a SYNC or trigger channel (docs/rig.md §3 has none), the brace's sample interval
  and motion capture's frame interval;
- the channels' noise against their datasheets;
- zeros that must hold from one trial to the next: motion capture's and the torque sensor's,
  each trial's 95 % interval against the session's median (a compliance or a gain between
  trials is the engine's parameter stability: a direct estimate per trial is confounded).
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence

import numpy as np
import pandas as pd

from exobench.emulator.chain import controller, crosscheck
from exobench.emulator.model import assumptions, discrepancy
from exobench.emulator.model.effects import ENCODER_COUNT_DEG
from exobench.emulator.rig import BRACE_RATE_HZ, sample_rate_Hz
from exobench.selection import checks as shared
from exobench.selection.checks import row, stated

DOC = "docs/emulator_assumptions.md"


def steps_of(samples: pd.DataFrame) -> np.ndarray:
    """Each sample's step (heel strike to heel strike; −1 before the first, the last step's
    number after the last)."""
    hs = np.flatnonzero(samples["heel_strike"].to_numpy())
    return np.searchsorted(hs, np.arange(len(samples)), side="right") - 1


def per_step(samples: pd.DataFrame, values: np.ndarray, keep: np.ndarray, how: str = "mean"):
    """The mean (or sum) of ``values`` over the kept samples of every complete step (a mean of
    none kept: NaN)."""
    step = steps_of(samples)
    count = max(int(step.max()), 0) if step.size else 0
    inside = keep & (step >= 0) & (step < count)
    sums = np.bincount(step[inside], values[inside], count)
    if how == "sum":
        return sums
    counts = np.bincount(step[inside], minlength=count).astype(float)
    return np.where(counts > 0, sums / np.maximum(counts, 1.0), np.nan)


def table61(parts: Sequence[Mapping], tolerance_s: float, share: float) -> list[dict]:
    """Per step, whether the recorded spring activity runs past Table 6.1's (more than
    ``tolerance_s`` of samples active where Table 6.1 has the clutch released: a late release)
    or starts after it (as long inactive where Table 6.1 has it engaged: a late engagement);
    the share of steps, against none."""
    late: dict[str, list] = {"clutch_release": [], "clutch_engage": []}
    for part in parts:
        s = part["samples"]
        active, expected = s["active"].to_numpy(bool), s["table61_active"].to_numpy(bool)
        every = np.ones(len(s), bool)
        for key, differs in (("clutch_release", active & ~expected),
                             ("clutch_engage", expected & ~active)):  # fmt: skip
            counts = per_step(s, differs.astype(float), every, "sum")
            late[key].append((counts > tolerance_s * BRACE_RATE_HZ).astype(float))
    words = {
        "clutch_release": "steps whose recorded spring activity runs past Table 6.1's",
        "clutch_engage": "steps whose recorded spring activity starts after Table 6.1's",
    }
    return [row(key, "table61", words[key], np.concatenate(values), 0.0, share, "1")
            for key, values in late.items()]  # fmt: skip


def count_drops(parts: Sequence[Mapping]) -> list[dict]:
    """The count drops the QC located (during a trial, or before it where the session's three
    angle readings place the move in the encoder): the encoder counts every increment, so any is
    a violation; a trial whose readings cannot say which sensor moved before it leaves the row
    undecided when nothing else is found."""
    found, open_ = [], []
    for part in parts:
        qc = part["qc"]
        if "drop_before_trial" in qc.get("fault_kinds", []):
            size = -qc.get("encoder_moved_deg", qc["encoder_offset_deg"])
            found.append(f"{part['trial']}: {size:+.2f}° before the trial")
        elif "undecided" in qc.get("zero_moved", ()):
            open_.append(f"{part['trial']} (encoder − motion capture "
                         f"{qc['encoder_offset_deg']:+.2f}° from the session's)")  # fmt: skip
        found += [f"{part['trial']}: {d['size_deg']:+.2f}° at {d['time_s']:.2f} s"
                  for d in qc["count_drops"]]  # fmt: skip
    detail = ("counts lost (encoder reads the knee more extended from then on): " + "; ".join(
        found)) if found else "no count lost in any trial"  # fmt: skip
    if open_:
        detail += ("; undecided where encoder and motion capture moved apart and the cable "
                   "cannot say which of them moved (no cable reading, or more than one sensor "
                   "moved): " + "; ".join(open_))  # fmt: skip
    verdict = "violated" if found else "undecided" if open_ else "holds"
    return [stated("encoder", "count_drops", "count drops the QC located", float(len(found)),
                   0.0, 0.0, "1", len(parts), verdict, detail)]  # fmt: skip


def resolution(parts: Sequence[Mapping], tolerance_deg: float) -> list[dict]:
    """The encoder's smallest step in every trial against one count (360° / 5000)."""
    counts = [discrepancy.encoder_count_deg(p["samples"]["brace_angle_deg"].to_numpy())
              for p in parts]  # fmt: skip
    return [row("encoder_resolution", "noise_levels", "the encoder's smallest step",
                np.array(counts), ENCODER_COUNT_DEG, tolerance_deg, "deg")]  # fmt: skip


def noise_levels(parts: Sequence[Mapping], sensors: Mapping, share: float,
                 torque_filter_Hz: float | None) -> list[dict]:  # fmt: skip
    """Each channel's noise per trial against its datasheet (``share`` of it either way): motion
    capture's from the second differences of its frames, the torque sensor's from those of the
    1 kHz torque (robust SD / √6: the knee's and the torque's own curvature is far smaller); the
    load cell's noise passes the real-time model's low-pass, which scales what the second
    differences see by ‖Δ²h‖/√6, h its impulse response (:func:`filtered_noise_gain`)."""
    mocap, torque = [], []
    for part in parts:
        s = part["samples"]
        frames = s["mocap_angle_deg"].to_numpy()[s["mocap_frame"].to_numpy(bool)]
        mocap.append(crosscheck.robust_sd(np.diff(frames, 2)) / np.sqrt(6.0))
        curvature = np.diff(s["brace_torque_Nm"].to_numpy(), 2)
        torque.append(crosscheck.robust_sd(curvature) / np.sqrt(6.0))
    sd_mocap = float(sensors["mocap_sd_deg"])
    sd_torque = float(sensors["load_cell_sd_Nm"]) * filtered_noise_gain(torque_filter_Hz)
    return [row("encoder_resolution", "noise_levels", "motion capture's frame noise (SD)",
                np.array(mocap), sd_mocap, share * sd_mocap, "deg"),
            row("torque_linearity", "noise_levels",
                "the torque sensor's noise (SD) as the recording's second differences show it",
                np.array(torque), sd_torque, share * sd_torque, "N·m")]  # fmt: skip


def filtered_noise_gain(cutoff_Hz: float | None, rate_Hz: float = 1000.0) -> float:
    """What the second-difference estimator (robust SD of Δ²x / √6) reads of unit white noise
    through the real-time model's low-pass: ‖Δ²h‖/√6 (1 without the filter)."""
    impulse = np.zeros(int(rate_Hz))
    impulse[8] = 1.0  # after a few zeros: the filter settles on zero
    response = controller.recorded_torque_Nm(impulse, cutoff_Hz, rate_Hz)
    return float(np.linalg.norm(np.diff(response, 2)) / np.sqrt(6.0))


def inactive_apart(part: Mapping) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Encoder against the aligned motion capture (count drops removed), the gait phase and the
    samples where the spring is inactive within complete steps."""
    s = part["samples"]
    t = s["t_s"].to_numpy()
    hs = np.flatnonzero(s["heel_strike"].to_numpy())
    phase = crosscheck.gait_phase(t, t[hs])
    apart = (s["brace_angle_deg"] - s["anatomical_angle_deg"] - s["encoder_error_deg"]).to_numpy()
    index = np.arange(len(s))
    keep = ~s["active"].to_numpy(bool) & (index >= hs[0]) & (index < hs[-1])
    return apart, phase, keep


def gait_locked(parts: Sequence[Mapping], tolerance_deg: float) -> list[dict]:
    """Encoder against motion capture while the spring is inactive (no cuff load): per trial,
    the RMS of the part of their difference locked to the gait (harmonics 1–4 of its cycle),
    against none; which harmonic carries most is said."""
    sizes, strongest = [], []
    for part in parts:
        apart, phase, keep = inactive_apart(part)
        coef = crosscheck.gait_locked(phase, apart, keep)
        locked = (crosscheck.locked_design(phase[keep]) @ coef) - coef[0]
        sizes.append(float(np.sqrt(np.mean(locked**2))))
        k = crosscheck.PHASE_HARMONICS
        strongest.append(int(np.argmax(np.hypot(coef[1 : 1 + k], coef[1 + k :]))) + 1)
    harmonic = int(np.bincount(strongest).argmax())
    detail = (f"the two part in step with the gait, most at harmonic {harmonic} of its cycle: a "
              "soft-tissue artefact of motion capture, a hinge off the knee's axis or play in "
              "the cuffs")  # fmt: skip
    out = row(
        "mocap",
        "encoder_vs_mocap",
        "encoder against motion capture, spring inactive: RMS of the part locked to the gait",
        np.array(sizes),
        0.0,
        tolerance_deg,
        "deg",
    )
    if out["decision"] == "violated":
        out["detail"] = detail
    return [out]


def torque_zero(parts: Sequence[Mapping], transmission: Mapping, blend: float,
                tolerance_Nm: float) -> tuple[list[dict], dict]:  # fmt: skip
    """The brace torque while the spring is inactive against the torque the cable model gives
    at the recorded motor and encoder angles (its zero: the motor holds the cable unloaded), per
    step; and each trial's steps (for the check between trials). A trial the QC found a count
    drop before is left out: the cable's stretch there rests on the drop's size, which only a
    fit gives."""
    trials = {}
    for part in undropped(parts):
        s = part["samples"]
        rate = np.gradient(
            discrepancy.smooth(s["brace_angle_deg"].to_numpy(), discrepancy.RATE_CUTOFF_HZ),
            1.0 / BRACE_RATE_HZ,
        )
        model = discrepancy.transmission_Nm(s, rate, transmission, blend)
        apart = s["brace_torque_Nm"].to_numpy() - model
        trials[part["trial"]] = per_step(s, apart, ~s["active"].to_numpy(bool))
    values = np.concatenate(list(trials.values())) if trials else np.zeros(0)
    return [row("torque_sensor", "torque_zero", "brace torque, spring inactive, less the cable "
                "model's", values, 0.0, tolerance_Nm, "N·m")], trials  # fmt: skip


def undropped(parts: Sequence[Mapping]) -> list[Mapping]:
    """The trials whose encoder the session's readings place no count drop before, nor leave
    undecided (:mod:`triangulation`)."""
    return [p for p in parts if "drop_before_trial" not in p["qc"].get("fault_kinds", [])
            and "undecided" not in p["qc"].get("zero_moved", ())]  # fmt: skip


def timing(parts: Sequence[Mapping], tolerance_ms: float) -> list[dict]:
    """The clock: no SYNC or trigger channel in the files (undecided), the brace's sample
    interval and motion capture's frame interval per trial (largest departure from 1 ms and
    from the frames' own interval, 10 ms at 100 Hz)."""
    brace, mocap = [], []
    for part in parts:
        s = part["samples"]
        brace.append(np.max(np.abs(np.diff(s["t_s"].to_numpy()) * 1e3 - 1e3 / BRACE_RATE_HZ)))
        frames = s["t_s"].to_numpy()[s["mocap_frame"].to_numpy(bool)]
        mocap.append(np.max(np.abs(np.diff(frames) * 1e3 - 1e3 / sample_rate_Hz(frames))))
    sync = stated("clocks", "sync", "clock offset from a SYNC or trigger channel", np.nan, 0.0,
                  0.0, "s", 0, "undecided",
                  "the files carry no SYNC or trigger channel (docs/rig.md §3): the clock offset "
                  "rests on the motion-capture alignment alone")  # fmt: skip
    return [sync,
            row("loop", "loop_rate", "brace sample interval, largest departure from 1 ms",
                np.array(brace), 0.0, tolerance_ms, "ms"),
            row("clocks", "loop_rate", "motion-capture frame interval, largest departure from "
                "its own (10 ms at 100 Hz; at the brace's 1 ms)", np.array(mocap), 0.0,
                tolerance_ms + 1.0, "ms")]  # fmt: skip


def heel_strikes(parts: Sequence[Mapping], cutoff_Hz: float, tolerance_ms: float) -> list[dict]:
    """The heel strikes found against the twin's own (its truth; without one, undecided), per
    trial, with what makes them late: Table 5.1's rule runs on the controller's causal velocity
    estimate (a 2nd-order Butterworth, group delay √2/(2π·f_c) at low frequencies), so it fires
    that much after the knee turns at peak extension, measured here as the encoder's lowest
    angle (zero-phase) before each heel strike found."""
    errors = [
        p["qc"]["gait_event_accuracy"]["mean_error_ms"]
        for p in parts
        if (p["qc"].get("gait_event_accuracy") or {}).get("mean_error_ms") is not None
    ]
    if not errors:
        return [stated("gait_events", "heel_strikes", "heel strikes found, against the gait's",
                       np.nan, 0.0, tolerance_ms, "ms", 0, "undecided",
                       "the recordings hold no true gait events to compare with")]  # fmt: skip
    after = []
    for part in parts:
        s = part["samples"]
        angle = discrepancy.smooth(s["brace_angle_deg"].to_numpy(), discrepancy.RATE_CUTOFF_HZ)
        for h in np.flatnonzero(s["heel_strike"].to_numpy())[1:]:
            before = slice(max(h - round(0.2 * BRACE_RATE_HZ), 0), h + 1)
            after.append(1e3 * (h - before.start - np.argmin(angle[before])) / BRACE_RATE_HZ)
    delay = 1e3 * np.sqrt(2.0) / (2.0 * np.pi * cutoff_Hz)
    out = row("gait_events", "heel_strikes", "heel strikes found minus the gait's (mean per "
              "trial)", np.array(errors), 0.0, tolerance_ms, "ms")  # fmt: skip
    late = float(np.mean(errors))
    out["detail"] = (
        f"found {late:.0f} ms {'late' if late > 0 else 'early'} on average: Table 5.1's rule "
        f"runs on the controller's causal {cutoff_Hz:g} Hz velocity estimate ({delay:.1f} ms "
        f"group delay) and fires {np.median(after):.0f} ms after the knee turns at peak "
        f"extension; the gait's heel strike follows that turn by {np.median(after) - late:.0f} "
        "ms"
    )  # fmt: skip
    return [out]


def between(parts: Sequence[Mapping], zeros: Mapping[str, np.ndarray],
            tolerances: Mapping) -> list[dict]:  # fmt: skip
    """Zeros that must hold from one trial to the next, each trial's 95 % interval against the
    session's median (a departure beyond the tolerance names the trials): motion capture's zero
    from the QC's alignment, the torque sensor's zero from the inactive torque (Student's t over
    the steps); trials the QC found a count drop before, or left undecided, are left out
    (:func:`undropped`). The trials whose motion capture or cable reading the session's three
    readings place a move in (:mod:`triangulation`) are named in the rows of motion capture's
    and the torque sensor's zero, the first violated where any moved."""
    alignment = {p["trial"]: p["qc"]["alignment"] for p in undropped(parts)}
    mocap = {t: (a["mocap_zero_deg"], a["mocap_zero_ci95_deg"]) for t, a in alignment.items()}
    torque = {t: (shared.interval(v)[0], list(shared.interval(v)[1:])) for t, v in zeros.items()}
    zero_deg, zero_Nm = (float(tolerances[k]) for k in ("zero_between_deg",
                                                          "torque_zero_between_Nm"))  # fmt: skip
    mocap_row = departures("mocap_zero_between", "motion capture's zero, trial against the "
                           "session", mocap, "deg", zero_deg)  # fmt: skip
    torque_row = departures("torque_zero_between", "the torque sensor's zero, trial against "
                            "the session", torque, "N·m", zero_Nm)  # fmt: skip
    for out, sensor, words in (
        (mocap_row, "mocap", "motion capture re-zeroed before {} (it moved against the cable)"),
        (torque_row, "cable", "the cable's reading of the brace angle moved before {} (the "
                              "cable's zero-torque stretch D or the torque sensor's zero)"),
    ):  # fmt: skip
        trials = [p["trial"] for p in parts if sensor in p["qc"].get("zero_moved", ())]
        if trials:
            out["detail"] = "; ".join(d for d in (out["detail"], words.format(", ".join(trials)))
                                      if d)  # fmt: skip
            if sensor == "mocap":
                out["decision"] = "violated"
    return [mocap_row, torque_row]


def departures(key: str, quantity: str, values: Mapping[str, tuple], unit: str,
               tolerance: float) -> dict:  # fmt: skip
    """One constant between trials: the largest distance of a trial's 95 % interval from the
    session's median, violated beyond ``tolerance`` (naming the trials), holds within it."""
    if len(values) < 2:
        return stated(key, "stability", quantity, np.nan, 0.0, tolerance, unit, len(values),
                      "undecided", "fewer than two trials to compare")  # fmt: skip
    median = float(np.median([v for v, _ in values.values()]))
    gaps = {t: max(ci[0] - median, median - ci[1], 0.0) for t, (_, ci) in values.items()}
    apart = [f"{t} ({values[t][0]:.3g} against {median:.3g})" for t, g in gaps.items()
             if g > tolerance]  # fmt: skip
    detail = ("trials apart from the session: " + "; ".join(apart)) if apart else ""
    if apart and alike_causes(key):
        detail += f"; {alike_causes(key)}: this check cannot tell which"
    return stated(key, "stability", quantity + " (largest gap of a 95 % interval)",
                  max(gaps.values()), 0.0, tolerance, unit, len(values),
                  "violated" if apart else "holds", detail)  # fmt: skip


def alike_causes(key: str) -> str:
    """A row's change between trials and those of the rows its check cannot tell it from, in
    words ("the torque sensor's zero … or the cable's zero-torque stretch D … changed between
    trials … or torque-sensor lag reading the trials apart"); empty for a row without such rows."""
    rows, terms = {r.key: r for r in assumptions.TABLE}, assumptions.relaxations()

    def cause(k):  # a between row's change, or a channel's own fault reading the trials apart
        if k in terms:
            return f"{terms[k][0].name(terms[k][1])} reading the trials apart"
        return rows[k].relaxations[0].name

    return " or ".join(cause(k) for k in (key, *rows[key].alike)) if rows[key].alike else ""


def checks(parts: Sequence[Mapping], settings: Mapping) -> pd.DataFrame:
    """Every direct check of the recordings, one row each (:data:`shared.COLUMNS`). ``parts``:
    per trial its name, stiffness, per-sample table and QC record (qc.json); ``settings``: the
    tolerances (``emulator.checks``), the sensors' datasheet, the transmission, the controller's
    velocity cut-off and direction blend and Table 6.1's activity tolerance. The brace must be
    at 1000 Hz (:func:`discrepancy.require_1kHz`); motion capture may run at its own rate."""
    for part in parts:
        discrepancy.require_1kHz(part["trial"], part["samples"])
    tol = settings["checks"]
    torque, zeros = torque_zero(parts, settings["transmission"],
                                settings["direction_blend_deg_per_s"],
                                float(tol["torque_zero_tolerance_Nm"]))  # fmt: skip
    rows = [
        *table61(parts, float(settings["activity_tolerance_s"]), float(tol["table61_share"])),
        *count_drops(parts),
        *heel_strikes(parts, float(settings["velocity_cutoff_Hz"]),
                      float(tol["heel_strike_tolerance_ms"])),
        *gait_locked(parts, float(tol["locked_tolerance_deg"])),
        *torque,
        *timing(parts, float(tol["interval_tolerance_ms"])),
        *resolution(parts, float(tol["resolution_tolerance_deg"])),
        *noise_levels(parts, settings["sensors"], float(tol["noise_share"]),
                      settings["torque_filter_Hz"]),
        *between(parts, zeros, tol),
    ]  # fmt: skip
    return shared.frame(rows)


# What each check sees (assumption, check -> the relaxations, term keys of the table, a
# violation of it may be); the others see what no model holds (named by the check itself).
SEES = {
    ("clutch_release", "table61"): ("clutch_release.delay",),
    ("clutch_engage", "table61"): ("clutch_engage.delay",),
    ("encoder", "count_drops"): ("encoder.step",),
    ("mocap", "encoder_vs_mocap"): ("mocap.harmonic", "hinge.offset", "cuff.play"),
    ("torque_sensor", "torque_zero"): ("torque_sensor.offset", "cable_calibration.offset"),
}


def seen(table: pd.DataFrame) -> dict[tuple[str, str], tuple[str, ...]]:
    """The violated checks that see relaxations a model can hold, with those relaxations."""
    broken = table[table["decision"] == "violated"]
    keys = zip(broken["assumption"], broken["check"], strict=True)
    return {key: SEES[key] for key in keys if key in SEES}


def suspects(table: pd.DataFrame) -> list[str]:
    """The library terms a violated check sees: the engine weighs them as other readings of
    what it claims (:func:`exobench.selection.discovery.readings`)."""
    registry = assumptions.registry_terms()
    return list(dict.fromkeys(t for terms in seen(table).values() for t in terms
                              if t not in registry))  # fmt: skip


def unaccounted_rows(table: pd.DataFrame, report: Mapping) -> dict:
    """The violated checks that see relaxations nothing in the engine's model holds (no effect
    selected, term named or other reading of them): (assumption, check) → those relaxations."""
    registry = assumptions.registry_terms()
    held = {*report["selected"], *(t["term"] for t in report["discovery"]["named"]),
            *(r["term"] for r in report.get("readings", []))}  # fmt: skip
    return {key: terms for key, terms in seen(table).items()
            if not any(registry.get(t, t) in held for t in terms)}  # fmt: skip


def unaccounted(table: pd.DataFrame, report: Mapping) -> list[str]:
    """What a violated check sees that nothing in the engine's model holds
    (:func:`unaccounted_rows`), in words, for "Left unexplained"."""
    out = []
    for (assumption, check), terms in unaccounted_rows(table, report).items():
        entry = table[(table["assumption"] == assumption) & (table["check"] == check)].iloc[0]
        names = " or ".join(assumptions.relaxations()[t][0].name(assumptions.relaxations()[t][1])
                            for t in terms)  # fmt: skip
        out.append(f"{entry['quantity']} is {entry['measured']:.3g} {entry['unit']} against "
                   f"{entry['expected']:.3g} ± {entry['tolerance']:.3g} ({check}); the model holds "
                   f"no {names}")  # fmt: skip
    return out


def markdown(table: pd.DataFrame) -> list[str]:
    """The checks as a section of summary.md (the assumptions: docs/emulator_assumptions.md)."""
    return shared.markdown(table, DOC)
