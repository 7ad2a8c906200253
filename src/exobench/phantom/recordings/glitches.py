"""Glitch detection: samples that depart from a channel's own behaviour — spikes, ghost frames,
swapped labels — told apart from what the rig really does.

Every test compares a deviation with ``threshold_mad`` × the median absolute deviation of the
same channel (its own noise) and with a floor in the channel's unit (the smallest excursion
worth repairing; on a noise-free channel the median is zero). A running median follows fast but
monotone motion (a spring that recoils in one frame) and removes short excursions, so what is
left is an excursion that leaves the path and comes back.
"""

from __future__ import annotations

import warnings
from collections.abc import Mapping, Sequence
from itertools import combinations

import numpy as np
from scipy.ndimage import median_filter

from exobench.phantom.recordings import gaps


def window_samples(window_s: float, rate_hz: float) -> int:
    """An odd number of samples, at least 3, spanning about ``window_s`` at ``rate_hz``."""
    samples = max(3, round(window_s * rate_hz))
    return samples + 1 - samples % 2


def running_median(values: np.ndarray, window: int) -> np.ndarray:
    """Centred running median of each column of (n, k) values, edges held (column by column:
    SciPy's one-dimensional median filter is several times faster than its n-dimensional one)."""
    columns = [median_filter(column, size=window, mode="nearest") for column in values.T]
    return np.stack(columns, axis=1) if columns else np.empty_like(values)


def departure(values: np.ndarray, window: int) -> np.ndarray:
    """Deviation (n, k) of each sample from the running median of its column; NaN where the
    sample is missing (gaps are bridged for the median, not tested)."""
    values = np.asarray(values, dtype=float)
    if np.isnan(values).all():
        return np.full(values.shape, np.nan)
    return values - running_median(gaps.bridged(values), window)


def outliers(size: np.ndarray, threshold_mad: float, floor: float) -> np.ndarray:
    """Samples whose non-negative ``size`` exceeds ``threshold_mad`` × its median and ``floor``."""
    finite = size[np.isfinite(size)]
    spread = float(np.median(finite)) if finite.size else 0.0
    with np.errstate(invalid="ignore"):
        return size > max(threshold_mad * spread, floor)


def consensus(cells: np.ndarray, window: int, threshold_mad: float) -> np.ndarray:
    """Departure (n, k) of each of k load cells that carry shares of one force, after the others'
    consensus: a transient of the force moves every cell by its share, a spike one cell only.

    Shares come from a least-squares fit of each cell to their sum (an offset beside), refitted
    without the samples whose residual exceeds ``threshold_mad`` × its median (spikes); the
    consensus is the median over cells of departure / share, and each cell keeps what its share
    of it does not explain.
    """
    deviation = departure(cells, window)
    kept = np.isfinite(cells).all(1)
    if kept.sum() < 2:
        return deviation
    total = np.nansum(cells, 1)
    design = np.column_stack([np.ones_like(total), total])
    for _ in range(2):
        fit = np.linalg.lstsq(design[kept], cells[kept], rcond=None)[0]
        residual = np.abs(cells - fit[0] - total[:, None] * fit[1])
        within = kept & (residual <= threshold_mad * np.median(residual[kept], 0)).all(1)
        kept = within if within.sum() > design.shape[1] else kept
    shares = np.where(np.abs(fit[1]) > 0, fit[1], np.nan)
    with np.errstate(invalid="ignore", divide="ignore"):
        ratio = deviation / shares
    if np.isfinite(ratio).all():
        force = np.median(ratio, 1)
    else:
        with warnings.catch_warnings():  # a sample missing in every cell has no consensus
            warnings.simplefilter("ignore", RuntimeWarning)
            force = np.nan_to_num(np.nanmedian(ratio, 1))
    return deviation - shares * force[:, None]


def impulses(xyz: np.ndarray, window: int, threshold_mad: float, floor: float):
    """Frames where a marker (n, 3) leaves its own path (a ghost of up to window // 2 frames)
    and how far (NaN where missing).

    A frame departs from the running median of its path and from the straight-line paths
    through the two frames before it and through the two after it: a step that stays (a spring
    recoiling in one frame, even against the motion) agrees with the frames after it.
    """
    size = np.linalg.norm(departure(xyz, window), axis=1)
    before, after = (np.full(xyz.shape[0], np.nan) for _ in range(2))
    before[2:] = np.linalg.norm(xyz[2:] - 2 * xyz[1:-1] + xyz[:-2], axis=1)
    after[:-2] = np.linalg.norm(xyz[:-2] - 2 * xyz[1:-1] + xyz[2:], axis=1)
    sides = [outliers(s, threshold_mad, floor) | np.isnan(s) for s in (before, after)]
    return outliers(size, threshold_mad, floor) & sides[0] & sides[1], size


def paired_jumps(
    xyz: np.ndarray, window: int, threshold_mad: float, floor: float, return_share: float
):
    """Frames between a jump of a marker (n, 3) and the jump that brings it back (a swapped
    label or a long ghost), and the size of the jump.

    A jump is a step between frames that departs from the running median of the steps; it is
    paired with the next jump when the two together leave less than ``return_share`` of the
    first one. A jump with no return (fast motion, e.g. a recoiling spring) is not flagged.
    """
    steps = np.diff(xyz, axis=0)
    deviation = departure(steps, window)
    size = np.linalg.norm(deviation, axis=1)
    jumps = np.flatnonzero(outliers(size, threshold_mad, floor))
    flagged = np.zeros(xyz.shape[0], bool)
    height = np.full(xyz.shape[0], np.nan)
    index = 0
    while index + 1 < jumps.size:
        first, second = jumps[index], jumps[index + 1]
        closes = np.linalg.norm(deviation[first] + deviation[second]) < return_share * size[first]
        if closes:
            flagged[first + 1 : second + 1] = True
            height[first + 1 : second + 1] = size[first]
        index += 2 if closes else 1
    return flagged, height


def rigid_violations(
    points: Mapping[str, np.ndarray],
    sets: Sequence[Sequence[str]],
    threshold_mad: float,
    floor: float,
) -> dict[str, tuple[np.ndarray, np.ndarray]]:
    """Frames where a marker is off the rigid segment it shares with others (a ghost or a
    swap), by marker: (flags, largest change of its distances to the others).

    Each distance between two markers of one set is compared with its median over the trial. In
    a set of three or more, a marker is flagged where more than half of its distances changed
    (the others moved only relative to it); in a set of two, both are.
    """
    frames = next(iter(points.values())).shape[0]
    out = {}
    for members in sets:
        violated = {label: np.zeros(frames, int) for label in members}
        change = {label: np.zeros(frames) for label in members}
        for first, second in combinations(members, 2):
            distance = np.linalg.norm(points[first] - points[second], axis=1)
            finite = distance[np.isfinite(distance)]
            if finite.size == 0:
                continue
            size = np.abs(distance - np.median(finite))
            hit = outliers(size, threshold_mad, floor)
            for label in (first, second):
                violated[label] += hit
                change[label] = np.fmax(change[label], np.where(hit, size, 0.0))
        needed = (len(members) - 1) / 2 if len(members) > 2 else 0.5
        for label in members:
            flags = violated[label] > needed
            previous = out.get(label, (np.zeros(frames, bool), np.zeros(frames)))
            out[label] = (
                previous[0] | flags,
                np.fmax(previous[1], np.where(flags, change[label], 0)),
            )
    return out
