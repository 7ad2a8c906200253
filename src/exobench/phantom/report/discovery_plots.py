"""Figures of the model discrepancy: measured against the rigid theory and the selected model
over the engine's window, with every estimate's interval; and each discovered term's correction
against the residual it explains."""

from __future__ import annotations

import textwrap
from collections.abc import Mapping

import numpy as np
import pandas as pd

from exobench import figures
from exobench.phantom.model.effects import OBSERVABLES
from exobench.phantom.report.plots import spring_label
from exobench.phantom.study.statistics import SPRING
from exobench.selection import summary
from exobench.studies import PHANTOM

MEDIANS = f"{PHANTOM.key}'s medians"

BINS = 20  # quantile bins of a term's correction in the figure


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


def terms_figure(table: pd.DataFrame, report: Mapping):
    """Per discovered term (named, else proposed) and the observable its correction is largest
    in: the residual of the model without the term (before) and with it (after) against the
    correction the term makes, binned; a term that explains the residual puts 'before' on the
    diagonal and 'after' on zero."""
    entries = [*report["discovery"]["named"], *report["discovery"]["proposed"]]
    fig, axes = figures.new_figure(max(len(entries), 1), 1, width=3.2 * max(len(entries), 1),
                                   height=3.4)  # fmt: skip
    if not entries:
        ax = axes[0, 0]
        ax.set_axis_off()
        why = (
            "no library term removes the structure left unexplained"
            if report["discovery"]["searched"]
            else "the registry leaves nothing unexplained, the library was not searched"
        )
        ax.text(0.5, 0.5, f"no discovered term: {why}", ha="center", va="center", wrap=True,
                fontsize=8, transform=ax.transAxes)  # fmt: skip
        return fig
    for letter, ax, entry in zip("abcdefgh", axes[0], entries, strict=False):
        rows = table[table["term"] == entry["term"]]
        best, unit = None, None
        for obs, group in rows.groupby("observable"):
            size = float(np.std(group[f"correction_{OBSERVABLES[obs]}"]))
            if best is None or size > best[0]:
                best, unit = (size, obs, group), OBSERVABLES[obs]
        _, obs, group = best
        x = group[f"correction_{unit}"].to_numpy()
        for kind, colour in (("before", "0.5"), ("after", "#0072B2")):
            mx, my, sd = binned(x, group[f"residual_{kind}_{unit}"].to_numpy())
            ax.errorbar(mx, my, yerr=sd, fmt="o", ms=3, color=colour, lw=0.8,
                        label=f"residual {kind} the term")  # fmt: skip
        span = np.array([x.min(), x.max()])
        ax.plot(span, span, "k:", lw=0.8, label="residual = correction")
        ax.axhline(0.0, color="k", lw=0.5)
        ax.set(xlabel=f"correction of the term ({unit})",
               ylabel=f"{obs} residual, measured − model ({unit})")  # fmt: skip
        kind = "named" if entry in report["discovery"]["named"] else "proposed, not named"
        ax.set_title(f"({letter}) " + "\n".join(textwrap.wrap(
            f"{entry['description']} ({kind}; gain {entry['gain']['gain_pct']:.0f} %)", 40)),
            fontsize=7, loc="left")  # fmt: skip
        ax.legend(fontsize=6)
    return fig


MODEL_STYLES = {
    "measured": {"color": "black", "lw": 1.6, "ls": "-"},
    "baseline": {"color": "#D55E00", "lw": 1.2, "ls": "--"},
    "extended": {"color": "#0072B2", "lw": 1.2, "ls": "-."},
}


def discrepancy(predictions: pd.DataFrame, recordings: Mapping, reported: Mapping | None):
    """Measured vs rigid baseline vs extended model over the engine's window: each stride's
    largest moment there, the mean work loops of the softest and stiffest spring, and every
    claimed (or tentative) parameter with its 95 % interval; the verdict's lines on top (with
    ``reported``, the model fitted to W.S.B. et al.'s medians beside them)."""
    fig, axes = figures.new_figure(4, 1, width=12.5, height=3.4)
    window = f"{predictions['t_s'].min():g}–{predictions['t_s'].max():g} s"
    per_spring = predictions.groupby(SPRING)["stride"].nunique()
    spread = "" if per_spring.nunique() == 1 else f"–{per_spring.max()}"
    count = f"n = {per_spring.min()}{spread} strides/spring"
    peaks = predictions.groupby([SPRING, "stride"]).max(numeric_only=True)
    medians = peaks.groupby(SPRING).median()
    ax = axes[0, 0]
    kn = medians.index.to_numpy() / 1000
    for model in MODEL_STYLES:
        ax.plot(
            kn, medians[f"{model}_moment_Nm"], marker="o", ms=3, label=model, **MODEL_STYLES[model]
        )
    if reported is not None:
        paper = pd.DataFrame(reported["predictions"])
        ax.plot(paper[SPRING] / 1000, paper["peak_moment_Nm"], "s", mfc="none", color="#0072B2",
                label=f"model of {MEDIANS} (stance peak)")  # fmt: skip
    ax.set_yscale("log")
    ax.set(xlabel="spring stiffness (kN/m)", ylabel="window peak knee moment (N·m)")
    ax.set_title(f"window peak (median)\n{window}, {count}", fontsize=8)
    ax.legend(fontsize=6)
    springs = sorted(predictions[SPRING].unique())
    for ax, spring in zip(axes[0, 1:3], (springs[0], springs[-1]), strict=True):
        rows = predictions[predictions[SPRING] == spring]
        mean = rows.groupby("t_s").mean(numeric_only=True)
        angle = np.rad2deg(mean["phantom_knee_angle_rad"])
        for model in MODEL_STYLES:
            ax.plot(angle, mean[f"{model}_moment_Nm"], label=model, **MODEL_STYLES[model])
        ax.set(xlabel="phantom knee flexion (deg)", ylabel="knee moment (N·m)")
        ax.set_title(f"mean loop, {spring_label(spring)}\n{window}, n = {per_spring[spring]} "
                     "strides", fontsize=8)  # fmt: skip
        top = 1.3 * mean["measured_moment_Nm"].max()
        ax.set_ylim(-0.05 * top, top)
    intervals(axes[0, 3], recordings, reported, f"{window}, n = {int(per_spring.sum())} strides")
    lines = [f"recordings — {line}" if i == 0 else line
             for i, line in enumerate(summary.title_block(recordings))]  # fmt: skip
    if reported is not None:
        lines.append(f"{MEDIANS} — {summary.title_block(reported)[0]}")
    fig.suptitle("\n".join(lines), fontsize=7)
    return fig


def intervals(ax, recordings: Mapping, reported: Mapping | None, sample: str) -> None:
    """Every parameter the recordings' report claims (or holds tentatively) with its 95 %
    interval, relative to its estimate (log scale), the values in the labels; the reported
    medians' estimate of the same parameter beside it."""
    fits = {"recordings": summary.as_fit(recordings)}
    if reported is not None:
        fits[MEDIANS] = summary.as_fit(reported)
    own = fits["recordings"]
    names = list(own["parameters"])
    for row, name in enumerate(names):
        value, (low, high) = own["parameters"][name], own["ci95"][name]
        ax.errorbar(1.0, row, xerr=[[1.0 - low / value], [high / value - 1.0]], fmt="o", ms=3,
                    color="#0072B2", capsize=2)  # fmt: skip
        other = fits.get(MEDIANS, {"parameters": {}})["parameters"].get(name)
        if other is not None and value > 0 and other > 0:
            ax.plot(other / value, row, "s", mfc="none", color="#0072B2", ms=4)
    bounds = summary.bounds_of(recordings)
    values = [summary.interval_text(own["parameters"][n], own["ci95"][n], own["units"][n],
                                    bounds.get(n)) for n in names]  # fmt: skip
    labels = [f"{n}\n{v}" for n, v in zip(names, values, strict=True)]
    ax.set_yticks(range(len(names)), labels, fontsize=5)
    ax.invert_yaxis()
    ax.set_xscale("log")
    ax.axvline(1.0, color="0.6", lw=0.8)
    ax.set(xlabel="value / estimate")
    ax.set_title(f"estimates, 95 % intervals\n{sample}", fontsize=8)
    if not names:
        ax.text(0.5, 0.5, "no effect claimed", transform=ax.transAxes, ha="center")
