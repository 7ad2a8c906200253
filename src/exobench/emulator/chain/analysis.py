"""Per-trial analysis: events, steps, energy per step, encoder cross-check, event accuracy."""

from __future__ import annotations

from collections.abc import Mapping

import numpy as np
import pandas as pd

from exobench.emulator.chain import activity, crosscheck, energy, events, gaps, triangulation
from exobench.emulator.rig import sample_rate_Hz, spring_torque

# dimensionless flags and labels the tables' unit suffixes do not cover
SAMPLE_UNITS = {
    "active": "1",
    "table61_active": "1",
    "mocap_frame": "1",
    "clutch_window": "1",
}
STEP_UNITS = {"correction": "1"}


def analyse(
    trial: str,
    brace: pd.DataFrame,
    mocap: pd.DataFrame,
    stiffness: float,
    settings: Mapping,
) -> tuple[pd.DataFrame, pd.DataFrame, dict]:
    """Per-sample, per-step tables and QC; U = −∫τ dθ_corrected over two windows per step.

    Everything runs at the brace's own rate (its time stamps' median step) and reads motion
    capture at its own frames. Brace gaps (NaN) are bridged for the filters and their steps
    left out of the steps table, with the reason in the QC; motion-capture gaps are left out of
    the alignment fit."""
    recorded, (brace, gap) = brace, gaps.bridge(brace)
    t = brace["time_s"].to_numpy()
    rate = sample_rate_Hz(t)
    angle = brace["brace_angle_deg"].to_numpy()
    torque = brace["brace_torque_Nm"].to_numpy()
    desired = brace["desired_torque_Nm"].to_numpy()
    flag = brace["clutch_engaged"].to_numpy() if "clutch_engaged" in brace else None
    omega = events.brace_velocity(angle, settings["velocity_cutoff_Hz"], rate)
    found = events.detect(angle, omega)
    hs = found.heel_strike
    equilibrium = settings["equilibrium_deg"]
    active = activity.recorded(desired, flag)
    window = activity.clutch_window(found.engaged, flag)
    expected = activity.table61(
        found.engaged, spring_torque(stiffness, equilibrium, angle), flag is not None
    )
    disagree, table61_check = activity.crosscheck(
        active, expected, hs, round(settings["activity_tolerance_s"] * rate)
    )
    knee = mocap["knee_flexion_deg"].to_numpy()
    seen = np.isfinite(knee)
    stamps, knee = mocap["time_s"].to_numpy()[seen], knee[seen]
    motor = brace["motor_angle_deg"].to_numpy()
    blend = float(settings["direction_blend_deg_per_s"])
    implied = triangulation.cable_angle_deg(motor, torque, omega, settings["transmission"], blend)
    held = triangulation.taut(torque, settings)
    masked = np.where(gaps.in_gap(t, gap, stamps), np.nan, knee)
    check = _crosscheck(t, angle, torque, hs, stamps, masked, implied, held, rate, settings)
    anatomical = crosscheck.encoder_frame(t, stamps, knee, check)
    error = crosscheck.encoder_error(t, check)
    corrected = angle - error
    channels = {
        "energy_J": (torque, corrected, active),
        "energy_active_J": (torque, corrected, window),
        "energy_uncorrected_J": (torque, angle, active),
        "energy_desired_J": (desired, corrected, active),
        "energy_ideal_J": (
            spring_torque(stiffness, equilibrium, anatomical),
            anatomical,
            found.engaged,
        ),
    }
    steps = pd.DataFrame(
        {
            "trial": trial,
            "step": np.arange(max(len(hs) - 1, 0)),
            "heel_strike_s": t[hs[:-1]] if len(hs) > 1 else np.zeros(0),
            "stride_time_s": np.diff(t[hs]) if len(hs) > 1 else np.zeros(0),
        }
    )
    for column, (tau, theta, on) in channels.items():
        steps[column] = energy.per_step(energy.interval_energy_J(tau, theta, on), hs)
    steps["table61_disagreement_s"] = disagree / rate
    drop_times = np.array([d["time_s"] for d in check["count_drops"]])
    drop_sizes = np.array([d["size_deg"] for d in check["count_drops"]])
    in_step = np.searchsorted(t[hs], drop_times, side="right") - 1 if len(hs) else drop_times
    inside = (in_step >= 0) & (in_step < len(steps))
    steps["encoder_drop_deg"] = np.bincount(
        in_step[inside].astype(int), drop_sizes[inside], len(steps)
    )
    steps["correction"] = [
        f"count drop of {d:+.2f}° removed from the encoder angle" if d else ""
        for d in steps["encoder_drop_deg"]
    ]
    if len(hs) > 1:
        starts = hs[:-1] - hs[0]
        span = slice(hs[0], hs[-1])
        active_angle = np.where(active[span], corrected[span], np.inf)
        steps["peak_flexion_deg"] = np.maximum.reduceat(corrected[span], starts)
        steps["peak_extension_deg"] = np.minimum.reduceat(active_angle, starts)
        steps["peak_extension_deg"] = steps["peak_extension_deg"].replace(np.inf, np.nan)
        steps["active_s"] = np.add.reduceat(active[span], starts) / rate
        steps["engage_pct"], steps["release_pct"] = activity.window_phases(window, hs)
    samples = pd.DataFrame(
        {
            "t_s": t,
            "brace_angle_deg": angle,
            "anatomical_angle_deg": anatomical,
            "mocap_angle_deg": np.interp(t, stamps, knee),
            # the brace samples nearest each motion-capture frame (between them: interpolated)
            "mocap_frame": np.isin(np.arange(len(t)), _nearest(t, stamps)),
            "corrected_angle_deg": corrected,
            "encoder_error_deg": error,
            "velocity_deg_per_s": omega,
            "brace_torque_Nm": torque,
            "desired_torque_Nm": desired,
            "motor_angle_deg": motor,
            "active": active,
            "engaged": found.engaged,
            "clutch_window": window,
            "table61_active": expected,
            "heel_strike": np.isin(np.arange(len(t)), hs),
        }
    )
    excluded = gaps.excluded_steps(recorded, hs)
    if excluded:
        steps = steps[~steps["step"].isin([e["step"] for e in excluded])].reset_index(drop=True)
    qc = {
        "alignment": {k: v for k, v in check.items() if k != "count_drops"},
        "count_drops": check["count_drops"],
        **crosscheck.bounded(check),
        "start_s": float(t[0]),
        **crosscheck.verdict(check),
        "activity_source": "clutch_engaged" if flag is not None else "desired_torque_Nm != 0",
        "clutch_window_source": (
            "clutch_engaged" if flag is not None else "Table 6.1 rebuilt offline from the encoder"
        ),
        "table61_crosscheck": table61_check,
        "cable": triangulation.cable_reading(corrected, implied, held, rate, settings),
        "n_steps": len(steps),
        "n_steps_corrected": int((steps["encoder_drop_deg"] != 0).sum()),
        "mean_energy_J": _mean(steps["energy_J"]),
        "mean_energy_uncorrected_J": _mean(steps["energy_uncorrected_J"]),
        "mean_energy_active_J": _mean(steps["energy_active_J"]),
        # only where a brace gap excluded steps: the default QC keeps its keys
        **({"excluded_steps": excluded} if excluded else {}),
    }
    return samples, steps, qc


def _crosscheck(t, angle, torque, hs, stamps, knee, implied, held, rate, settings) -> dict:
    """Encoder against motion capture (:func:`crosscheck.fit`), then against the cable where it
    is taut (``held``): a count drop the cable sees and motion capture missed (below its noise)
    is removed before motion capture is aligned again, and listed with the others."""
    args = (stamps, knee, t)
    rest = (torque, t[hs], settings["drop_threshold_sd"], settings["artefact_alpha"])
    check = crosscheck.fit(*args, angle, *rest)
    if not triangulation.readable(held, rate, settings):
        return check
    known = [d["time_s"] for d in check["count_drops"]]
    corrected = angle - crosscheck.encoder_error(t, check)
    seen = triangulation.cable_drops(t, corrected, implied, held, hs, settings, known)
    if not seen:
        return check
    check = crosscheck.fit(*args, angle - crosscheck.encoder_error(t, {"count_drops": seen}), *rest)
    # a drop the cable found is the cable's: motion capture's fit may step near it again
    apart = crosscheck.MIN_SIDE_S
    own = [d for d in check["count_drops"]
           if all(abs(d["time_s"] - c["time_s"]) >= apart for c in seen)]  # fmt: skip
    return {**check, "count_drops": sorted([*own, *seen], key=lambda d: d["time_s"])}


def _nearest(t: np.ndarray, stamps: np.ndarray) -> np.ndarray:
    """Index of the sample of ``t`` nearest each stamp inside t's span."""
    i = np.clip(np.searchsorted(t, stamps), 1, len(t) - 1)
    i = np.where(np.abs(t[i - 1] - stamps) <= np.abs(t[i] - stamps), i - 1, i)
    return i[(stamps >= t[0]) & (stamps <= t[-1])]


def _mean(values: pd.Series) -> float | None:
    return float(values.mean()) if len(values) else None


def event_accuracy(detected_s: np.ndarray, true_s: np.ndarray, match_window_s: float) -> dict:
    """Timing error detected − true (ms) of true strikes in span, matched within match_window_s."""
    empty = {"n_true": len(true_s), "n_in_span": 0, "n_matched": 0}
    if len(detected_s) == 0:
        return {**empty, "mean_error_ms": None, "mean_abs_error_ms": None, "max_abs_error_ms": None}
    span = (true_s >= detected_s[0] - match_window_s) & (true_s <= detected_s[-1] + match_window_s)
    inside = true_s[span]
    nearest = detected_s[np.argmin(np.abs(detected_s[None, :] - inside[:, None]), axis=1)]
    error_ms = 1000.0 * (nearest - inside)
    matched = np.abs(error_ms) <= 1000.0 * match_window_s
    error_ms = error_ms[matched]
    return {
        "n_true": len(true_s),
        "n_in_span": len(inside),
        "n_matched": int(matched.sum()),
        "mean_error_ms": float(error_ms.mean()) if matched.any() else None,
        "mean_abs_error_ms": float(np.abs(error_ms).mean()) if matched.any() else None,
        "max_abs_error_ms": float(np.abs(error_ms).max()) if matched.any() else None,
    }
