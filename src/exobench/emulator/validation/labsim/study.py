"""Simulated trials (one per speed and stiffness) and the files a lab would write: the brace and
motion-capture CSVs, manifest.csv and, beside them, each trial's truth."""

from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import NamedTuple

import numpy as np

from .cable import calibration_vector, real_cable
from .controller import HEEL_STRIKE, PEAK_EXTENSION, PEAK_FLEXION, controller_vector, run_loop
from .cuffs import hinge_angle, real_cuffs
from .files import write_trial_files
from .gait import treadmill_gait
from .reading import NOMINAL, Reading, trial_reading
from .rig import (
    BETWEEN,
    CUFF_TIME_CONSTANT_S,
    DROP_WINDOW,
    FS,
    FS_MOCAP,
    SIDE,
    VIOLATIONS,
    WARMUP_S,
    Z_MAX,
    check_duration,
    checked_violations,
    value_of,
)
from .sensors import encoder_vector, mocap_channel, torque_channel


class RigState(NamedTuple):
    """The rig's true signals over the recording at 1 kHz: knee and brace (deg), the motor pulley
    (deg), the delivered torque (N·m), the controller's velocity estimate (°/s), its Table 5.1
    events (controller.PEAK_FLEXION, …) and its clutch."""

    knee_deg: np.ndarray
    brace_deg: np.ndarray
    motor_deg: np.ndarray
    torque_Nm: np.ndarray
    rate_deg_per_s: np.ndarray
    events: np.ndarray
    engaged: np.ndarray


# The constant a between-trial violation re-sets, by key (a compliance: the session's × 1 + s·z).
BETWEEN_CONSTANTS = {
    "straps_between.between": "compliance_deg_per_Nm",
    "mocap_zero_between.between": "zero_deg",
    "torque_zero_between.between": "offset_Nm",
    "cable_tension_between.between": "offset_deg",
}


class Trial(NamedTuple):
    """One trial: the brace file's and the motion-capture file's columns (rows × columns, in the
    contract's order), its truth (written beside the files) and the rig's true signals."""

    name: str
    speed_m_per_s: float
    stiffness_Nm_per_rad: float
    brace: np.ndarray
    mocap: np.ndarray
    truth: dict
    state: RigState


class Draws(NamedTuple):
    """What the law leaves open, drawn per study unless given: the tissue's time constant (s), the
    artefact's harmonic and phase (rad)."""

    cuff_time_constant_s: float
    artefact: tuple[int, float]


def trial_name(speed_m_per_s: float, stiffness_Nm_per_rad: float) -> str:
    """v<speed × 10>_k<stiffness × 10>: v08_k35 walks at 0.8 m/s against 3.5 N·m/rad."""
    return f"v{round(10 * speed_m_per_s):02d}_k{round(10 * stiffness_Nm_per_rad):02d}"


def study_draws(
    violations: Mapping[str, Mapping[str, float]],
    rng: np.random.Generator,
    cuff_time_constant_s: float | None,
    artefact: tuple[int, float] | None,
) -> Draws:
    """T ~ U(5, 50 ms) with cuff.elastic, (k, ψ) ~ (U{1, 2, 3}, U[0, 2π)) with mocap.harmonic."""
    if cuff_time_constant_s is None:
        cuff_time_constant_s = 0.02
        if "cuff.elastic" in violations:
            cuff_time_constant_s = float(rng.uniform(*CUFF_TIME_CONSTANT_S))
    if not cuff_time_constant_s > 0.0:
        raise ValueError(f"the cuffs' time constant must be > 0 s, got {cuff_time_constant_s}")
    if artefact is None:
        artefact = (2, 0.0)
        if "mocap.harmonic" in violations:
            artefact = (int(rng.integers(1, 4)), float(rng.uniform(0.0, 2 * np.pi)))
    if artefact[0] not in (1, 2, 3):
        raise ValueError(f"the artefact's harmonic is 1, 2 or 3, got {artefact[0]}")
    return Draws(float(cuff_time_constant_s), (int(artefact[0]), float(artefact[1])))


def trial_draws(
    violations: Mapping[str, Mapping[str, float]],
    rng: np.random.Generator,
    duration_s: float,
    drop_time_s: float | None,
    z: Mapping[str, float],
) -> dict[str, dict[str, float]]:
    """Trial i's drawn values: the count drop's instant, z_i and the constant it re-sets."""
    drawn = {}
    if "encoder.step" in violations:
        if drop_time_s is None:
            drop_time_s = float(rng.uniform(*DROP_WINDOW) * duration_s)
        if not 0.0 <= drop_time_s < duration_s:
            raise ValueError(f"the count drop's instant must lie in [0, {duration_s}) s")
        drawn["encoder.step"] = {"time_s": float(drop_time_s)}
    for key in BETWEEN:
        if key not in violations:
            continue
        z_i = z[key] if key in z else _truncated_normal(rng)
        spread = value_of(violations, key, 0.0)
        if key == "straps_between.between":  # a compliance cannot fall below zero (rigid cuffs)
            factor = max(0.0, 1.0 + spread * z_i)
            drawn[key] = {
                "z": z_i,
                BETWEEN_CONSTANTS[key]: value_of(violations, "cuff.elastic", 0.0) * factor,
            }
        else:
            drawn[key] = {"z": z_i, BETWEEN_CONSTANTS[key]: spread * z_i}
    if "clutch_engage.event" in violations:  # which loading peaks engage: one uniform a peak
        drawn["clutch_engage.event"] = {"seed": int(rng.integers(2**32))}
    return drawn


def loading_peaks(drawn: Mapping[str, Mapping], share: float, samples: int) -> np.ndarray:
    """Whether the k-th peak flexion Table 6.1 does not arm (at or below 40°, the knee past 40°
    before) engages the clutch: u_k < w, u_k uniform from the trial's drawn seed."""
    if share <= 0.0:
        return np.zeros(samples, dtype=np.bool_)
    seed = int(drawn["clutch_engage.event"]["seed"])
    return np.random.default_rng(seed).uniform(size=samples) < share


def _truncated_normal(rng: np.random.Generator) -> float:
    """A standard normal draw within ±Z_MAX (drawn again beyond)."""
    z = float(rng.standard_normal())
    return z if abs(z) <= Z_MAX else _truncated_normal(rng)


def _between_value(drawn: Mapping[str, Mapping[str, float]], key: str) -> float:
    """The trial's re-set constant of a between-trial violation, 0 without it."""
    return float(drawn[key][BETWEEN_CONSTANTS[key]]) if key in drawn else 0.0


def simulate_trial(
    name: str,
    speed_m_per_s: float,
    stiffness_Nm_per_rad: float,
    duration_s: float,
    violations: Mapping[str, Mapping[str, float]],
    draws: Draws,
    drawn: Mapping[str, Mapping[str, float]],
    gait_rng: np.random.Generator,
    noise: tuple[float, float],
    noise_rng: np.random.Generator,
    reading: Reading,
    reading_drawn: Mapping,
) -> Trial:
    """One trial: the walker's gait, the closed loop from the warm-up on, the channels and noise,
    as the lab reads them (reading_drawn: the reading's draws for the trial, trial_reading's)."""
    samples, frames = round(duration_s * FS), round(duration_s * FS_MOCAP)
    t = (np.arange(samples + round(WARMUP_S * FS)) - round(WARMUP_S * FS)) / FS
    gait = treadmill_gait(speed_m_per_s, t[0], duration_s, gait_rng)
    knee = gait.knee(t)
    compliance = value_of(violations, "cuff.elastic", 0.0)
    if "straps_between.between" in drawn:
        compliance = _between_value(drawn, "straps_between.between")
    drop_at = drawn["encoder.step"]["time_s"] if "encoder.step" in drawn else np.inf
    # the lab's calibration: its controller's and its real cable's (each trial's when redone)
    calibration = calibration_vector(reading_drawn.get("transmission", reading.transmission()))
    tension = _between_value(drawn, "cable_tension_between.between")
    loop = run_loop(
        hinge_angle(knee, value_of(violations, "hinge.offset", 0.0)),
        t,
        controller_vector(stiffness_Nm_per_rad, violations, reading),
        calibration,
        encoder_vector(violations, drop_at, reading.encoder_counts_per_turn),
        real_cable(violations, tension, calibration, reading.friction_bias_Nm),
        real_cuffs(violations, compliance, draws.cuff_time_constant_s),
        value_of(violations, "clutch_release.event", 0.0),
        loading_peaks(drawn, value_of(violations, "clutch_engage.event", 0.0), t.size),
    )
    zero_Nm = _between_value(drawn, "torque_zero_between.between")
    recorded = slice(t.size - samples, None)
    # the load cell's own noise enters before the real-time model's low-pass
    sensor_noise = noise[0] * noise_rng.standard_normal(t.size)
    torque = torque_channel(
        loop.torque, t, violations, zero_Nm, sensor_noise, reading.torque_filter_Hz
    )[recorded]
    zero_deg = _between_value(drawn, "mocap_zero_between.between")
    zero_deg += reading_drawn.get("mocap_zero_deg", 0.0)
    knee_seen = mocap_channel(gait, frames, violations, zero_deg, draws.artefact)
    knee_seen += noise[1] * noise_rng.standard_normal(frames)
    time = t[recorded]
    brace = np.column_stack(
        [time, loop.encoder[recorded], torque, loop.desired[recorded], loop.motor_reading[recorded]]
    )
    mocap = np.column_stack([np.arange(frames) / FS_MOCAP, knee_seen])
    truth = {
        "trial": name,
        "speed_m_per_s": float(speed_m_per_s),
        "stiffness_Nm_per_rad": float(stiffness_Nm_per_rad),
        "side": SIDE,
        "duration_s": float(duration_s),
        "noise": {"torque_sd_Nm": float(noise[0]), "mocap_sd_deg": float(noise[1])},
        "violations": {key: dict(params) for key, params in violations.items()},
        "drawn": {key: dict(values) for key, values in drawn.items()},
        "heel_strikes_s": [float(h) for h in gait.heel_strikes if 0.0 <= h < duration_s],
        **controller_events(time, loop.events[recorded], loop.engaged[recorded]),
    }
    state = RigState(
        knee[recorded],
        loop.brace[recorded],
        loop.motor[recorded],
        loop.torque[recorded],
        loop.rate[recorded],
        loop.events[recorded],
        loop.engaged[recorded],
    )
    return Trial(
        name, float(speed_m_per_s), float(stiffness_Nm_per_rad), brace, mocap, truth, state
    )


def controller_events(time: np.ndarray, events: np.ndarray, engaged: np.ndarray) -> dict:
    """The controller's Table 5.1 events and Table 6.1 engagements ([on, off), s) in the record."""
    edges = np.diff(engaged.astype(int), prepend=0, append=0)
    on, off = np.flatnonzero(edges == 1), np.flatnonzero(edges == -1)
    ends = np.append(time, time[-1] + 1.0 / FS)  # an engagement open at the end closes there
    return {
        "controller": {
            "peak_flexions_s": time[events == PEAK_FLEXION].tolist(),
            "peak_extensions_s": time[events == PEAK_EXTENSION].tolist(),
            "heel_strikes_s": time[events == HEEL_STRIKE].tolist(),
            "engaged_s": [[float(ends[a]), float(ends[b])] for a, b in zip(on, off, strict=True)],
        }
    }


def simulate_study(
    *,
    speeds_m_per_s: Sequence[float],
    stiffnesses_Nm_per_rad: Sequence[float],
    duration_s: float,
    violations: Mapping[str, Mapping[str, float]],
    seed: int,
    torque_noise_Nm: float | None = None,
    mocap_noise_deg: float | None = None,
    drop_time_s: float | None = None,
    cuff_time_constant_s: float | None = None,
    artefact: tuple[int, float] | None = None,
    between_z: Mapping[str, Sequence[float]] | None = None,
    reading: Reading | None = None,
) -> list[Trial]:
    """The trials write_study writes (every speed × every stiffness, in that order), as arrays.

    What a law leaves open is drawn from the seed unless given: the count drop's instant per trial
    (drop_time_s), the tissue's time constant (cuff_time_constant_s), the artefact's harmonic and
    phase (artefact), each between-trial violation's z_i (between_z: key → one z per trial);
    every drawn value is in the trial's truth. The lab reads the thesis as reading says (NOMINAL
    when None); its noise levels unless torque_noise_Nm or mocap_noise_deg is given. A given
    reading is in each trial's truth ("reading"), with the trial's own draws ("reading_drawn").
    """
    violations = checked_violations(violations)
    if not duration_s > 0.0:
        raise ValueError(f"duration_s must be > 0, got {duration_s}")
    check_duration(violations, duration_s)
    lab = NOMINAL if reading is None else reading
    if not isinstance(lab, Reading):
        raise ValueError(f"reading must be a Reading, got {reading!r}")
    if torque_noise_Nm is None:
        torque_noise_Nm = lab.load_cell_sd_Nm
    if mocap_noise_deg is None:
        mocap_noise_deg = lab.mocap_sd_deg
    if min(torque_noise_Nm, mocap_noise_deg) < 0.0:
        raise ValueError("noise levels must be ≥ 0")
    conditions = [(v, k) for v in speeds_m_per_s for k in stiffnesses_Nm_per_rad]
    names = [trial_name(v, k) for v, k in conditions]
    if len(set(names)) != len(names) or not names:
        raise ValueError(f"speeds and stiffnesses give no or duplicate trial names: {names}")
    if min(k for _, k in conditions) < 0.0:
        raise ValueError("stiffnesses must be ≥ 0 N·m/rad")
    fixed = {key: [float(z) for z in values] for key, values in (between_z or {}).items()}
    for key, values in fixed.items():
        if key not in VIOLATIONS or key not in BETWEEN or len(values) != len(names):
            raise ValueError(f"between_z[{key!r}]: one z per trial of a between-trial violation")
    gait_rng, noise_rng, draw_rng, reading_rng = (
        np.random.default_rng(s) for s in np.random.SeedSequence(seed).spawn(4)
    )
    draws = study_draws(violations, draw_rng, cuff_time_constant_s, artefact)
    trials = []
    for i, (name, (speed, stiffness)) in enumerate(zip(names, conditions, strict=True)):
        z = {key: values[i] for key, values in fixed.items()}
        drawn = trial_draws(violations, draw_rng, duration_s, drop_time_s, z)
        reading_drawn = trial_reading(lab, reading_rng)
        if "cuff.elastic" in violations:
            drawn["cuff.elastic"] = {"time_constant_s": draws.cuff_time_constant_s}
        if "mocap.harmonic" in violations:
            drawn["mocap.harmonic"] = {
                "harmonic": draws.artefact[0],
                "phase_rad": draws.artefact[1],
            }
        trial = simulate_trial(
            name,
            speed,
            stiffness,
            duration_s,
            violations,
            draws,
            drawn,
            gait_rng,
            (torque_noise_Nm, mocap_noise_deg),
            noise_rng,
            lab,
            reading_drawn,
        )
        trial.truth["seed"] = seed
        if reading is not None:
            trial.truth["reading"] = reading.as_dict()
            trial.truth["reading_drawn"] = reading_drawn
        trials.append(trial)
    return trials


def write_study(folder: Path, **kwargs) -> Path:
    """Write simulate_study(**kwargs)'s trials into folder; return manifest.csv's path.

    Per trial <trial>_brace.csv and <trial>_mocap.csv (docs/rig.md §3) and truth/<trial>.json.
    """
    return write_trial_files(Path(folder), simulate_study(**kwargs))
