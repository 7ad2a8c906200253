"""Stride segmentation stage: strides from SYNC pulses, else from the kinematics (§2.4)."""

from __future__ import annotations

import numpy as np
import pandas as pd

from exobench.errors import InputError
from exobench.phantom.rig import ANALOG_RATE_HZ

RAMP = "hexapod ramp stride"
GAP = "marker gap longer than the fill limit"
ANALOG_GAP = "load-cell gap (glitch) longer than the fill limit"
LOW_FORCE = "peak spring force below the minimum"
INCOMPLETE = "stride not wholly inside the recording"
SATURATED = "load cell saturated or clipped (flat run at its extreme)"


def sync_starts(sync_v: np.ndarray, threshold_v: float) -> np.ndarray:
    """Sample indices of the rising edges of the SYNC pulses."""
    high = sync_v > threshold_v
    rising = np.flatnonzero(high[1:] & ~high[:-1]) + 1
    return np.concatenate([[0], rising]) if high[0] else rising


def kinematic_starts(flexion_rad: np.ndarray, swing_peak_fraction: float) -> np.ndarray:
    """Stride starts from the swing flexion peaks: period and phase fitted to all peaks.

    Peaks are numbered by their nearest whole stride from the first one (missing peaks, e.g.
    in low-amplitude ramp strides, leave gaps), then peak = phase + period·number is fitted by
    least squares, so timing jitter of single peaks averages out.
    """
    from scipy.signal import find_peaks  # only here: recordings with SYNC pulses skip its import

    spread = np.ptp(flexion_rad)
    peaks, _ = find_peaks(flexion_rad, prominence=0.5 * spread, distance=int(0.5 * ANALOG_RATE_HZ))
    if peaks.size < 2:
        raise ValueError("fewer than two swing peaks: cannot find strides")
    number = np.round((peaks - peaks[0]) / np.median(np.diff(peaks)))
    period, first_peak = np.polyfit(number, peaks, 1)
    # First start within half a period of the file's start (it may lie just before it).
    offset = np.mod(first_peak - swing_peak_fraction * period + 0.5 * period, period) - 0.5 * period
    count = int(np.ceil((flexion_rad.size - 0.5 * period - offset) / period))
    return np.round(offset + period * np.arange(count)).astype(int)


def stride_table(
    starts,
    samples_per_stride,
    total,
    ramp_strides,
    long_gap,
    spring_force,
    minimum,
    saturated,
    analog_gap=None,
):
    """One row per programmed stride with inclusion and the reason for any exclusion."""
    count = starts.size
    stride = np.arange(count)
    ends = starts + samples_per_stride
    complete = (starts >= 0) & (ends <= total)
    reason = np.full(count, "", dtype=object)
    peak_force = np.full(count, np.nan)
    gap_touch = np.zeros(count, bool)
    analog_touch = np.zeros(count, bool)
    saturation = np.zeros(count, bool)
    analog_gap = np.zeros(total, bool) if analog_gap is None else analog_gap
    if complete.any():
        index = starts[complete, None] + np.arange(samples_per_stride)[None, :]
        peak_force[complete] = spring_force[index].max(1)
        gap_touch[complete] = long_gap[index].any(1)
        analog_touch[complete] = analog_gap[index].any(1)
        saturation[complete] = saturated[index].any(1)
    reason[(peak_force < minimum)] = LOW_FORCE
    reason[analog_touch] = ANALOG_GAP
    reason[gap_touch] = GAP
    reason[saturation] = SATURATED
    reason[(stride < ramp_strides) | (stride >= count - ramp_strides)] = RAMP
    reason[~complete] = INCOMPLETE
    return pd.DataFrame(
        {
            "stride": stride,
            "start_s": starts / ANALOG_RATE_HZ,
            "end_s": ends / ANALOG_RATE_HZ,
            "peak_spring_force_N": peak_force,
            "analysed": np.isin(reason, ["", LOW_FORCE]),
            "included": reason == "",
            "exclusion_reason": reason.astype(str),
        }
    )


def flag(filtered: pd.DataFrame, column: str) -> np.ndarray:
    """A per-sample flag of the filtered table (all False for tables without it)."""
    if column in filtered.columns:
        return filtered[column].to_numpy(bool)
    return np.zeros(len(filtered), bool)


def segment(
    filtered: pd.DataFrame,
    angles: pd.DataFrame,
    ramp_strides: int,
    swing_fraction: float,
    settings,
    minimum_force_N: float,
    source: str,
) -> pd.DataFrame:
    """Stride table of one trial, from SYNC when the recording has it, else from kinematics.

    InputError (naming ``source``) when no stride can be found, none is included, or fewer than
    ``settings["min_analysable_share"]`` of the strides between the ramps are analysable (the
    rest excluded for gaps, glitches, saturation): a fault that holds across the trial.
    """
    if "SYNC_V" in filtered.columns:
        starts = sync_starts(filtered["SYNC_V"].to_numpy(), float(settings["sync_threshold_V"]))
        method = "sync"
    else:
        starts = np.array([], int)
    if starts.size < 2:
        flexion = angles["phantom_knee_angle_rad"].to_numpy()
        try:
            starts = kinematic_starts(flexion, swing_fraction)
        except ValueError as error:
            raise InputError(source, "strides", "at least two strides", str(error)) from error
        method = "kinematics"
    samples = int(np.median(np.diff(starts)))
    table = stride_table(
        starts,
        samples,
        len(filtered),
        ramp_strides,
        filtered["marker_gap"].to_numpy(),
        filtered["LC_SPRING_N"].to_numpy(),
        minimum_force_N,
        flag(filtered, "load_cell_saturated"),
        flag(filtered, "analog_gap"),
    )
    table.insert(1, "segmentation", method)
    reasons = table["exclusion_reason"].value_counts().to_dict()
    if not table["included"].any():
        raise InputError(source, "strides", "at least one included stride", reasons)
    programmed = table["exclusion_reason"] != RAMP
    share = float(settings["min_analysable_share"])
    if table.loc[programmed, "analysed"].sum() < share * programmed.sum():
        raise InputError(
            source, "strides",
            f"at least {share:.0%} of the {programmed.sum()} strides between the ramps analysable",
            reasons,
        )  # fmt: skip
    return table
