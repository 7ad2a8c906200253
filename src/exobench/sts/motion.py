"""Motion laws of the generalized coordinates φ1 (hip), φ2 (knee), φ3 (ankle) over the cycle.

Upright at 0 s, seat reached at 1.5 s (the legs stop), seated at 2 s. Three laws
(:data:`LAWS`): the seed's piecewise-linear laws (seed 001 eq. 4), minimum-jerk quintic segments
through the same postures, which start and end every segment at rest, and the corrected laws
(:mod:`exobench.sts.corrected`): minimum-jerk segments through corrected postures, on the chain
whose knee and hip turn the human way. Arrays have one row per sample and the columns
(φ1, φ2, φ3).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from exobench.errors import InputError

COORDINATES = ("phi1", "phi2", "phi3")
# Seed 001 eq. (4): rates of the first stage and the second-stage law of φ1, in units of π.
FIRST_STAGE_RATE = np.array([0.4, 0.25, 0.06]) * np.pi  # rad/s, 0 ≤ t ≤ 1.5 s
SECOND_STAGE_START = np.array([0.6, 0.375, 0.09]) * np.pi  # rad at t = 1.5 s
SECOND_STAGE_RATE = np.array([-0.3, 0.0, 0.0]) * np.pi  # rad/s, 1.5 s ≤ t ≤ 2 s
STAGE_END_S = 1.5
CYCLE_S = 2.0
# the study's postures at the seat (1.5 s) and seated (2 s)
STUDY_POSTURES = (SECOND_STAGE_START, SECOND_STAGE_START + SECOND_STAGE_RATE * 0.5)


@dataclass(frozen=True)
class Law:
    """A motion law: the chain convention (exobench.sts.kinematics.CONVENTIONS) it runs on."""

    convention: str


LAWS = {
    "piecewise": Law("study"),
    "smooth": Law("study"),
    "corrected": Law("corrected"),
    "corrected_study_seat": Law("corrected"),
}


def law(name: str) -> Law:
    """The law called ``name``; KeyError naming the known laws otherwise."""
    if name not in LAWS:
        raise KeyError(f"unknown motion law '{name}': one of {sorted(LAWS)}")
    return LAWS[name]


@dataclass(frozen=True)
class Motion:
    """Sampled coordinates, rates and accelerations of one motion law."""

    t_s: np.ndarray
    q_rad: np.ndarray
    qd_rad_per_s: np.ndarray
    qdd_rad_per_s2: np.ndarray


def time_grid(sample_rate_Hz: float) -> np.ndarray:
    """Samples of the 2 s cycle, both ends and the 1.5 s stage change included."""
    last_stage = (CYCLE_S - STAGE_END_S) * sample_rate_Hz  # samples in the 0.5 s after it
    if not (np.isclose(last_stage, round(last_stage)) and round(last_stage) >= 1):
        raise InputError(
            "config",
            "sts.sample_rate_Hz",
            "a rate that puts a sample on the 1.5 s stage change (a multiple of 2 Hz)",
            sample_rate_Hz,
        )
    return np.linspace(0.0, CYCLE_S, round(CYCLE_S * sample_rate_Hz) + 1)


def piecewise(t_s: np.ndarray) -> Motion:
    """Seed 001 eq. (4); rate jumps (also from and to rest at 0 and 2 s) as one-sample impulses.

    The laws are linear in time, so the acceleration is zero inside each stage. Each jump in
    rate Δφ̇ is represented on the sample grid as Δφ̇/Δt at the sample where it happens: its
    integral is the true jump, its height grows as 1/Δt (a Dirac impulse in the limit).
    """
    first = t_s[:, None] <= STAGE_END_S
    q = np.where(
        first,
        FIRST_STAGE_RATE * t_s[:, None],
        SECOND_STAGE_START + SECOND_STAGE_RATE * (t_s[:, None] - STAGE_END_S),
    )
    qd = np.where(first, FIRST_STAGE_RATE, SECOND_STAGE_RATE)
    dt = t_s[1] - t_s[0]
    qdd = np.zeros_like(q)
    qdd[0] = FIRST_STAGE_RATE / dt
    qdd[np.searchsorted(t_s, STAGE_END_S)] = (SECOND_STAGE_RATE - FIRST_STAGE_RATE) / dt
    qdd[-1] = -SECOND_STAGE_RATE / dt
    qd[0] = 0.0
    qd[-1] = 0.0
    return Motion(t_s, q, qd, qdd)


def rate_jumps() -> dict[str, list[float]]:
    """Jumps in φ̇ (rad/s) of the piecewise laws at 0, 1.5 and 2 s, cycle at rest outside."""
    return {
        "0.0": FIRST_STAGE_RATE.tolist(),
        "1.5": (SECOND_STAGE_RATE - FIRST_STAGE_RATE).tolist(),
        "2.0": (-SECOND_STAGE_RATE).tolist(),
    }


def _min_jerk(tau: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Minimum-jerk blend s(τ) = 10τ³ − 15τ⁴ + 6τ⁵ and its first two derivatives in τ."""
    return (
        tau**3 * (10 - 15 * tau + 6 * tau**2),
        30 * tau**2 * (1 - tau) ** 2,
        60 * tau * (1 - tau) * (1 - 2 * tau),
    )


def min_jerk(t_s: np.ndarray, at_seat: np.ndarray, seated: np.ndarray) -> Motion:
    """Quintic minimum-jerk segments from upright (0) to ``at_seat`` at 1.5 s and ``seated``
    at 2 s: q = q₀ + Δq·s(τ), q̇ = Δq·s'(τ)/T, q̈ = Δq·s''(τ)/T² per segment of duration T."""
    end = CYCLE_S - STAGE_END_S
    first = t_s <= STAGE_END_S
    tau = np.where(first, t_s / STAGE_END_S, (t_s - STAGE_END_S) / end)
    duration = np.where(first, STAGE_END_S, end)[:, None]
    s, ds, dds = (x[:, None] for x in _min_jerk(tau))
    at_seat, seated = np.asarray(at_seat, float), np.asarray(seated, float)
    start = np.where(first[:, None], 0.0, at_seat)
    change = np.where(first[:, None], at_seat, seated - at_seat)
    return Motion(
        t_s,
        start + change * s,
        change * ds / duration,
        change * dds / duration**2,
    )


def smooth(t_s: np.ndarray) -> Motion:
    """Quintic minimum-jerk segments through the eq. (4) postures at 0, 1.5 and 2 s."""
    return min_jerk(t_s, *STUDY_POSTURES)
