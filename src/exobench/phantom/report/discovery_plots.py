"""Figures of the model discrepancy: the measured peak stance moment per spring beside each
model's error, the work loops of the softest and stiffest spring, every estimate with its
interval; and what the extended model leaves in the knee moment, with each discovered term's
correction against the residual it explains. Any verdict draws: estimates of any sign, at a fit
bound or without an interval, no effect at all."""

from __future__ import annotations

import textwrap
from collections.abc import Mapping

import numpy as np
import pandas as pd
from matplotlib.lines import Line2D

from exobench import figures
from exobench.phantom.model.effects import OBSERVABLES
from exobench.phantom.report.plots import count_text, spring_label
from exobench.phantom.study.statistics import SPRING
from exobench.selection import summary
from exobench.studies import PHANTOM

MEDIANS = f"{PHANTOM.key}'s medians"

BINS = 20  # quantile bins of a term's correction in the figure
PEAK = "peak_moment_Nm"  # the summary's metric panel (a) draws
MODEL_STYLES = {
    "measured": {"color": "0.6", "lw": 3.5, "ls": "-"},
    "baseline": {"color": "#D55E00", "lw": 1.2, "ls": "--"},
    "extended": {"color": "#0072B2", "lw": 1.2, "ls": "-"},
}
MODEL_NAMES = {
    "measured": "measured",
    "baseline": "rigid theory (baseline)",
    "extended": "extended model",
}
# What each status of an estimate is called and how its marker is drawn.
STATUS = {
    "claimed": {"marker": "o", "mfc": "#0072B2", "label": "claimed"},
    "tentative": {"marker": "o", "mfc": "white", "label": "tentative, not claimed"},
    "hypothesis": {"marker": "D", "mfc": "#0072B2", "label": "hypothesis (discovered term)"},
    "proposed": {"marker": "D", "mfc": "white", "label": "proposed term, not named"},
}
BOUND_MARKERS = {"lower": "<", "upper": ">"}
BOUND_COLOUR = "#D55E00"


def short_name(description: str) -> str:
    """An effect's name as the figures write it: its description up to the first bracket."""
    return description.split(" (")[0].strip()


def entry_spec(report: Mapping, entry: Mapping) -> Mapping:
    """The registry's (or the term library's) specification of an entry, empty if unknown."""
    key = entry.get("effect", entry.get("term"))
    library = report.get("discovery", {}).get("library", {})
    return report.get("registry", {}).get(key) or library.get(key) or {}


def at_bound(value: float, interval, bounds) -> str:
    """'lower' or 'upper' when the estimate (or an end of its interval) sits at that fit
    bound; '' otherwise."""
    if bounds is None:
        return ""
    ends = [value, *(interval or [])]
    for side, bound in zip(("lower", "upper"), bounds, strict=True):
        if bound is not None and any(np.isclose(v, bound, rtol=1e-6, atol=1e-12) for v in ends):
            return side
    return ""


def estimates(report: Mapping) -> pd.DataFrame:
    """One row per parameter the report claims, holds tentatively, names as a hypothesis or
    proposes: the parameter's key (to match two reports; never drawn), the effect's name (from
    its description), what the parameter means, estimate, 95 % interval (NaN without one),
    unit, status and the fit bound it sits at ('' if none)."""
    groups = {
        "claimed": report.get("effects_found", []),
        "tentative": report.get("tentative", []),
        "hypothesis": report.get("discovery", {}).get("named", []),
        "proposed": report.get("discovery", {}).get("proposed", []),
    }
    rows = []
    for status, entries in groups.items():
        for entry in entries:
            spec = entry_spec(report, entry)
            specs = {p["name"]: p for p in spec.get("parameters", [])}
            description = entry.get("description") or spec.get("description") or "an effect"
            intervals = entry.get("ci95") or {}
            units = entry.get("units") or {}
            for name, value in entry["parameters"].items():
                interval = intervals.get(name)
                bounds = specs.get(name, {}).get("bounds")
                side = at_bound(float(value), interval, bounds)
                rows.append({
                    "parameter": name,
                    "effect": short_name(description),
                    "description": description,
                    "meaning": specs.get(name, {}).get("meaning", ""),
                    "estimate": float(value),
                    "low": np.nan if interval is None else float(interval[0]),
                    "high": np.nan if interval is None else float(interval[1]),
                    "unit": units.get(name, specs.get(name, {}).get("unit", "1")),
                    "status": status,
                    "bound": side,
                    "bound_value": float(bounds[side == "upper"]) if side else np.nan,
                    "many": len(entry["parameters"]) > 1,
                })  # fmt: skip
    columns = ["parameter", "effect", "description", "meaning", "estimate", "low", "high",
               "unit", "status", "bound", "bound_value", "many"]  # fmt: skip
    return pd.DataFrame(rows, columns=columns)


def plain(value: float) -> str:
    """A number to three significant digits as a plain decimal (1050, not 1.05e+03)."""
    return figures.plain_number(float(f"{value:.3g}"))


def value_text(value: float, interval, unit: str) -> str:
    """'65.6 [65.3, 65.9] N·m/rad': an estimate, its 95 % interval and unit, plain numbers."""
    ci = "" if interval is None else f" [{plain(interval[0])}, {plain(interval[1])}]"
    return f"{plain(value)}{ci}" + ("" if unit in ("1", "") else f" {summary.unit_text(unit)}")


def estimate_label(row) -> str:
    """A row's label: the effect (and the parameter, for an effect with several), its estimate
    [interval] and unit, and what is special about it (tentative, at a bound, no interval)."""
    name = f"{row.effect}: {row.meaning}" if row.many and row.meaning else row.effect
    interval = None if np.isnan(row.low) else (row.low, row.high)
    notes = [] if row.status == "claimed" else [STATUS[row.status]["label"]]
    if row.bound:
        notes.append(f"at its {row.bound} fit bound {plain(row.bound_value)}")
    if interval is None:
        notes.append("no interval")
    if row.estimate == 0:
        notes.append("estimate 0: axis in its unit")
    lines = [*textwrap.wrap(name, 36), value_text(row.estimate, interval, row.unit)]
    return "\n".join(lines + ([f"{'; '.join(notes)}"] if notes else []))


def relative(values, estimate: float) -> np.ndarray:
    """Values relative to an estimate, (value − estimate) / |estimate| in % (the difference
    itself, in the parameter's unit, for an estimate of 0)."""
    difference = np.asarray(values, dtype=float) - estimate
    return difference / abs(estimate) * 100.0 if estimate != 0 else difference


def window_text(predictions: pd.DataFrame) -> str:
    """The engine's window as panels state it, e.g. '0–0.44 s'."""
    return f"{predictions['t_s'].min():g}–{predictions['t_s'].max():g} s"


def engine_sample(predictions: pd.DataFrame) -> pd.DataFrame:
    """The rows of the strides the engine fitted its models to (column ``fitted``; every row of
    a table without it)."""
    return predictions[predictions["fitted"]] if "fitted" in predictions else predictions


def engine_strides(predictions: pd.DataFrame) -> str:
    """The engine's strides per spring, e.g. 'n = 11 strides per spring'."""
    sample = engine_sample(predictions)
    return count_text(sample.groupby(SPRING)["stride"].nunique()) + " strides per spring"


def work_window(protocol: Mapping) -> str:
    """The work window of ``summary.csv``'s peak moment, e.g. '0–45 % of cycle'."""
    pct = 100.0 * float(protocol["work_window_s"]) / float(protocol["stride_time_s"])
    return f"0–{pct:g} % of cycle"


def model_errors(predictions: pd.DataFrame) -> pd.DataFrame:
    """Per spring, the RMS difference of the rigid baseline and of the extended model from the
    measured knee moment over the engine's window and strides (N·m)."""
    predictions = engine_sample(predictions)
    squares = pd.DataFrame({
        SPRING: predictions[SPRING],
        "baseline": (predictions["baseline_moment_Nm"] - predictions["measured_moment_Nm"]) ** 2,
        "extended": (predictions["extended_moment_Nm"] - predictions["measured_moment_Nm"]) ** 2,
    })  # fmt: skip
    return np.sqrt(squares.groupby(SPRING).mean())


def mean_loops(predictions: pd.DataFrame, spring: float) -> pd.DataFrame:
    """Mean phantom knee angle (deg) and measured and predicted moments over every stride of one
    spring in the table, per time in the window."""
    rows = predictions[predictions[SPRING] == spring]
    mean = rows.groupby("t_s").mean(numeric_only=True)
    return mean.assign(angle_deg=np.rad2deg(mean["phantom_knee_angle_rad"]))


def peak_panel(ax, summary_table: pd.DataFrame, protocol, reported, paper) -> None:
    """Measured peak stance moment per spring as ``summary.csv`` gives it (median and
    quartiles), with W.S.B. et al.'s medians and the model fitted to them beside it."""
    rows = summary_table[summary_table["metric"] == PEAK].sort_values(SPRING)
    kn = rows[SPRING].to_numpy() / 1000
    median = rows["median"].to_numpy()
    whiskers = [median - rows["q1"].to_numpy(), rows["q3"].to_numpy() - median]
    ax.errorbar(kn, median, yerr=whiskers, fmt="o-", color="black", ms=4, capsize=2, lw=1.0,
                label="measured, median [quartiles]")  # fmt: skip
    if paper is not None and len(paper):
        ax.plot(paper[SPRING] / 1000, paper["value"], "x", color="black", ms=7, mew=1.5,
                label=f"{PHANTOM.key} report (median)")  # fmt: skip
    if reported is not None:
        fitted = pd.DataFrame(reported["predictions"])
        ax.plot(fitted[SPRING] / 1000, fitted[PEAK], "s", mfc="none", color="#0072B2", ms=7,
                label=f"model fitted to {PHANTOM.key}'s medians")  # fmt: skip
    ax.set(xlabel="spring stiffness (kN/m)", ylabel="peak stance moment (N·m)")
    ax.legend(fontsize=7, loc="upper left")
    low, high = ax.dataLim.y0, ax.dataLim.y1
    span = max(high - low, 0.1 * abs(high), 1e-9)
    ax.set_ylim(low - 0.1 * span, high + 0.5 * span)  # room for the legend above the data
    ax.set_title(f"peak stance moment, {work_window(protocol)}\n"
                 f"{count_text(rows['n'])} included strides per spring", fontsize=8,
                 loc="left")  # fmt: skip


def error_panel(ax, predictions: pd.DataFrame) -> None:
    """Each model's RMS error in the knee moment per spring (log scale)."""
    errors = model_errors(predictions)
    kn = errors.index.to_numpy() / 1000
    for model in ("baseline", "extended"):
        ax.plot(
            kn, errors[model], marker="o", ms=4, label=MODEL_NAMES[model], **MODEL_STYLES[model]
        )
    ax.set_yscale("log")
    ax.set(xlabel="spring stiffness (kN/m)", ylabel="knee-moment error, RMS (N·m)")
    ax.legend(fontsize=7)
    ax.set_title(f"model error, {window_text(predictions)} of each stride\n"
                 f"{engine_strides(predictions)}", fontsize=8, loc="left")  # fmt: skip


def loop_panel(ax, predictions: pd.DataFrame, spring: float) -> None:
    """Work loops of one spring over every stride in the table: each stride's measured loop
    (thin), and the mean loop measured (wide, light), of the rigid theory and of the extended
    model (narrow, on top), the whole range of all in the axes."""
    rows = predictions[predictions[SPRING] == spring]
    for _, stride in rows.groupby(["trial", "stride"], sort=True):
        ax.plot(np.rad2deg(stride["phantom_knee_angle_rad"]), stride["measured_moment_Nm"],
                color="0.8", lw=0.3, zorder=0)  # fmt: skip
    mean = mean_loops(predictions, spring)
    for model in ("measured", "baseline", "extended"):
        ax.plot(mean["angle_deg"], mean[f"{model}_moment_Nm"], label=MODEL_NAMES[model],
                **MODEL_STYLES[model])  # fmt: skip
    ax.set(xlabel="phantom knee flexion (deg)", ylabel="knee moment (N·m)")
    strides = rows.groupby(["trial", "stride"]).ngroups
    ax.set_title(f"loops, {spring_label(spring)}, {window_text(predictions)}\n"
                 f"each of n = {strides} strides (thin) and their mean", fontsize=8,
                 loc="left")  # fmt: skip


def estimates_panel(ax, recordings: Mapping, reported: Mapping | None, sample: str) -> None:
    """Every estimate of the recordings' report with its 95 % interval, relative to the
    estimate; a fit bound marked, no whisker without an interval; the estimate of the same
    parameter from W.S.B. et al.'s medians beside it."""
    table = estimates(recordings)
    other = estimates(reported) if reported is not None else estimates({})
    other = other.drop_duplicates("parameter").set_index("parameter")["estimate"]
    kinds, drawn = set(), [0.0]
    for row, item in enumerate(table.itertuples()):
        style = STATUS[item.status]
        if not np.isnan(item.low):
            ends = relative([item.low, item.high], item.estimate)
            ax.plot(ends, [row, row], color="#0072B2", lw=1.2)
            ax.plot(ends, [row, row], "|", color="#0072B2", ms=8)
            drawn += list(ends)
        marker = BOUND_MARKERS.get(item.bound, style["marker"])
        colour = BOUND_COLOUR if item.bound else "#0072B2"
        ax.plot(0.0, row, marker, ms=7, color=colour, mfc=colour if item.bound else style["mfc"])
        kinds.add(("bound", item.bound) if item.bound else ("status", item.status))
        seed = other.get(item.parameter)
        if seed is not None:
            ax.plot(relative(seed, item.estimate), row, "s", mfc="none", color="#0072B2", ms=7)
            kinds.add(("seed", ""))
            drawn.append(float(relative(seed, item.estimate)))
    ax.set_yticks(range(len(table)), [estimate_label(r) for r in table.itertuples()],
                  fontsize=8)  # fmt: skip
    ax.set_ylim(max(len(table), 1) - 0.5, -0.5)
    ax.axvline(0.0, color="0.6", lw=0.8)
    ax.set_xlabel("(value − estimate) / |estimate| (%)")
    ax.set_title(f"estimates with 95 % intervals\n{sample}", fontsize=8, loc="left")
    if table.empty:
        ax.text(0.5, 0.5, "no effect claimed,\nheld tentatively or named", ha="center",
                va="center", transform=ax.transAxes, fontsize=9)  # fmt: skip
        return
    span = max(float(np.max(np.abs(drawn))), 1.0)
    ax.set_xlim(-1.15 * span, 1.15 * span)
    ax.legend(handles=estimate_key(kinds), fontsize=7, loc="upper center",
              bbox_to_anchor=(0.5, -0.13), borderaxespad=0.0)  # fmt: skip


def estimate_key(kinds: set) -> list:
    """Legend entries for the kinds of mark the estimates panel drew, and only those."""
    handles = []
    for status, style in STATUS.items():
        if ("status", status) in kinds:
            handles.append(Line2D([], [], ls="none", marker=style["marker"], color="#0072B2",
                                  mfc=style["mfc"], label=style["label"]))  # fmt: skip
    for side, marker in BOUND_MARKERS.items():
        if ("bound", side) in kinds:
            handles.append(Line2D([], [], ls="none", marker=marker, color=BOUND_COLOUR,
                                  label=f"estimate at its {side} fit bound"))  # fmt: skip
    if ("seed", "") in kinds:
        handles.append(Line2D([], [], ls="none", marker="s", mfc="none", color="#0072B2",
                              label=f"estimate from {PHANTOM.key}'s medians"))  # fmt: skip
    return handles


def discrepancy(
    predictions: pd.DataFrame,
    recordings: Mapping,
    summary_table: pd.DataFrame,
    protocol: Mapping,
    reported: Mapping | None = None,
    paper: pd.DataFrame | None = None,
):
    """Measured against the rigid theory and the extended model: (a) the peak stance moment per
    spring as ``summary.csv`` gives it (and W.S.B. et al.'s medians with the model fitted to them),
    (b) each model's RMS error per spring over the engine's window and strides, (c) every
    estimate with its interval, (d, e) the mean work loops of the softest and stiffest spring;
    one line on top: the error the extended model cuts most."""
    fig, panel = figures.new_mosaic(
        [["peak", "error", "estimates"], ["soft", "stiff", "estimates"]], width=13.0, height=6.6
    )
    peak_panel(panel["peak"], summary_table, protocol, reported, paper)
    error_panel(panel["error"], predictions)
    strides = int(engine_sample(predictions).groupby(SPRING)["stride"].nunique().sum())
    estimates_panel(panel["estimates"], recordings, reported,
                    f"{window_text(predictions)}, n = {strides} strides")  # fmt: skip
    springs = sorted(predictions[SPRING].unique())
    loop_panel(panel["soft"], predictions, springs[0])
    loop_panel(panel["stiff"], predictions, springs[-1])
    panel["soft"].legend(fontsize=7, loc="upper left")
    fig.suptitle(summary.title_block(recordings)[0], fontsize=10)
    return fig


def residuals(predictions: pd.DataFrame) -> pd.DataFrame:
    """Mean knee-moment residual of the extended model (measured − extended, N·m) per spring
    and time in the window, over the engine's strides."""
    predictions = engine_sample(predictions)
    rows = predictions.assign(
        residual=predictions["measured_moment_Nm"] - predictions["extended_moment_Nm"]
    )
    return rows.groupby([SPRING, "t_s"])["residual"].mean().unstack(SPRING)


def binned(x: np.ndarray, y: np.ndarray, bins: int = BINS) -> tuple[np.ndarray, ...]:
    """Means of x and y and the SD of y in quantile bins of x (bins without samples dropped)."""
    edges = np.quantile(x, np.linspace(0.0, 1.0, bins + 1))
    which = np.clip(np.searchsorted(edges, x, side="right") - 1, 0, bins - 1)
    count = np.bincount(which, minlength=bins)
    keep = count > 0
    mean_x = np.bincount(which, x, bins)[keep] / count[keep]
    mean_y = np.bincount(which, y, bins)[keep] / count[keep]
    square = np.bincount(which, y * y, bins)[keep] / count[keep]
    return mean_x, mean_y, np.sqrt(np.maximum(square - mean_y**2, 0.0))


def residual_panel(ax, predictions: pd.DataFrame, report: Mapping) -> None:
    """What the extended model leaves in the knee moment: the mean residual per spring over the
    window, against the noise (± 1 SD of the disengaged swing's knee moment)."""
    table = residuals(predictions)
    noise = float(report.get("noise_scales", {}).get("moment_Nm", np.nan))
    times = table.index.to_numpy()
    if np.isfinite(noise):
        ax.fill_between(times, -noise, noise, color="0.85", lw=0, label="± 1 SD of the noise")
    colours = figures.ordered_colours(len(table.columns))
    for colour, spring in zip(colours, table.columns, strict=True):
        ax.plot(times, table[spring], color=colour, lw=1.0, label=spring_label(spring))
    ax.axhline(0.0, color="k", lw=0.5)
    ax.set(xlabel="time from the stride's start (s)",
           ylabel="knee moment, measured − extended (N·m)")  # fmt: skip
    ax.legend(fontsize=7, loc="upper left", bbox_to_anchor=(1.02, 1.0), borderaxespad=0.0)
    ax.set_title(f"left by the extended model, {window_text(predictions)}\n"
                 f"mean over {engine_strides(predictions)}", fontsize=8, loc="left")  # fmt: skip


def term_panel(ax, table: pd.DataFrame, entry: Mapping, kind: str, window: str,
               names: Mapping) -> None:  # fmt: skip
    """One discovered term, in the observable where its correction is largest: the residual of
    the model without it (before) and with it (after) against its correction, binned."""
    rows = table[table["term"] == entry["term"]]
    sizes = {
        obs: float(np.std(group[f"correction_{OBSERVABLES[obs]}"]))
        for obs, group in rows.groupby("observable")
    }
    obs = max(sizes, key=sizes.get)
    unit, group = OBSERVABLES[obs], rows[rows["observable"] == obs]
    x = group[f"correction_{unit}"].to_numpy()
    for which, colour in (("before", "0.5"), ("after", "#0072B2")):
        mx, my, sd = binned(x, group[f"residual_{which}_{unit}"].to_numpy())
        ax.errorbar(mx, my, yerr=sd, fmt="o", ms=3, color=colour, lw=0.8,
                    label=f"residual {which} the term")  # fmt: skip
    span = np.array([x.min(), x.max()])
    ax.plot(span, span, "k:", lw=0.8, label="residual = correction")
    ax.axhline(0.0, color="k", lw=0.5)
    shown = summary.unit_text(unit)
    ax.set(xlabel=f"correction of the term ({shown})",
           ylabel=f"{names.get(obs, 'observable')}, measured − model ({shown})")  # fmt: skip
    strides = group[["trial", "stride"]].drop_duplicates().shape[0]
    title = f"{short_name(entry['description'])} ({kind}; gain {entry['gain']['gain_pct']:.0f} %)"
    ax.set_title("\n".join(textwrap.wrap(title, 44)) + f"\n{window}, n = {strides} strides",
                 fontsize=8, loc="left")  # fmt: skip
    ax.legend(fontsize=7)


def terms_figure(table: pd.DataFrame, predictions: pd.DataFrame, report: Mapping):
    """What the extended model leaves in the knee moment (panel a), then per discovered term
    (named, else proposed) its correction against the residual it explains."""
    named = report.get("discovery", {}).get("named", [])
    entries = [*((e, "named") for e in named),
               *((e, "proposed, not named") for e in report.get("discovery", {}).get(
                   "proposed", []))]  # fmt: skip
    fig, axes = figures.new_figure(1 + len(entries), 1, width=5.6 + 4.2 * len(entries),
                                   height=3.8)  # fmt: skip
    residual_panel(axes[0, 0], predictions, report)
    for ax, (entry, kind) in zip(axes[0, 1:], entries, strict=True):
        term_panel(ax, table, entry, kind, window_text(predictions),
                   report.get("observable_names", {}))  # fmt: skip
    return fig
