"""Filtering stage: gap filling, zero-phase Butterworth low-pass, markers to 1000 Hz (§2.4)."""

from __future__ import annotations

import numpy as np
import pandas as pd
from scipy.interpolate import CubicSpline

from exobench import signals
from exobench.errors import InputError
from exobench.phantom.recordings import gaps
from exobench.phantom.rig import ANALOG_RATE_HZ, MARKERS, POINT_RATE_HZ

MARKER_COLUMNS = [f"{label}_{axis}_mm" for label in MARKERS for axis in "xy"]


def butterworth_zero_phase(values: np.ndarray, rate_hz: float, cutoff_hz: float, order: int):
    """Zero-phase Butterworth low-pass along axis 0.

    ``order`` is the order of the combined forward–backward response, so a filter of order/2
    runs each way; ``cutoff_hz`` is where that combined response is −3 dB. Each pass is then
    designed at the cutoff corrected by C = (2^(1/2) − 1)^(1/order) (Winter's correction for
    two passes), applied to the prewarped frequency of the bilinear design so it is exact.
    """
    sos = signals.butterworth(order // 2, pass_cutoff_hz(rate_hz, cutoff_hz, order), rate_hz)
    return signals.zero_phase(sos, values)


def pass_cutoff_hz(rate_hz: float, cutoff_hz: float, order: int) -> float:
    """Design cut-off of one pass so that the two-pass response is −3 dB at ``cutoff_hz``."""
    if order % 2:
        raise ValueError("the forward–backward order must be even")
    correction = (np.sqrt(2.0) - 1.0) ** (1.0 / order)
    warped = np.tan(np.pi * cutoff_hz / rate_hz) / correction
    return float(rate_hz / np.pi * np.arctan(warped))


def fill_gaps(values: np.ndarray, max_gap: int) -> tuple[np.ndarray, np.ndarray]:
    """Fill of NaN runs in each column, by cubic spline up to max_gap samples and linearly in
    longer runs (flagged: their strides are excluded, and a spline across them would overshoot
    and the filter carry it into the strides beside them)."""
    filled = values.copy()
    linear = gaps.bridged(values)
    long_gap = np.zeros(values.shape[0], bool)
    index = np.arange(values.shape[0])
    for column in range(values.shape[1]):
        missing = np.isnan(values[:, column])
        if not missing.any():
            continue
        if missing.sum() > values.shape[0] - 4:
            raise ValueError(f"column {column} has fewer than 4 samples")
        spline = CubicSpline(index[~missing], values[~missing, column])
        long = gaps.run_length_at(missing) > max_gap
        short = missing & ~long
        filled[short, column] = spline(index[short])
        filled[long, column] = linear[long, column]
        long_gap |= long
    return filled, long_gap


def filter_trial(markers: pd.DataFrame, analog: pd.DataFrame, settings, source: str):
    """Filtered sagittal markers at 1000 Hz and filtered load cells, one table (docs/rig.md).

    Gaps (occlusions, blanked glitches) are spline-filled first: in the markers up to
    ``max_gap_frames`` frames, in the load cells up to the same time; a sample in a longer gap
    is flagged (``marker_gap``, ``analog_gap``), and the strides it touches are excluded.
    """
    cutoff, order = float(settings["filter_cutoff_Hz"]), int(settings["filter_order"])
    max_gap = int(settings["max_gap_frames"])
    per_frame = round(ANALOG_RATE_HZ / POINT_RATE_HZ)
    raw = markers[MARKER_COLUMNS].to_numpy(float)
    loads = [c for c in analog.columns if c.startswith("LC_")]
    try:
        filled, long_gap = fill_gaps(raw, max_gap)
        filled_loads, analog_gap = fill_gaps(analog[loads].to_numpy(float), max_gap * per_frame)
    except ValueError as error:
        raise InputError(
            source, "POINT, ANALOG", "channels with at least 4 valid samples", str(error)
        ) from error
    smooth = butterworth_zero_phase(filled, POINT_RATE_HZ, cutoff, order)
    t_points = markers["t_s"].to_numpy()
    t = analog["t_s"].to_numpy()
    upsampled = CubicSpline(t_points, smooth, axis=0)(t)
    gap_at_1khz = np.repeat(long_gap, per_frame)[: t.size]
    table = {"t_s": t}
    table.update({name: upsampled[:, i] for i, name in enumerate(MARKER_COLUMNS)})
    filtered_loads = butterworth_zero_phase(filled_loads, ANALOG_RATE_HZ, cutoff, order)
    table.update({name: filtered_loads[:, i] for i, name in enumerate(loads)})
    if "SYNC_V" in analog.columns:
        table["SYNC_V"] = analog["SYNC_V"].to_numpy(float)
    table["marker_gap"] = gap_at_1khz
    table["analog_gap"] = analog_gap
    if "load_cell_saturated" in analog.columns:
        table["load_cell_saturated"] = analog["load_cell_saturated"].to_numpy(bool)
    return pd.DataFrame(table)


def split(filtered: pd.DataFrame) -> tuple[pd.DataFrame, pd.DataFrame]:
    """The filtered table as its two files: the filtered marker paths at their own rate (100 Hz:
    the 1000 Hz paths are their cubic spline, which passes through them) and the 1000 Hz
    channels and flags (load cells, SYNC, marker and analog gaps, saturation)."""
    per_frame = round(ANALOG_RATE_HZ / POINT_RATE_HZ)
    channels = [c for c in filtered.columns if c not in MARKER_COLUMNS]
    markers = filtered[["t_s", *MARKER_COLUMNS]].iloc[::per_frame].reset_index(drop=True)
    return markers, filtered[channels]
