"""Digital twin of the emulator experiment: writes docs/rig.md §3 recordings plus truth.

Per sample at 1000 Hz: the anatomical knee angle (:mod:`gait`); the brace angle, which lags it
through the cuffs in proportion to the brace torque, settling with the soft tissue's time
constant (cuff compliance); the encoder reading (quantised, with an optional count drop from
some time on); the real-time controller (velocity estimate, gait events, clutch, spring law,
motor set point, PID, motor); the cable torque from the true motor and brace angles and the
delivered brace torque, changed by transmission friction the calibration does not know, recorded
as the real-time model records it: the load cell (with its noise) through a causal 20 Hz
low-pass (Heer §5.2). A
controller that departs from Table 6.1 holds its clutch a whole number of samples past the peak
extension that should release it (a late release). The loop is compiled (:mod:`twin_loop`) and
written apart from the analysis. Motion capture (vectorised, :func:`motion_capture`) reads the
anatomical angle at 100 Hz through its own zero, gain and clock, with a soft-tissue artefact
that follows the gait phase and white noise. The truth's energy per step is the twin's own sum
(:func:`stored_energy_per_step_J`), not the analysis's.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import pandas as pd
from scipy.signal import lfilter, lfilter_zi

from exobench import atomic
from exobench.emulator import trial_name, twin_files
from exobench.emulator.rig import (
    BRACE_RATE_HZ,
    CLUTCH_ANGLE_DEG,
    HEEL_STRIKE_DEG,
    MANIFEST_COLUMNS,
    MOCAP_RATE_HZ,
    PEAK_FLEXION_DEG,
)
from exobench.emulator.twin import gait, twin_loop
from exobench.plumbing import stamp

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
    effects = cfg["effects"]
    shape = gait.shape_for(cfg["gait"]["shapes"], speed)
    t, anatomical, heel_strikes, phase = gait.trajectory(
        shape, cfg["protocol"]["duration_s"], BRACE_RATE_HZ, cfg["gait"]["variability"], rng
    )
    cuff = _effect(effects, "cuff_compliance", "compliance_deg_per_Nm", 0.0)
    friction = _effect(effects, "transmission_friction", "friction_fraction", 0.0)
    sizes, onsets = count_drops_for(effects, name)
    hold = round(_effect(effects, "clutch_departure", "release_delay_s", 0.0) * BRACE_RATE_HZ)
    dropped = (t[:, None] >= onsets[None, :]) @ sizes  # counts lost by each sample
    # a drop before the trial is absorbed by the transmission calibration's D (seed §5.3) in
    # the set point; the spring law keeps the static-trial zero and sees the drop
    shift = float(sizes[onsets <= 0.0].sum())
    brace, encoder, torque, desired, motor, clutch, event = _loop(
        cfg, anatomical, dropped, shift, stiffness, cuff, friction, hold
    )
    noise = cfg["sensors"]
    load_cell = torque + noise["load_cell_sd_Nm"] * rng.standard_normal(len(t))
    recorded = recorded_torque_Nm(load_cell, cfg["controller"]["torque_filter_Hz"])
    brace_frame = pd.DataFrame(
        {
            "time_s": t,
            "brace_angle_deg": encoder,
            "brace_torque_Nm": recorded,
            "desired_torque_Nm": desired,
            "motor_angle_deg": motor,
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
        # energy the wearer stored in each complete step: −∫ τ dθ_brace while engaged
        "true_energy_per_step_J": stored_energy_per_step_J(
            torque, brace, clutch > 0, np.searchsorted(t, heel_strikes)
        ).tolist(),
        # the same as the files show it: the recorded (filtered) torque over the encoder angle
        # while the controller asked for torque
        "recorded_energy_per_step_J": stored_energy_per_step_J(
            recorded, encoder, desired != 0.0, np.searchsorted(t, heel_strikes)
        ).tolist(),
        # the samples at which the controller flagged Table 5.1's events online
        "controller_event_samples": {
            label: np.flatnonzero(event == code).tolist()
            for label, code in (
                ("peak_flexion", twin_loop.PEAK_FLEXION),
                ("peak_extension", twin_loop.PEAK_EXTENSION),
                ("heel_strike", twin_loop.HEEL_STRIKE),
            )
        },
    }
    return Recording(name, speed, stiffness, brace_frame, mocap, truth)


def stored_energy_per_step_J(torque_Nm, brace_deg, engaged, heel_strike_samples) -> np.ndarray:
    """Work done on the engaged spring in each step between heel strikes, −∫ τ dθ.

    Trapezoids over the sample intervals that begin engaged; strikes are sorted sample indices.
    The twin's own sum, apart from the analysis's.
    """
    work = -0.5 * (torque_Nm[1:] + torque_Nm[:-1]) * np.radians(np.diff(brace_deg))
    step = np.searchsorted(heel_strike_samples, np.arange(work.size), side="right")
    weights = np.where(engaged[:-1], work, 0.0)
    total = np.bincount(step, weights=weights, minlength=len(heel_strike_samples) + 1)
    return total[1 : len(heel_strike_samples)]


def lowpass(cutoff_Hz: float, rate_Hz: float) -> tuple[np.ndarray, np.ndarray]:
    """(b, a) of the controller's 2nd-order Butterworth low-pass (bilinear, prewarped): its
    velocity estimate and its load cell (Heer §5.2).

    K = tan(π·f_c/f_s), n = 1 + √2·K + K²: b = K²·(1, 2, 1)/n, a = (1, 2(K² − 1)/n,
    (1 − √2·K + K²)/n). The twin's own design, apart from the analysis's.
    """
    if not 0.0 < cutoff_Hz < rate_Hz / 2.0:
        raise ValueError(f"low-pass cut-off {cutoff_Hz} Hz: expected in (0, {rate_Hz / 2} Hz)")
    k = np.tan(np.pi * cutoff_Hz / rate_Hz)
    norm = 1.0 + np.sqrt(2.0) * k + k * k
    b = np.array([1.0, 2.0, 1.0]) * k * k / norm
    return b, np.array([1.0, 2.0 * (k * k - 1.0) / norm, (1.0 - np.sqrt(2.0) * k + k * k) / norm])


def recorded_torque_Nm(load_cell_Nm: np.ndarray, cutoff_Hz: float | None) -> np.ndarray:
    """The brace torque as the real-time model records it (Heer §5.2): the load cell through the
    causal low-pass y_i = Σ b_k·x_(i−k) − Σ a_k·y_(i−k), settled on the first sample (the model
    ran before the recording started); unfiltered when ``cutoff_Hz`` is None."""
    if cutoff_Hz is None:
        return load_cell_Nm
    b, a = lowpass(float(cutoff_Hz), BRACE_RATE_HZ)
    return lfilter(b, a, load_cell_Nm, zi=lfilter_zi(b, a) * load_cell_Nm[0])[0]


def _loop(
    cfg: Mapping,
    anatomical: np.ndarray,
    dropped: np.ndarray,
    shift: float,
    stiffness: float,
    cuff: float,
    friction: float,
    hold: int,
) -> tuple[np.ndarray, ...]:
    """:func:`twin_loop.run` with the controller and transmission of ``cfg``.

    Scalars go in as float: a value written as an integer in the config would compile a
    second version.
    """
    ctl, trans = cfg["controller"], cfg["transmission"]
    dt = 1.0 / BRACE_RATE_HZ
    b, a = lowpass(float(ctl["velocity_cutoff_Hz"]), BRACE_RATE_HZ)
    pid = [ctl["pid"][k] for k in ("kp_per_s", "ki_per_s2", "kd", "derivative_filter_N")]
    return twin_loop.run(
        np.ascontiguousarray(anatomical, float),
        np.ascontiguousarray(dropped, float),
        ENCODER_STEP_DEG,
        dt,
        b,
        a,
        np.array([PEAK_FLEXION_DEG, HEEL_STRIKE_DEG, CLUTCH_ANGLE_DEG], float),
        float(cuff),
        float(dt / cfg["effects"]["cuff_compliance"]["time_constant_s"]),
        hold,
        float(stiffness),
        float(ctl["equilibrium_deg"]),
        float(shift),
        float(trans["brace_pulley_radius_m"] / trans["motor_pulley_radius_m"]),
        float(ctl["direction_blend_deg_per_s"]),
        np.array([trans["extension"][k] for k in "BCD"], float),
        np.array([trans["flexion"][k] for k in "BCD"], float),
        np.array(pid, float),
        float(ctl["motor_time_constant_s"]),
        float(friction),
    )


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


def write_recordings(recordings: list[Recording], folder) -> None:
    """Manifest, brace and motion-capture CSVs as docs/rig.md §3 fixes them, truth, stamp."""
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
