"""Plausibility of recorded channels: physical ranges, unit slips and saturated (clipped) runs."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from exobench.errors import InputError

# A unit slip by a factor of 1000 (N·mm for N·m, mm for m, ...) is named as such.
UNIT_SLIP = 1000.0


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

    A slip is named when the values divided by 1000 fit the range and the values lie more than
    5× beyond it (an offset or a sign error does not look like a slip).
    """
    values = np.asarray(values, dtype=float)
    finite = values[np.isfinite(values)]
    if finite.size == 0:
        return
    low, high = float(finite.min()), float(finite.max())
    if plausible.low <= low and high <= plausible.high:
        return
    expected = f"values in {plausible.unit} within {plausible.describe()}"
    scaled_in_range = plausible.low <= low / UNIT_SLIP and high / UNIT_SLIP <= plausible.high
    far_out = max(abs(low), abs(high)) > 5 * max(abs(plausible.low), abs(plausible.high))
    if scaled_in_range and far_out:
        expected = (
            f"{plausible.unit}, values look {UNIT_SLIP:g}× too large ({plausible.describe()})"
        )
    raise InputError(path, field, expected, f"{low:.6g} to {high:.6g}")


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
