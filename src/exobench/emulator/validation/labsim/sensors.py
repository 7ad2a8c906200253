"""The channels: the brace encoder (whole counts), the torque sensor behind its low-pass (20 Hz
nominally), and motion capture of the knee at 100 Hz on its own clock."""

from collections.abc import Mapping

import numba
import numpy as np
from scipy import signal

from .gait import Gait, gait_phase
from .rig import FS, FS_MOCAP, TORQUE_CUTOFF_HZ, value_of

# Layout of the encoder's vector: gain g, drift ḃ (deg/s), count drop Δ (deg) and its instant (s),
# the size of its count, 360°/N (deg).
(GAIN, DRIFT, DROP, DROP_AT, STEP, ENCODER_SIZE) = range(6)


@numba.njit(cache=True)
def encoder_reading(brace_deg: float, t: float, q: np.ndarray) -> float:
    """Whole counts (360°/N) of g·θ_b − ḃ·t − Δ·[t ≥ t_drop], t ≥ 0 since the first sample."""
    angle = q[GAIN] * brace_deg - q[DRIFT] * max(t, 0.0)
    if t >= q[DROP_AT]:
        angle -= q[DROP]
    return q[STEP] * round(angle / q[STEP])


def encoder_vector(
    violations: Mapping[str, Mapping[str, float]],
    drop_at_s: float,
    counts_per_turn: int,
) -> np.ndarray:
    """The encoder's gain, drift and count drop (its instant drop_at_s) of the violations, and
    its count 360°/N of N counts per turn."""
    q = np.zeros(ENCODER_SIZE)
    q[GAIN] = value_of(violations, "encoder.gain", 1.0)
    q[DRIFT] = value_of(violations, "encoder.drift", 0.0)
    q[DROP], q[DROP_AT] = value_of(violations, "encoder.step", 0.0), drop_at_s
    q[STEP] = 360.0 / counts_per_turn
    return q


def butterworth(cutoff_hz: float, order: int = 2) -> tuple[np.ndarray, np.ndarray]:
    """Low-pass Butterworth of this order at the loop's rate (bilinear): numerator, denominator."""
    return signal.butter(order, cutoff_hz, fs=FS)


def torque_channel(
    torque: np.ndarray,
    t: np.ndarray,
    violations: Mapping[str, Mapping[str, float]],
    zero_Nm: float,
    noise: np.ndarray,
    cutoff_hz: float | None = TORQUE_CUTOFF_HZ,
) -> np.ndarray:
    """brace_torque_Nm: the cutoff_hz filter of g·(τ(1 + q|τ|) + n), n the load cell's own noise,
    read d late, + o + ḃt + z (no filter when cutoff_hz is None).

    t is the time since the trial's first sample (warm-up samples before it, t < 0, settle the
    filter); the sample stamped t holds the filtered torque at t − d (linear between samples).
    """
    quadratic = value_of(violations, "torque_linearity.nonlinearity", 0.0)
    sensed = torque * (1.0 + quadratic * np.abs(torque)) if quadratic else torque
    filtered = value_of(violations, "torque_sensor.gain", 1.0) * (sensed + noise)
    if cutoff_hz is not None:
        filtered = signal.lfilter(*butterworth(cutoff_hz), filtered)
    delay = value_of(violations, "torque_sensor.delay", 0.0)
    if delay:
        samples = np.arange(t.size)
        filtered = np.interp(samples - delay * FS, samples, filtered)
    offset = value_of(violations, "torque_sensor.offset", 0.0) + zero_Nm
    return filtered + offset + value_of(violations, "torque_sensor.drift", 0.0) * np.maximum(t, 0.0)


def mocap_channel(
    gait: Gait,
    frames: int,
    violations: Mapping[str, Mapping[str, float]],
    zero_deg: float,
    artefact: tuple[int, float],
) -> np.ndarray:
    """knee_flexion_deg before noise: z + g·θ(s') + a·sin(2πkφ(s') + ψ), s' = s(1 − ε) − d.

    s = j / 100 Hz is the frame's stamp; z includes the trial's re-zeroing; (k, ψ) the artefact's
    harmonic and phase, φ the gait phase of the knee shown.
    """
    shown = np.arange(frames) / FS_MOCAP * (1.0 - value_of(violations, "clocks.drift", 0.0))
    shown -= value_of(violations, "clocks.delay", 0.0)
    reading = value_of(violations, "mocap.gain", 1.0) * gait.knee(shown)
    amplitude = value_of(violations, "mocap.harmonic", 0.0)
    if amplitude:
        harmonic, phase = artefact
        reading += amplitude * np.sin(2 * np.pi * harmonic * gait_phase(gait, shown) + phase)
    return reading + value_of(violations, "mocap.offset", 0.0) + zero_deg
