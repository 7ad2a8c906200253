"""When the emulated spring was active, as the recording shows it, against Table 6.1.

Seed 002 stores energy while the controller's spring is active: the recorded clutch flag where
the file has one, else a non-zero desired torque. Table 6.1 reconstructed offline from the
encoder is only a cross-check: the spring should ask for torque exactly while Table 6.1's clutch
is engaged and the spring law τ = κ·max(0, θ_eq − θ) is non-zero (while engaged, for a flag).
"""

from __future__ import annotations

import numpy as np

PHASE_BIN_PCT = 10.0  # gait-cycle bins of the cross-check


def recorded(desired_Nm: np.ndarray, clutch_flag: np.ndarray | None) -> np.ndarray:
    """Recorded activity per sample: the clutch flag if recorded, else desired torque ≠ 0."""
    if clutch_flag is not None:
        return np.asarray(clutch_flag) != 0
    return np.asarray(desired_Nm) != 0.0


def clutch_window(engaged: np.ndarray, clutch_flag: np.ndarray | None) -> np.ndarray:
    """The spring's active window, Heer's energy window: the recorded clutch flag if the file has
    one, else Table 6.1's engage-to-release rebuilt offline (no spring-law gate)."""
    if clutch_flag is not None:
        return np.asarray(clutch_flag) != 0
    return np.asarray(engaged, bool).copy()


def window_phases(window: np.ndarray, heel_strikes: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Per step, 100·(i − hs_k)/(hs_k+1 − hs_k) of the window's onset and of its end inside it."""
    if len(heel_strikes) < 2:
        return np.zeros(0), np.zeros(0)
    span = np.arange(heel_strikes[0], heel_strikes[-1])
    starts = heel_strikes[:-1] - heel_strikes[0]
    window = np.asarray(window, bool)
    on = window[span]
    # onsets and ends, not the step's first and last window samples: a window running on past a
    # heel strike gives the next step no engage and itself no release (NaN), not 0 % and 100 %
    rises = on & ~np.concatenate([[False], window[:-1]])[span]
    falls = on & ~np.concatenate([window[1:], [False]])[span]
    never = np.iinfo(np.int64).max
    first = np.minimum.reduceat(np.where(rises, span, never), starts)
    last = np.maximum.reduceat(np.where(falls, span, -1), starts)
    length = np.diff(heel_strikes)
    engage = np.where(first < never, 100.0 * (first - heel_strikes[:-1]) / length, np.nan)
    release = np.where(last >= 0, 100.0 * (last + 1 - heel_strikes[:-1]) / length, np.nan)
    return engage, release


def table61(engaged: np.ndarray, spring_Nm: np.ndarray, flag_recorded: bool) -> np.ndarray:
    """What Table 6.1 expects the recording to show: engaged (a flag) or engaged with τ > 0."""
    return engaged.copy() if flag_recorded else engaged & (spring_Nm > 0.0)


def crosscheck(
    active: np.ndarray, expected: np.ndarray, heel_strikes: np.ndarray, tolerance_samples: int
) -> tuple[np.ndarray, dict]:
    """Per-step disagreement (samples) and the trial's summary: share of steps, gait phases.

    A step disagrees when more than ``tolerance_samples`` of its samples differ; a phase bin of
    a step disagrees likewise within the bin. Phases are gait-cycle % from heel strike.
    """
    n_bins = round(100.0 / PHASE_BIN_PCT)
    n_steps = max(len(heel_strikes) - 1, 0)
    edges = [float(b * PHASE_BIN_PCT) for b in range(n_bins)]
    if n_steps == 0:
        empty = {"phase_pct": edges, "share_of_steps": [0.0] * n_bins}
        summary = {"n_steps": 0, "steps_disagreeing": 0, "share_of_steps_disagreeing": None}
        return np.zeros(0, dtype=int), {**summary, "by_phase": empty, "phases_disagreeing_pct": []}
    span = np.arange(heel_strikes[0], heel_strikes[-1])
    step = np.searchsorted(heel_strikes, span, side="right") - 1
    phase = (span - heel_strikes[step]) / (heel_strikes[step + 1] - heel_strikes[step])
    phase_bin = np.minimum((phase * n_bins).astype(int), n_bins - 1)
    differs = active[span] != expected[span]
    per_step = np.bincount(step, differs, n_steps).astype(int)
    per_bin = np.bincount(step * n_bins + phase_bin, differs, n_steps * n_bins)
    bin_share = (per_bin.reshape(n_steps, n_bins) > tolerance_samples).mean(axis=0)
    disagreeing = per_step > tolerance_samples
    summary = {
        "n_steps": n_steps,
        "steps_disagreeing": int(disagreeing.sum()),
        "share_of_steps_disagreeing": float(disagreeing.mean()),
        "recorded_only_samples": int((active[span] & ~expected[span]).sum()),
        "table61_only_samples": int((~active[span] & expected[span]).sum()),
        "by_phase": {"phase_pct": edges, "share_of_steps": [float(v) for v in bin_share]},
        "phases_disagreeing_pct": [
            [edge, edge + PHASE_BIN_PCT] for edge, v in zip(edges, bin_share, strict=True) if v > 0
        ],
    }
    return per_step, summary
