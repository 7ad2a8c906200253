"""Plausibility of recorded channels: physical ranges, unit slips and saturated (clipped) runs."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from exobench.errors import InputError

# A unit slip by a factor of 1000 (N·mm for N·m, mm for m, kN/m for N/m, ...) is named as such
# when it scales the whole channel: at least this share of its values lies outside the range
# (a spike or a transient does not; it is a glitch of a few samples).
UNIT_SLIP = 1000.0
SLIP_SHARE = 0.1


@dataclass(frozen=True)
class ChannelRange:
    """Physically plausible values of one recorded channel, in its unit.

    ``clip_low``: a flat run at the channel's minimum is clipping (False where a flat minimum
    is physical, e.g. an idle extension spring holding its pretension).
    """

    low: float
    high: float
    unit: str
    clip_low: bool = True

    def describe(self) -> str:
        """The range as text, e.g. '-30 to 30 N·m'."""
        return f"{self.low:g} to {self.high:g} {self.unit}"


def check_range(path, field: str, values: np.ndarray, plausible: ChannelRange) -> None:
    """Refuse finite values outside ``plausible``; name a 1000× unit slip when it explains them.

    A slip is named when the values divided (multiplied) by 1000 all fit the range, they lie
    more than 5× beyond (below) it, and they are out of range in at least :data:`SLIP_SHARE` of
    the samples: a whole channel scaled, not a few large samples (an offset, a sign error or a
    spike does not look like a slip).
    """
    values = np.asarray(values, dtype=float)
    finite = values[np.isfinite(values)]
    if finite.size == 0:
        return
    low, high = float(finite.min()), float(finite.max())
    if plausible.low <= low and high <= plausible.high:
        return
    raise InputError(path, field, range_expectation(finite, plausible), f"{low:.6g} to {high:.6g}")


def out_of_range(values: np.ndarray, plausible: ChannelRange) -> np.ndarray:
    """Samples outside ``plausible`` (NaN samples are not)."""
    values = np.asarray(values, dtype=float)
    return (values < plausible.low) | (values > plausible.high)


def range_expectation(finite: np.ndarray, plausible: ChannelRange) -> str:
    """What a channel with values outside ``plausible`` was expected to hold, naming a 1000×
    slip (too large or too small) when the whole channel scales."""
    outside = out_of_range(finite, plausible).mean() >= SLIP_SHARE
    low, high = float(finite.min()), float(finite.max())
    reach = 5 * max(abs(plausible.low), abs(plausible.high))
    larger = plausible.low <= low / UNIT_SLIP and high / UNIT_SLIP <= plausible.high
    if outside and larger and max(abs(low), abs(high)) > reach:
        return f"{plausible.unit}, values look {UNIT_SLIP:g}× too large ({plausible.describe()})"
    smaller = plausible.low <= low * UNIT_SLIP and high * UNIT_SLIP <= plausible.high
    if outside and smaller and plausible.low > 0 and 5 * high < plausible.low:
        return f"{plausible.unit}, values look {UNIT_SLIP:g}× too small ({plausible.describe()})"
    return f"values in {plausible.unit} within {plausible.describe()}"


def flat_runs_at_extremes(values: np.ndarray, min_samples: int, clip_low: bool) -> np.ndarray:
    """Samples inside runs of ≥ ``min_samples`` equal values at the channel's max (or min).

    A saturated or clipped sensor holds its extreme value exactly; a live, noisy signal does not.
    """
    values = np.asarray(values, dtype=float)
    flagged = np.zeros(values.size, bool)
    if values.size < min_samples or not np.isfinite(values).any():
        return flagged
    extremes = [np.nanmax(values)] + ([np.nanmin(values)] if clip_low else [])
    for extreme in extremes:
        at = values == extreme
        edges = np.diff(np.concatenate([[0], at.astype(np.int8), [0]]))
        starts, ends = np.flatnonzero(edges == 1), np.flatnonzero(edges == -1)
        long = (ends - starts) >= min_samples
        coverage = np.zeros(values.size + 1, int)
        np.add.at(coverage, starts[long], 1)
        np.add.at(coverage, ends[long], -1)
        flagged |= np.cumsum(coverage[:-1]) > 0
    return flagged
