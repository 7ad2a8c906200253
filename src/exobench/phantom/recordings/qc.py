"""Quality control of a recording: glitches repaired or excluded locally, systematic faults
refused, and the per-trial QC table of what was done, channel by channel.

A glitch (a spike, a ghost frame, a swapped label, a sample out of range or not a number)
becomes a gap: the filter stage fills it when it is no longer than ``max_gap_frames``, else the
strides it touches are excluded. A fault of the whole channel (most of it out of range, e.g. a
unit slip) is refused (InputError), as is a recording left with too few analysable strides.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, replace

import numpy as np
import pandas as pd

from exobench import plausibility
from exobench.errors import InputError
from exobench.phantom.recordings import gaps, glitches
from exobench.phantom.recordings.c3d import Recording
from exobench.phantom.rig import (
    ANALOG_RANGES,
    ANALOG_RATE_HZ,
    ANALOG_UNITS,
    LOAD_CELLS,
    MARKER_RANGE,
    POINT_RATE_HZ,
)

DROPOUT = "dropout"
SATURATED = "saturated"
FILLED = "filled"
TOO_LONG = "not filled: gap longer than the fill limit"
FLAGGED = "flagged: its strides are excluded"
NOT_MAPPED = "not mapped"
LOOKS_LIKE_SYNC = "not mapped: looks like a sync pulse train"
NOT_READ = "not read: map it with phantom.rig.labels"
EVENT_COLUMNS = ("channel", "kind", "start_s", "end_s", "deviation_mm", "deviation_N")
TEXT_UNITS = {"channel": "1", "kind": "1", "repair": "1"}
QC_UNITS = {**TEXT_UNITS, "last_stride": "1", "stride_excluded": "1"}


@dataclass(frozen=True)
class Screened:
    """A recording with its glitches blanked (NaN), the analog samples of saturated load cells
    and one row per event (glitch, dropout, saturated run) at the recording's rates."""

    recording: Recording
    saturated: np.ndarray
    events: pd.DataFrame


def screen(recording: Recording, settings: Mapping) -> Screened:
    """Find the recording's glitches against each channel's own behaviour and blank them;
    refuse (InputError) a channel whose fault is systematic.

    ``settings``: ``phantom.chain.glitches`` (thresholds, windows, rigid marker sets).
    """
    path, k = recording.path, float(settings["threshold_mad"])
    floor_mm, share = float(settings["min_deviation_mm"]), float(settings["max_implausible_share"])
    window = glitches.window_samples(float(settings["marker_window_s"]), recording.point_rate_hz)
    kinds, clean, events = {}, {}, []
    for label, xyz in recording.markers_mm.items():
        missing = np.isnan(xyz).any(1)
        outside = plausibility.out_of_range(xyz, MARKER_RANGE).any(1)
        refuse_systematic(path, f"POINT {label}", xyz[~missing], outside[~missing], share)
        jumps, jump_size = glitches.paired_jumps(
            np.where(outside[:, None], np.nan, xyz), window, k, floor_mm,
            float(settings["jump_return_share"]),
        )  # fmt: skip
        kinds[label] = {
            "out of range": (outside, np.abs(xyz).max(1) - MARKER_RANGE.high),
            "ghost or swapped label (jumped out and back)": (jumps & ~missing, jump_size),
        }
        clean[label] = np.where((outside | jumps)[:, None], np.nan, xyz)
        events += run_events(label, {DROPOUT: (missing, None)}, recording.point_rate_hz, "mm")
    rigid = glitches.rigid_violations(clean, settings["rigid_sets"], k, floor_mm)
    markers = {}
    for label, xyz in recording.markers_mm.items():
        off, size = rigid.get(label, (np.zeros(len(xyz), bool), np.zeros(len(xyz))))
        kinds[label]["off its rigid segment"] = (off & ~np.isnan(xyz).any(1), size)
        rest = np.where(off[:, None], np.nan, clean[label])
        ghost, ghost_size = glitches.impulses(rest, window, k, floor_mm)
        kinds[label]["ghost"] = (ghost, ghost_size)
        flagged = np.any([flags for flags, _ in kinds[label].values()], axis=0)
        markers[label] = np.where(flagged[:, None], np.nan, xyz)
        events += run_events(label, kinds[label], recording.point_rate_hz, "mm")
    analogs, saturated, analog_events = screen_analogs(recording, settings)
    table = pd.DataFrame(events + analog_events, columns=list(EVENT_COLUMNS)).astype(
        {"channel": str, "kind": str, **{c: float for c in EVENT_COLUMNS[2:]}}
    )
    table = table.sort_values(["start_s", "channel", "kind"], kind="stable", ignore_index=True)
    return Screened(replace(recording, markers_mm=markers, analogs=analogs), saturated, table)


def screen_analogs(recording: Recording, settings: Mapping):
    """Blanked analog channels, the samples where a load cell is saturated, and the events.

    The ankle cells carry shares of one force: a spike is what departs from the other cells'
    consensus, so a real transient of the force (every cell moves) is not one."""
    path, rate = recording.path, recording.analog_rate_hz
    k, share = float(settings["threshold_mad"]), float(settings["max_implausible_share"])
    floor = float(settings["min_deviation_N"])
    window = glitches.window_samples(float(settings["analog_window_s"]), rate)
    analogs = dict(recording.analogs)
    blank = {}
    for label in (*LOAD_CELLS, "LC_SPRING"):
        values = analogs[label]
        not_number = ~np.isfinite(values)
        if not_number.mean() > share:
            raise InputError(
                path, f"ANALOG {label}",
                f"finite numbers (at most {share:.1%} of the samples not, as glitches)",
                f"{not_number.sum()} of {values.size} samples not finite",
            )  # fmt: skip
        outside = plausibility.out_of_range(values, ANALOG_RANGES[label])
        refuse_systematic(path, f"ANALOG {label}", values[~not_number], outside[~not_number], share)
        blank[label] = {"not a number": not_number, "out of range": outside}
    numbers = {c: np.where(blank[c]["not a number"], np.nan, analogs[c]) for c in blank}
    cells = np.column_stack([numbers[c] for c in LOAD_CELLS])
    departures = {
        **dict(zip(LOAD_CELLS, glitches.consensus(cells, window, k).T, strict=True)),
        "LC_SPRING": glitches.departure(numbers["LC_SPRING"][:, None], window)[:, 0],
    }
    saturated = np.zeros(next(iter(analogs.values())).size, bool)
    events = []
    run = round(float(settings["saturation_run_s"]) * rate)
    for label, departure in departures.items():
        size = np.abs(departure)
        spikes = glitches.outliers(size, k, floor)
        flagged = spikes | _any(blank[label])
        values = np.where(flagged, np.nan, analogs[label])
        clipped = plausibility.flat_runs_at_extremes(values, run, ANALOG_RANGES[label].clip_low)
        saturated |= clipped
        kinds = {
            "spike": (spikes, size),
            "out of range": (blank[label]["out of range"], np.abs(analogs[label])),
            "not a number": (blank[label]["not a number"], None),
        }
        events += run_events(label, kinds, rate, ANALOG_UNITS[label])
        events += run_events(label, {SATURATED: (clipped, None)}, rate, ANALOG_UNITS[label])
        analogs[label] = values
    return analogs, saturated, events


def _any(kinds: Mapping[str, np.ndarray]) -> np.ndarray:
    return np.any(list(kinds.values()), axis=0)


def refuse_systematic(path, field: str, values: np.ndarray, outside: np.ndarray, share: float):
    """Refuse a channel out of its range in more than ``share`` of its samples (a unit slip, a
    reversed sign, a wrong channel: named by :func:`plausibility.range_expectation`)."""
    if outside.size and outside.mean() > share:
        finite = values[np.isfinite(values)]
        low, high = float(finite.min()), float(finite.max())
        plausible = MARKER_RANGE if field.startswith("POINT") else ANALOG_RANGES[field.split()[1]]
        expected = plausibility.range_expectation(finite, plausible)
        found = f"{low:.6g} to {high:.6g} ({outside.mean():.1%} of the samples out of range)"
        raise InputError(path, field, expected, found)


def run_events(channel: str, kinds: Mapping, rate_hz: float, unit: str) -> list[tuple]:
    """One event per run of flagged samples of a channel; the kinds that flag samples in it,
    joined, and the largest deviation in it (in ``unit``: mm or N; NaN for V or none)."""
    flags = [flags for flags, _ in kinds.values()]
    starts, lengths = gaps.runs(np.any(flags, axis=0))
    out = []
    for start, length in zip(starts, lengths, strict=True):
        span = slice(start, start + length)
        names = [name for name, (flags, _) in kinds.items() if flags[span].any()]
        sizes = [np.nanmax(size[span]) for _, (f, size) in kinds.items() if size is not None
                 and f[span].any() and np.isfinite(size[span]).any()]  # fmt: skip
        deviation = max(sizes) if sizes else np.nan
        out.append((channel, " and ".join(names), start / rate_hz, (start + length) / rate_hz,
                    deviation if unit == "mm" else np.nan,
                    deviation if unit == "N" else np.nan))  # fmt: skip
    return out


def repairs(events: pd.DataFrame, markers: pd.DataFrame, analog: pd.DataFrame, max_gap_frames):
    """Each event with what became of it at the analysis rates: ``repair`` (filled, or a gap
    longer than the fill limit, or saturated samples flagged) and the gap it left (``gap_s``)."""
    per_frame = round(ANALOG_RATE_HZ / POINT_RATE_HZ)
    length_at = {}
    for label in {*events["channel"]}:
        is_marker = f"{label}_x_mm" in markers.columns
        column = markers[f"{label}_x_mm"] if is_marker else analog[f"{label}_{ANALOG_UNITS[label]}"]
        length_at[label] = gaps.run_length_at(column.isna().to_numpy())
    gap_s, repair = [], []
    for row in events.itertuples(index=False):
        is_marker = f"{row.channel}_x_mm" in markers.columns
        rate = POINT_RATE_HZ if is_marker else ANALOG_RATE_HZ
        limit = max_gap_frames * (1 if is_marker else per_frame)
        first = int(np.floor(row.start_s * rate + 1e-9))
        last = max(int(np.ceil(row.end_s * rate - 1e-9)), first + 1)
        longest = int(length_at[row.channel][first:last].max(initial=0))
        gap_s.append(longest / rate)
        if row.kind == SATURATED:
            repair.append(FLAGGED)
        else:
            repair.append(FILLED if longest <= limit else TOO_LONG)
    return events.assign(gap_s=gap_s, repair=repair)


def sync_edges(values: np.ndarray, threshold_V: float) -> int:
    """Rising edges through ``threshold_V`` of a channel that behaves like a sync pulse train
    (at least two, and above the threshold less than half of the time); 0 for any other."""
    values = np.asarray(values, dtype=float)
    high = values[np.isfinite(values)] > threshold_V
    edges = int(np.count_nonzero(high[1:] & ~high[:-1])) + bool(high.size and high[0])
    return edges if edges >= 2 and high.mean() < 0.5 else 0


def unmapped_events(recording: Recording, threshold_V: float) -> pd.DataFrame:
    """One QC row per analog channel the recording holds that no contract name maps to (read
    only when it has no SYNC): its label, whether it looks like a sync pulse train, the span of
    the recording, repair :data:`NOT_READ`."""
    duration = recording.frames / recording.point_rate_hz
    rows = [
        (label, LOOKS_LIKE_SYNC if sync_edges(values, threshold_V) else NOT_MAPPED, 0.0,
         duration, np.nan, np.nan, 0.0, NOT_READ)
        for label, values in recording.unmapped.items()
    ]  # fmt: skip
    return pd.DataFrame(rows, columns=[*EVENT_COLUMNS, "gap_s", "repair"])


def unmapped_warning(recording: Recording, threshold_V: float) -> str | None:
    """One line on the analog channels a recording without SYNC holds unmapped: the one that
    looks like a sync pulse train (else every one) and how to map it; None when there is none."""
    if not recording.unmapped:
        return None
    edges = {label: sync_edges(v, threshold_V) for label, v in recording.unmapped.items()}
    pulses = [label for label, count in edges.items() if count]
    others = [label for label in recording.unmapped if label not in pulses]
    start = f"{recording.path}: no SYNC channel, and"
    if pulses:
        label = pulses[0]
        line = (f"{start} analog channel '{label}' is not mapped but looks like a sync pulse "
                f"train ({edges[label]} rising edges through {threshold_V:g} V): to use it, map "
                f"it with phantom.rig.labels: {{SYNC: {label}}}")  # fmt: skip
        if len(pulses) + len(others) > 1:
            line += f" (also not mapped: {', '.join(pulses[1:] + others)})"
    else:
        names = ", ".join(repr(label) for label in others)
        line = (f"{start} analog channel(s) {names} not mapped: if one is the stride sync, map "
                "it with phantom.rig.labels: {SYNC: <label>}")  # fmt: skip
    return line + "; the strides are found from the knee kinematics"


def qc_table(trial: str, events: pd.DataFrame, strides: pd.DataFrame) -> pd.DataFrame:
    """The trial's QC table: every event with the strides it falls in, whether any of them is
    excluded and why (an analog channel not mapped falls in none)."""
    starts, ends = strides["start_s"].to_numpy(), strides["end_s"].to_numpy()
    first = np.searchsorted(starts, events["start_s"].to_numpy(), side="right") - 1
    last = np.searchsorted(starts, events["end_s"].to_numpy() - 1e-9, side="right") - 1
    unmapped = (events["repair"] == NOT_READ).to_numpy()
    first, last = np.where(unmapped, -1, first), np.where(unmapped, -1, last)
    inside = (first >= 0) & (events["start_s"].to_numpy() < ends[np.maximum(first, 0)])
    reasons = strides["exclusion_reason"].to_numpy()
    why = [
        "; ".join(dict.fromkeys(r for r in reasons[max(a, 0) : b + 1] if r))
        for a, b in zip(first, last, strict=True)
    ]
    table = events.assign(
        trial=trial,
        stride=np.where(inside, first, -1),
        last_stride=np.where(last >= 0, last, -1),
        stride_excluded=[bool(text) for text in why],
        exclusion_reason=why,
    )
    return table[["trial", *EVENT_COLUMNS, "gap_s", "repair", "stride", "last_stride",
                  "stride_excluded", "exclusion_reason"]]  # fmt: skip


def summary_line(trial: str, qc: pd.DataFrame, strides: pd.DataFrame) -> str:
    """One line for the run's log: strides kept, events by kind with their channels and what
    became of them, and the strides excluded by reason."""
    included = int(strides["included"].sum())
    parts = [f"{trial}: {included} of {len(strides)} strides included"]
    if qc.empty:
        parts.append("no glitch, dropout or saturation")
    for kind, group in qc.groupby("kind", sort=True):
        channels = sorted(set(group["channel"]))
        where = ", ".join(channels) if len(channels) <= 3 else f"{len(channels)} channels"
        outcome = ", ".join(f"{n} {r}" for r, n in group["repair"].value_counts().items())
        parts.append(f"{len(group)} {kind} on {where} ({outcome})")
    excluded = strides.loc[~strides["included"], "exclusion_reason"].value_counts()
    if len(excluded):
        parts.append("excluded: " + ", ".join(f"{r} ×{n}" for r, n in excluded.items()))
    return "; ".join(parts)
