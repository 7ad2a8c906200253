"""Digital twin of the emulator experiment: writes RIG.md §3 recordings plus truth.

Per sample at 1000 Hz: the anatomical knee angle (:mod:`gait`); the brace angle, which lags it
through the cuffs in proportion to the brace torque, settling with the soft tissue's time
constant (cuff compliance); the encoder reading
(quantised, with an optional count drop from some time on); the controller of
:mod:`controller` (velocity estimate, gait events, clutch, spring law, motor set point, PID,
motor); the cable torque from the true motor and brace angles and the delivered brace torque,
changed by transmission friction the calibration does not know. A controller that departs from
Table 6.1 holds its clutch a whole number of samples past the peak extension that should
release it (a late release). Motion capture (vectorised,
:func:`motion_capture`) reads the anatomical angle at 100 Hz through its own zero, gain and clock,
with a soft-tissue artefact that follows the gait phase and white noise.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import pandas as pd

from exobench import atomic, stamp
from exobench.emulator import controller, energy, gait, trial_name, twin_files
from exobench.emulator.rig import BRACE_RATE_HZ, MANIFEST_COLUMNS, MOCAP_RATE_HZ, spring_torque

ENCODER_COUNTS_PER_REV = 5000  # 1250 CPR, quadrature
ENCODER_STEP_DEG = 360.0 / ENCODER_COUNTS_PER_REV


@dataclass(frozen=True)
class Recording:
    """One trial: brace CSV columns (1000 Hz), motion capture (100 Hz) and the twin's truth."""

    name: str
    speed_m_per_s: float
    stiffness_Nm_per_rad: float
    brace: pd.DataFrame
    mocap: pd.DataFrame
    truth: dict


def _effect(effects: Mapping, name: str, key: str, default: float) -> float:
    """Parameter of a switchable effect, or the value that makes it absent."""
    effect = effects[name]
    return float(effect[key]) if effect["enabled"] else default


def count_drops_for(effects: Mapping, name: str) -> tuple[np.ndarray, np.ndarray]:
    """Sizes (deg) and onsets (s) of the encoder count drops of trial ``name`` (empty if none).

    ``size_deg`` and ``time_s`` are numbers (one drop) or lists of equal length (several).
    """
    drop = effects["encoder_count_drop"]
    if not drop["enabled"] or name not in drop["trials"]:
        return np.zeros(0), np.zeros(0)
    sizes, times = np.broadcast_arrays(
        np.atleast_1d(np.asarray(drop["size_deg"], float)),
        np.atleast_1d(np.asarray(drop["time_s"], float)),
    )
    return sizes, times


def simulate(
    speed: float, stiffness: float, cfg: Mapping, rng: np.random.Generator, name: str
) -> Recording:
    """Simulate one condition sample by sample; return the files' content and the truth."""
    protocol, ctl, trans, effects = (
        cfg["protocol"],
        cfg["controller"],
        cfg["transmission"],
        cfg["effects"],
    )
    shape = gait.shape_for(cfg["gait"]["shapes"], speed)
    t, anatomical, heel_strikes, phase = gait.trajectory(
        shape, protocol["duration_s"], BRACE_RATE_HZ, cfg["gait"]["variability"], rng
    )
    dt = 1.0 / BRACE_RATE_HZ
    cuff = _effect(effects, "cuff_compliance", "compliance_deg_per_Nm", 0.0)
    cuff_lag = dt / effects["cuff_compliance"]["time_constant_s"]
    friction = _effect(effects, "transmission_friction", "friction_fraction", 0.0)
    sizes, onsets = count_drops_for(effects, name)
    hold = round(_effect(effects, "clutch_departure", "release_delay_s", 0.0) * BRACE_RATE_HZ)
    released = -hold - 1  # the sample at which Table 6.1 last released the clutch (none yet)
    dropped = (t[:, None] >= onsets[None, :]) @ sizes  # counts lost by each sample
    b, a = controller.velocity_filter(ctl["velocity_cutoff_Hz"], BRACE_RATE_HZ)
    blend = ctl["direction_blend_deg_per_s"]
    ratio = trans["brace_pulley_radius_m"] / trans["motor_pulley_radius_m"]
    pid = controller.Pid(**ctl["pid"], dt=dt)
    events = controller.Events()
    n = len(t)
    out = {k: np.zeros(n) for k in ("brace", "encoder", "torque", "desired", "motor", "engaged")}
    raw_1 = raw_2 = omega_1 = omega_2 = 0.0  # velocity filter history (inputs, outputs)
    # a drop before the trial is absorbed by the transmission calibration's D (seed §5.3) in
    # the set point; the spring law keeps the static-trial zero and sees the drop
    set_point_shift = float(sizes[onsets <= 0.0].sum())
    motor = ratio * anatomical[0] + controller.cable_offset_deg(0.0, trans["flexion"])
    motor_rate = 0.0
    torque = 0.0
    cuff_offset = 0.0
    encoder_prev = None
    brace_prev = anatomical[0]
    for i in range(n):
        cuff_offset += cuff_lag * (cuff * torque - cuff_offset)
        brace = anatomical[i] + cuff_offset
        encoder = ENCODER_STEP_DEG * np.floor(brace / ENCODER_STEP_DEG) - dropped[i]
        raw = 0.0 if encoder_prev is None else (encoder - encoder_prev) / dt
        omega = b[0] * raw + b[1] * raw_1 + b[2] * raw_2 - a[1] * omega_1 - a[2] * omega_2
        was_engaged = events.engaged
        controller.update_events(events, encoder, omega, omega_1)
        raw_2, raw_1, omega_2, omega_1 = raw_1, raw, omega_1, omega
        if was_engaged and not events.engaged:
            released = i
        clutch = events.engaged or i < released + hold
        desired = float(spring_torque(stiffness, ctl["equilibrium_deg"], encoder)) * clutch
        target = float(
            controller.set_point_deg(encoder + set_point_shift, desired, omega, trans, blend)
        )
        motor_rate += dt / ctl["motor_time_constant_s"] * (pid(target - motor) - motor_rate)
        motor += motor_rate * dt
        true_rate = (brace - brace_prev) / dt
        w = float(controller.direction_weight(true_rate, blend))
        offset = motor - ratio * brace
        cable = w * float(controller.cable_torque_Nm(offset, trans["extension"])) + (
            1.0 - w
        ) * float(controller.cable_torque_Nm(offset, trans["flexion"]))
        torque = cable * (1.0 + friction * (2.0 * w - 1.0))
        out["brace"][i], out["encoder"][i], out["torque"][i] = brace, encoder, torque
        out["desired"][i], out["motor"][i], out["engaged"][i] = desired, motor, clutch
        encoder_prev, brace_prev = encoder, brace
    noise = cfg["sensors"]
    brace_frame = pd.DataFrame(
        {
            "time_s": t,
            "brace_angle_deg": out["encoder"],
            "brace_torque_Nm": out["torque"] + noise["load_cell_sd_Nm"] * rng.standard_normal(n),
            "desired_torque_Nm": out["desired"],
            "motor_angle_deg": out["motor"],
        }
    )
    mocap, alignment = motion_capture(t, anatomical, phase, effects, noise, rng)
    truth = {
        "heel_strikes_s": heel_strikes.tolist(),
        "encoder_count_drop_deg": float(sizes.sum()),
        "encoder_count_drops_deg": sizes.tolist(),
        "encoder_fault_times_s": onsets.tolist(),
        "cuff_compliance_deg_per_Nm": cuff,
        "transmission_friction_fraction": friction,
        "clutch_release_delay_s": hold / BRACE_RATE_HZ,
        **alignment,
        "true_energy_per_step_J": _true_energy(t, heel_strikes, out),
    }
    return Recording(name, speed, stiffness, brace_frame, mocap, truth)


def motion_capture(
    t: np.ndarray,
    anatomical: np.ndarray,
    phase: np.ndarray,
    effects: Mapping,
    sensors: Mapping,
    rng: np.random.Generator,
) -> tuple[pd.DataFrame, dict]:
    """Motion capture at 100 Hz and its truth: zero + gain·(θ_anat + artefact)(t − clock) + noise.

    The soft-tissue artefact is A·sin(2π·h·φ) of the gait phase φ (h-th harmonic of the cycle):
    skin markers slide over the bones in step with the gait, not as white noise. The clock
    offset δ means the frame stamped s shows the knee at s − δ.
    """
    zero = _effect(effects, "mocap_alignment", "zero_deg", 0.0)
    gain = _effect(effects, "mocap_alignment", "gain", 1.0)
    clock = _effect(effects, "mocap_alignment", "clock_offset_s", 0.0)
    artefact = effects["soft_tissue_artefact"]
    amplitude = _effect(effects, "soft_tissue_artefact", "amplitude_deg", 0.0)
    seen = anatomical + amplitude * np.sin(2.0 * np.pi * artefact["harmonic"] * phase)
    stamps = t[:: round(BRACE_RATE_HZ / MOCAP_RATE_HZ)]
    knee = zero + gain * np.interp(stamps - clock, t, seen)
    frame = pd.DataFrame(
        {
            "time_s": stamps,
            "knee_flexion_deg": knee + sensors["mocap_sd_deg"] * rng.standard_normal(len(stamps)),
        }
    )
    truth = {
        "mocap_zero_deg": zero,
        "mocap_gain": gain,
        "mocap_clock_offset_s": clock,
        "soft_tissue_artefact_deg": amplitude,
    }
    return frame, truth


def _true_energy(t: np.ndarray, heel_strikes: np.ndarray, out: Mapping) -> list[float]:
    """Energy the wearer stored in each complete step: −∫ τ dθ_brace while engaged."""
    stored = energy.interval_energy_J(out["torque"], out["brace"], out["engaged"] > 0)
    return energy.per_step(stored, np.searchsorted(t, heel_strikes)).tolist()


def write_recordings(recordings: list[Recording], folder) -> None:
    """Manifest, brace and motion-capture CSVs as RIG.md §3 fixes them, truth, stamp."""
    folder = Path(folder)
    rows = []
    for rec in recordings:
        brace_file, mocap_file = f"{rec.name}_brace.csv", f"{rec.name}_mocap.csv"
        atomic.write_text(folder / brace_file, _csv(rec.brace))
        atomic.write_text(folder / mocap_file, _csv(rec.mocap))
        atomic.write_json(folder / "truth" / f"{rec.name}.json", rec.truth)
        rows.append(
            (rec.name, brace_file, mocap_file, rec.speed_m_per_s, rec.stiffness_Nm_per_rad, "right")
        )
    manifest = pd.DataFrame(rows, columns=list(MANIFEST_COLUMNS))
    atomic.write_text(folder / "manifest.csv", _csv(manifest))
    stamp.write_stamp(folder, twin_files([r.name for r in recordings]))


def _csv(frame: pd.DataFrame) -> str:
    """CSV text with floats to 6 decimals; a frame of finite floats only is formatted a row at a
    time (the text pandas writes, in about a quarter of its time)."""
    plain = all(isinstance(t, np.dtype) and t.kind == "f" for t in frame.dtypes)
    named = all(isinstance(c, str) and not set(c) & set(',"\n') for c in frame.columns)
    values = frame.to_numpy()
    if not (plain and named) or not np.isfinite(values).all():
        return frame.to_csv(index=False, lineterminator="\n", float_format="%.6f")
    row = ",".join(["%.6f"] * frame.shape[1])
    lines = [",".join(frame.columns), *(row % r for r in map(tuple, values.tolist()))]
    return "\n".join(lines) + "\n"


def run(cfg: Mapping, seed: int) -> list[Recording]:
    """Every condition of the protocol, in order, each with its own random stream."""
    protocol = cfg["protocol"]
    recordings = []
    for i, speed in enumerate(protocol["speeds_m_per_s"]):
        for j, stiffness in enumerate(protocol["stiffnesses_Nm_per_rad"]):
            rng = np.random.default_rng([seed, i, j])
            name = trial_name(speed, stiffness)
            recordings.append(simulate(speed, stiffness, cfg, rng, name))
    return recordings
