"""The load cells' and SYNC's analog channels: the true forces through each channel's
nonlinearity, gain, offset, drift, lag and crosstalk, on the analog clock (its lag and rate)."""

import math
from collections.abc import Mapping, Sequence

import numpy as np

from .rig import ANKLE_CELLS, FS_ANALOG, LOAD_CELLS, STRIDE_S, SYNC_S, SYNC_V, value_of


def sync_signal(n: int, delay_samples: float = 0.0, rate_error: float = 0.0) -> np.ndarray:
    """SYNC (V) stamped k: 5 V while 0 ≤ k' < n and k' mod stride < 20 ms, k' = k(1 − ε) − d."""
    pos = np.arange(n) - delay_samples
    if rate_error:
        pos = np.arange(n) * (1.0 - rate_error) - delay_samples
    on = (pos >= 0) & (pos < n) & (np.mod(pos, round(STRIDE_S * FS_ANALOG)) < SYNC_S * FS_ANALOG)
    return np.where(on, SYNC_V, 0.0)


def _lagged(signal: np.ndarray, substeps: int, delay_s: float, rate_error: float) -> np.ndarray:
    """Analog samples t = k/fs of a signal sampled substeps× faster, read at t(1 − ε) − d."""
    if delay_s == 0.0 and rate_error == 0.0:
        return signal[::substeps]
    fine_fs = FS_ANALOG * substeps
    n = signal.size // substeps
    stamps = np.arange(n) * substeps * (1.0 - rate_error)  # ends held
    return np.interp(stamps - delay_s * fine_fs, np.arange(signal.size), signal)


def load_cell_signals(
    fx: np.ndarray,
    fy: np.ndarray,
    tension: np.ndarray,
    violations: Mapping[str, Mapping[str, float]],
    cell_shares: Sequence[float],
    substeps: int,
) -> np.ndarray:
    """Load cells' g·N(true + s·other)(t(1 − ε) − d − D) (4, n), N(F) = F(1 + q|F|), F in kN.

    The ankle cells share F_y cos α + F_x sin α; their crosstalk is a share of the spring's true
    tension, the spring cell's a share of the true vertical ankle force F_y; D and ε are the
    analog clock's delay and rate error.
    """
    tilt = value_of(violations, "cell_direction.tilt", 0.0)
    along = fy * math.cos(tilt) + fx * math.sin(tilt) if tilt else fy
    sensed = [share * along for share in cell_shares] + [tension]
    others = [tension] * len(ANKLE_CELLS) + [fy]
    clock = value_of(violations, "clocks.delay", 0.0)
    rate = value_of(violations, "clocks.drift", 0.0)
    quadratic = value_of(violations, "cell_linearity.nonlinearity", 0.0) / 1000.0  # per N
    out = []
    for cell, own, other in zip(LOAD_CELLS, sensed, others, strict=True):
        share = value_of(violations, f"{cell}.crosstalk", 0.0)
        signal = own + share * other if share else own
        if quadratic:
            signal = signal * (1.0 + quadratic * np.abs(signal))
        delay = value_of(violations, f"{cell}.delay", 0.0) + clock
        lagged = _lagged(signal, substeps, delay, rate)
        out.append(value_of(violations, f"{cell}.gain", 1.0) * lagged)
    return np.array(out)
