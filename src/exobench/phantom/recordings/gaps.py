"""Gaps in a recorded channel: runs of missing (or flagged) samples and their lengths."""

from __future__ import annotations

import numpy as np


def runs(mask: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Start indices and lengths of the runs of True in a boolean vector."""
    edges = np.diff(np.concatenate([[0], np.asarray(mask).astype(np.int8), [0]]))
    starts = np.flatnonzero(edges == 1)
    return starts, np.flatnonzero(edges == -1) - starts


def run_length_at(mask: np.ndarray) -> np.ndarray:
    """Length of the run of True each sample belongs to (0 where False)."""
    starts, lengths = runs(mask)
    out = np.zeros(np.asarray(mask).size, int)
    if starts.size:
        index = np.repeat(starts, lengths) + (
            np.arange(lengths.sum()) - np.repeat(np.cumsum(lengths) - lengths, lengths)
        )
        out[index] = np.repeat(lengths, lengths)
    return out


def bridged(values: np.ndarray) -> np.ndarray:
    """Values (n, k) with each column's NaN runs bridged linearly (a column with no number left
    NaN)."""
    out = np.array(values, dtype=float)
    index = np.arange(out.shape[0])
    for column in range(out.shape[1]):
        missing = np.isnan(out[:, column])
        if missing.any() and not missing.all():
            out[missing, column] = np.interp(index[missing], index[~missing], out[~missing, column])
    return out
