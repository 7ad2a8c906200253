"""The load cells' and SYNC's analog channels: the true forces through each channel's
gain, offset, drift, lag and crosstalk, on the analog clock."""

import math
from collections.abc import Mapping, Sequence

import numpy as np

from .rig import ANKLE_CELLS, FS_ANALOG, LOAD_CELLS, STRIDE_S, SYNC_S, SYNC_V, value_of


def sync_signal(n: int, delay_samples: float = 0.0) -> np.ndarray:
    """SYNC (V) stamped k: 5 V while 0 ≤ k − d < n and (k − d) mod stride < 20 ms, else 0."""
    pos = np.arange(n) - delay_samples
    on = (pos >= 0) & (pos < n) & (np.mod(pos, round(STRIDE_S * FS_ANALOG)) < SYNC_S * FS_ANALOG)
    return np.where(on, SYNC_V, 0.0)


def _lagged(signal: np.ndarray, substeps: int, delay_s: float) -> np.ndarray:
    """Analog samples k/fs of a signal sampled substeps× faster, read at k/fs − d (ends held)."""
    if delay_s == 0.0:
        return signal[::substeps]
    fine_fs = FS_ANALOG * substeps
    n = signal.size // substeps
    return np.interp(np.arange(n) * substeps - delay_s * fine_fs, np.arange(signal.size), signal)


def load_cell_signals(
    fx: np.ndarray,
    fy: np.ndarray,
    tension: np.ndarray,
    violations: Mapping[str, Mapping[str, float]],
    cell_shares: Sequence[float],
    substeps: int,
) -> np.ndarray:
    """Load cells' g·(true + s·other)(t − d − D) (4, n); ankle cells share F_y cos α + F_x sin α.

    The ankle cells' crosstalk is a share of the spring's true tension, the spring cell's a share
    of the true vertical ankle force F_y; D is the analog clock's delay.
    """
    tilt = value_of(violations, "cell_direction.tilt", 0.0)
    along = fy * math.cos(tilt) + fx * math.sin(tilt) if tilt else fy
    sensed = [share * along for share in cell_shares] + [tension]
    others = [tension] * len(ANKLE_CELLS) + [fy]
    clock = value_of(violations, "clocks.delay", 0.0)
    out = []
    for cell, own, other in zip(LOAD_CELLS, sensed, others, strict=True):
        share = value_of(violations, f"{cell}.crosstalk", 0.0)
        signal = own + share * other if share else own
        delay = value_of(violations, f"{cell}.delay", 0.0) + clock
        out.append(value_of(violations, f"{cell}.gain", 1.0) * _lagged(signal, substeps, delay))
    return np.array(out)
