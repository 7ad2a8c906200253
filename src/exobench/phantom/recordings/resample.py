"""Resampling a recording to the analysis rates (markers 100 Hz, analog channels 1000 Hz)."""

from __future__ import annotations

import numpy as np

from exobench import signals

# Downsampling first low-passes at this share of the output rate (numerical design: below its
# Nyquist frequency, far above the analysis chain's 6 Hz), so that noise and vibration above the
# new Nyquist frequency do not fold into the band the analysis keeps.
ANTI_ALIAS_SHARE = 0.4
ANTI_ALIAS_ORDER = 4


def support(count: int, rate_in_hz: float, rate_out_hz: float, available: int):
    """For ``count`` output samples: the four input samples around each (n, 4, clipped to the
    ``available`` ones) and their cubic-convolution weights (Keys, a = −0.5); an output that
    falls on an input sample takes it alone."""
    position = np.arange(count) * (rate_in_hz / rate_out_hz)
    base = np.floor(position + 1e-9).astype(int)
    f = np.clip(position - base, 0.0, None)[:, None]
    weights = np.hstack(
        [
            ((-0.5 * f + 1.0) * f - 0.5) * f,
            (1.5 * f - 2.5) * f * f + 1.0,
            ((-1.5 * f + 2.0) * f + 0.5) * f,
            (0.5 * f - 0.5) * f * f,
        ]
    )
    on_sample = f[:, 0] < 1e-9
    weights[on_sample] = [0.0, 1.0, 0.0, 0.0]
    index = np.clip(base[:, None] + np.arange(-1, 3)[None, :], 0, available - 1)
    return index, weights


def resample(values: np.ndarray, rate_in_hz: float, rate_out_hz: float, count: int) -> np.ndarray:
    """``count`` samples at ``rate_out_hz`` of values (n, ...) recorded at ``rate_in_hz`` by cubic
    convolution; NaN where a supporting sample is NaN (a gap stays a gap); unchanged samples when
    the rates agree."""
    values = np.asarray(values, dtype=float)
    if rate_in_hz == rate_out_hz:
        return values[:count].copy()
    if rate_out_hz < rate_in_hz:
        values = anti_aliased(values, rate_in_hz, ANTI_ALIAS_SHARE * rate_out_hz)
    index, weights = support(count, rate_in_hz, rate_out_hz, values.shape[0])
    weights = weights.reshape((count, 4) + (1,) * (values.ndim - 1))
    picked = np.where(weights != 0.0, values[index], 0.0)  # a sample of weight 0 plays no part
    return np.sum(picked * weights, axis=1)


def anti_aliased(values: np.ndarray, rate_hz: float, cutoff_hz: float) -> np.ndarray:
    """Values low-passed along axis 0 (zero-phase Butterworth, ``ANTI_ALIAS_ORDER`` each way)
    at ``cutoff_hz``; gaps (NaN) bridged linearly for the filter and left NaN after it."""
    flat = values.reshape(values.shape[0], -1)
    missing = np.isnan(flat)
    bridged = flat.copy()
    where = np.arange(flat.shape[0])
    for column in np.flatnonzero(missing.any(axis=0) & ~missing.all(axis=0)):
        ok = ~missing[:, column]
        bridged[:, column] = np.interp(where, where[ok], flat[ok, column])
    bridged[:, missing.all(axis=0)] = 0.0
    smooth = signals.zero_phase(signals.butterworth(ANTI_ALIAS_ORDER, cutoff_hz, rate_hz), bridged)
    return np.where(missing, np.nan, smooth).reshape(values.shape)


def resample_flags(flags: np.ndarray, rate_in_hz: float, rate_out_hz: float, count: int):
    """``count`` flags at ``rate_out_hz``: an output sample is flagged when an input sample it is
    computed from is."""
    flags = np.asarray(flags, dtype=bool)
    if rate_in_hz == rate_out_hz:
        return flags[:count].copy()
    index, weights = support(count, rate_in_hz, rate_out_hz, flags.size)
    return (flags[index] & (weights != 0.0)).any(axis=1)


def analysis_frames(frames: int, point_rate_hz: float, analysis_rate_hz: float) -> int:
    """Frames at the analysis rate that fall inside a recording of ``frames`` camera frames."""
    return int(np.floor(frames * analysis_rate_hz / point_rate_hz + 1e-9))
