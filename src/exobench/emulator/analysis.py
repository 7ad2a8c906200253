"""Per-trial analysis: events, steps, energy per step, encoder cross-check, event accuracy."""

from __future__ import annotations

from collections.abc import Mapping

import numpy as np
import pandas as pd

from exobench.emulator import crosscheck, energy, events
from exobench.emulator.rig import BRACE_RATE_HZ, spring_torque

MATCH_WINDOW_S = 0.3  # a detected heel strike further than this from every true one is unmatched


def analyse(
    trial: str,
    brace: pd.DataFrame,
    mocap: pd.DataFrame,
    stiffness: float,
    settings: Mapping,
) -> tuple[pd.DataFrame, pd.DataFrame, dict]:
    """Per-sample table, per-step table and the trial's quality-control record."""
    t = brace["time_s"].to_numpy()
    angle = brace["brace_angle_deg"].to_numpy()
    torque = brace["brace_torque_Nm"].to_numpy()
    desired = brace["desired_torque_Nm"].to_numpy()
    omega = events.brace_velocity(angle, settings["velocity_cutoff_Hz"])
    found = events.detect(angle, omega)
    anatomical = np.interp(t, mocap["time_s"].to_numpy(), mocap["knee_flexion_deg"].to_numpy())
    torque_at_mocap = np.interp(mocap["time_s"].to_numpy(), t, torque)
    angle_at_mocap = np.interp(mocap["time_s"].to_numpy(), t, angle)
    check = crosscheck.fit(
        mocap["time_s"].to_numpy(),
        angle_at_mocap - mocap["knee_flexion_deg"].to_numpy(),
        torque_at_mocap,
    )
    fault = crosscheck.verdict(check, settings["fault_threshold_deg"], float(t[0]))
    corrected = crosscheck.corrected_angle(t, angle, check, fault)
    equilibrium = settings["equilibrium_deg"]
    channels = {
        "energy_J": (torque, angle),
        "energy_desired_J": (desired, angle),
        "energy_ideal_J": (spring_torque(stiffness, equilibrium, anatomical), anatomical),
        "energy_corrected_J": (spring_torque(stiffness, equilibrium, corrected), corrected),
    }
    hs = found.heel_strike
    steps = pd.DataFrame(
        {
            "trial": trial,
            "step": np.arange(max(len(hs) - 1, 0)),
            "heel_strike_s": t[hs[:-1]] if len(hs) > 1 else np.zeros(0),
            "stride_time_s": np.diff(t[hs]) if len(hs) > 1 else np.zeros(0),
        }
    )
    for column, (tau, theta) in channels.items():
        steps[column] = energy.per_step(energy.interval_energy_J(tau, theta, found.engaged), hs)
    if len(hs) > 1:
        starts = hs[:-1] - hs[0]
        span = slice(hs[0], hs[-1])
        engaged_angle = np.where(found.engaged[span], angle[span], np.inf)
        steps["peak_flexion_deg"] = np.maximum.reduceat(angle[span], starts)
        steps["peak_extension_deg"] = np.minimum.reduceat(engaged_angle, starts)
        steps["peak_extension_deg"] = steps["peak_extension_deg"].replace(np.inf, np.nan)
        steps["engaged_s"] = np.add.reduceat(found.engaged[span], starts) / BRACE_RATE_HZ
    samples = pd.DataFrame(
        {
            "t_s": t,
            "brace_angle_deg": angle,
            "anatomical_angle_deg": anatomical,
            "corrected_angle_deg": corrected,
            "encoder_error_deg": crosscheck.encoder_error(t, check),
            "velocity_deg_per_s": omega,
            "brace_torque_Nm": torque,
            "desired_torque_Nm": desired,
            "engaged": found.engaged,
            "heel_strike": np.isin(np.arange(len(t)), hs),
        }
    )
    qc = {
        "encoder_offset_deg": check["offset_deg"],
        "encoder_step_deg": check["step_deg"],
        "encoder_drift_deg_per_min": check["drift_deg_per_min"],
        "cuff_compliance_deg_per_Nm": check["compliance_deg_per_Nm"],
        "residual_sd_deg": check["residual_sd_deg"],
        **fault,
        "n_steps": len(steps),
        "mean_energy_J": _mean(steps["energy_J"]),
        "mean_energy_corrected_J": _mean(steps["energy_corrected_J"]),
    }
    return samples, steps, qc


def _mean(values: pd.Series) -> float | None:
    return float(values.mean()) if len(values) else None


def event_accuracy(detected_s: np.ndarray, true_s: np.ndarray) -> dict:
    """Heel-strike timing error (detected − true, ms) over the true events inside the detected span.

    True heel strikes before the first or after the last detected one (within the matching
    window) cannot be detected from a recording cut mid-stride and are left out.
    """
    empty = {"n_true": len(true_s), "n_in_span": 0, "n_matched": 0}
    if len(detected_s) == 0:
        return {**empty, "mean_error_ms": None, "mean_abs_error_ms": None, "max_abs_error_ms": None}
    span = (true_s >= detected_s[0] - MATCH_WINDOW_S) & (true_s <= detected_s[-1] + MATCH_WINDOW_S)
    inside = true_s[span]
    nearest = detected_s[np.argmin(np.abs(detected_s[None, :] - inside[:, None]), axis=1)]
    error_ms = 1000.0 * (nearest - inside)
    matched = np.abs(error_ms) <= 1000.0 * MATCH_WINDOW_S
    error_ms = error_ms[matched]
    return {
        "n_true": len(true_s),
        "n_in_span": len(inside),
        "n_matched": int(matched.sum()),
        "mean_error_ms": float(error_ms.mean()) if matched.any() else None,
        "mean_abs_error_ms": float(np.abs(error_ms).mean()) if matched.any() else None,
        "max_abs_error_ms": float(np.abs(error_ms).max()) if matched.any() else None,
    }
