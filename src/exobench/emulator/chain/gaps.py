"""Gaps (NaN) in a recording (docs/rig.md §3): the brace's are bridged for the filters and
event detection and their steps excluded; motion capture's frames are left out of the fit."""

from __future__ import annotations

import numpy as np
import pandas as pd


def bridge(brace: pd.DataFrame) -> tuple[pd.DataFrame, np.ndarray]:
    """The brace with every channel's gaps linearly interpolated in time, and the mask of the
    samples where any channel had one."""
    missing = brace.isna()
    if not missing.to_numpy().any():
        return brace, np.zeros(len(brace), bool)
    t = brace["time_s"].to_numpy()
    bridged = brace.copy()
    for column in missing.columns[missing.any()]:
        held = ~missing[column].to_numpy()
        bridged[column] = np.interp(t, t[held], brace[column].to_numpy()[held])
    return bridged, missing.any(axis=1).to_numpy()


def excluded_steps(brace: pd.DataFrame, heel_strikes: np.ndarray) -> list[dict]:
    """Each step (heel strike to the next) holding a brace gap: its index, start and the
    reason (the channels and the span of their gaps within the step)."""
    t = brace["time_s"].to_numpy()
    missing = brace.isna().to_numpy()
    gap_rows = np.flatnonzero(missing.any(axis=1))
    step = np.searchsorted(heel_strikes, gap_rows, side="right") - 1
    inside = (step >= 0) & (step < len(heel_strikes) - 1)
    excluded = []
    for k in np.unique(step[inside]):
        rows = gap_rows[step == k]
        channels = brace.columns[missing[rows].any(axis=0)]
        excluded.append(
            {
                "step": int(k),
                "heel_strike_s": float(t[heel_strikes[k]]),
                "reason": (
                    f"gap in {', '.join(channels)} from {t[rows[0]]:.3f} to {t[rows[-1]]:.3f} s "
                    f"({len(rows)} samples): its energy is not computed across it"
                ),
            }
        )
    return excluded


def in_gap(t: np.ndarray, gap: np.ndarray, stamps: np.ndarray) -> np.ndarray:
    """Stamps that fall between brace samples of which one lies in a gap."""
    return np.interp(stamps, t, gap.astype(float)) > 0.0
