"""Figures of seed 000's results (figures 5–11) from curves, summary and statistics tables."""

from __future__ import annotations

import re
from collections.abc import Mapping

import numpy as np
import pandas as pd

from exobench import figures
from exobench.phantom.metrics import COMPONENTS
from exobench.phantom.statistics import SPRING

POWER_WINDOW_PCT = 45.0


def spring_label(spring: float) -> str:
    """Legend label of a spring, in kN/m."""
    return f"{spring / 1000:.1f} kN/m"


class Figures:
    """Tables the figures draw from, and the shared bar and curve helpers."""

    def __init__(self, curves: pd.DataFrame, summary: pd.DataFrame, marks: pd.DataFrame, protocol):
        self.curves, self.summary, self.marks = curves, summary, marks
        self.springs = sorted(curves[SPRING].unique())
        self.colours = dict(
            zip(self.springs, figures.ordered_colours(len(self.springs)), strict=True)
        )
        self.clutch = (float(protocol["clutch_on_pct"]), float(protocol["clutch_off_pct"]))
        self.mark_edges: dict[int, set] = {}

    def curve(self, spring: float) -> pd.DataFrame:
        return self.curves[self.curves[SPRING] == spring]

    def shade_clutch(self, ax) -> None:
        ax.axvspan(*self.clutch, color="0.9", zorder=0, label="_clutch")

    def mean_curves(self, ax, signal: str, ylabel: str, window: float | None = None) -> None:
        """Mean curve of one signal for every spring, SD band, clutch window shaded."""
        self.shade_clutch(ax)
        for spring in self.springs:
            rows = self.curve(spring)
            if window is not None:
                rows = rows[rows["gait_cycle_pct"] <= window]
            x, mean, sd = rows["gait_cycle_pct"], rows[f"mean_{signal}"], rows[f"sd_{signal}"]
            ax.plot(x, mean, color=self.colours[spring], lw=1.2, label=spring_label(spring))
            ax.fill_between(x, mean - sd, mean + sd, color=self.colours[spring], alpha=0.12, lw=0)
        ax.set(xlabel="gait cycle (%)", ylabel=ylabel)

    def bars(self, ax, metric: str, ylabel: str, width: float = 0.8):
        """Mean ± SD bars per spring with seed 000's significance marks at the axes' edge."""
        rows = self.summary[self.summary["metric"] == metric].set_index(SPRING).loc[self.springs]
        marks = self.marks[self.marks["metric"] == metric].set_index(SPRING)["notation"]
        x = np.arange(len(self.springs))
        colours = [self.colours[s] for s in self.springs]
        ax.bar(
            x, rows["mean"], width, yerr=rows["sd"], color=colours, capsize=2, error_kw={"lw": 0.8}
        )
        edges = self.mark_edges.setdefault(id(ax), set())
        for xi, mean, spring in zip(x, rows["mean"], self.springs, strict=True):
            mark = wrap_marks(marks.get(spring, ""))
            if not mark:
                continue
            edge = "top" if mean >= 0 else "bottom"
            edges.add(edge)
            ax.annotate(
                mark,
                (xi, 0.985 if edge == "top" else 0.015),
                xycoords=("data", "axes fraction"),
                ha="center",
                va="top" if edge == "top" else "bottom",
                fontsize=5.5,
                linespacing=0.9,
            )
        ax.set_xticks(x, [f"{s / 1000:.1f}" for s in self.springs])
        ax.tick_params(axis="x", labelsize=7)
        ax.set(xlabel="spring stiffness (kN/m)", ylabel=ylabel)
        low, high = min(ax.dataLim.y0, 0.0), max(ax.dataLim.y1, 0.0)
        room = 0.3 * (high - low)
        ax.set_ylim(low - room * ("bottom" in edges), high + room * ("top" in edges))
        return rows


def wrap_marks(mark: str, per_line: int = 2) -> str:
    """Significance marks two groups a line, e.g. (1)(2)(3) -> (1)(2) / (3)."""
    groups = re.findall(r"\([^)]*\)", mark)
    return "\n".join("".join(groups[i : i + per_line]) for i in range(0, len(groups), per_line))


def kinematics(fig_tables: Figures):
    """Figure 5: mean knee angles over the cycle and stance flexion (phantom, exoskeleton)."""
    fig, axes = figures.new_figure(2, 2, width=7.5, height=5.5)
    fig_tables.mean_curves(axes[0, 0], "phantom_knee_angle_deg", "phantom knee flexion (deg)")
    fig_tables.bars(axes[0, 1], "phantom_stance_flexion_deg", "phantom stance flexion (deg)")
    fig_tables.mean_curves(axes[1, 0], "exo_knee_angle_deg", "exoskeleton knee flexion (deg)")
    fig_tables.bars(axes[1, 1], "exo_stance_flexion_deg", "exoskeleton stance flexion (deg)")
    axes[0, 0].legend(fontsize=6, ncols=2)
    return fig


def kinetics(fig_tables: Figures):
    """Figure 6: mean knee moment over the cycle and peak stance moment."""
    fig, axes = figures.new_figure(2, 1, width=7.5, height=3.0)
    fig_tables.mean_curves(axes[0, 0], "knee_moment_Nm", "knee moment, extensor + (N·m)")
    fig_tables.bars(axes[0, 1], "peak_moment_Nm", "peak stance moment (N·m)")
    axes[0, 0].legend(fontsize=6, ncols=2)
    return fig


def assistance(fig_tables: Figures):
    """Figure 7: work loops (moment over angle) and stiffness, phantom and exoskeleton."""
    fig, axes = figures.new_figure(2, 2, width=7.5, height=5.5)
    for row, (who, label) in enumerate((("phantom", "phantom"), ("exo", "exoskeleton"))):
        ax = axes[row, 0]
        for spring in fig_tables.springs:
            rows = fig_tables.curve(spring)
            ax.plot(
                rows[f"mean_{who}_knee_angle_deg"],
                rows["mean_knee_moment_Nm"],
                color=fig_tables.colours[spring],
                lw=1.0,
                label=spring_label(spring),
            )
        ax.set(xlabel=f"{label} knee flexion (deg)", ylabel="knee moment (N·m)")
        fig_tables.bars(axes[row, 1], f"{who}_stiffness_Nm_per_rad", f"{label} stiffness (N·m/rad)")
    axes[0, 0].legend(fontsize=6, ncols=2)
    return fig


def power_by_spring(fig_tables: Figures):
    """Figure 8: mean power of every component during 0–45 % of the cycle, one panel a spring."""
    count = len(fig_tables.springs)
    fig, axes = figures.new_figure(3, int(np.ceil(count / 3)), width=7.5, height=4.5)
    panels = axes.ravel()
    for ax, spring in zip(panels, fig_tables.springs, strict=False):
        rows = fig_tables.curve(spring)
        rows = rows[rows["gait_cycle_pct"] <= POWER_WINDOW_PCT]
        for component in COMPONENTS:
            ax.plot(
                rows["gait_cycle_pct"],
                rows[f"mean_power_{component}_W"],
                lw=1.0,
                color=figures.COMPONENT_COLOURS[component],
                label=component,
            )
        ax.axhline(0, color="0.5", lw=0.5)
        ax.set(title=spring_label(spring), xlabel="gait cycle (%)", ylabel="power (W)")
    for ax in panels[count:]:
        ax.set_visible(False)
    panels[0].legend(fontsize=6)
    share_y(panels[:count])
    return fig


def power_by_component(fig_tables: Figures):
    """Figure 9: mean power of each component during 0–45 % of the cycle for every spring."""
    fig, axes = figures.new_figure(3, 2, width=7.5, height=4.5)
    panels = axes.ravel()
    for ax, component in zip(panels, COMPONENTS, strict=False):
        fig_tables.mean_curves(ax, f"power_{component}_W", "power (W)", window=POWER_WINDOW_PCT)
        ax.axhline(0, color="0.5", lw=0.5)
        ax.set_title(component)
    panels[-1].set_visible(False)
    panels[0].legend(fontsize=6, ncols=2)
    share_y(panels[: len(COMPONENTS)])
    return fig


def work(fig_tables: Figures):
    """Figure 10: positive and negative work bars per spring, net work as a white line."""
    fig, axes = figures.new_figure(3, 2, width=7.5, height=5.0)
    panels = axes.ravel()
    for ax, component in zip(panels, COMPONENTS, strict=False):
        for kind in ("positive", "negative"):
            fig_tables.bars(ax, f"work_{component}_{kind}_J", "work (J)")
        net = fig_tables.summary[fig_tables.summary["metric"] == f"work_{component}_net_J"]
        net = net.set_index(SPRING).loc[fig_tables.springs, "mean"]
        for x, value in enumerate(net):
            ax.plot([x - 0.4, x + 0.4], [value, value], color="white", lw=2.0)
            ax.plot([x - 0.4, x + 0.4], [value, value], color="black", lw=0.6)
        ax.axhline(0, color="0.3", lw=0.6)
        ax.set_title(component)
    panels[-1].set_visible(False)
    return fig


def relative_work(fig_tables: Figures):
    """Figure 11: shares of interface, spring and frame in the positive and negative work."""
    count = len(fig_tables.springs)
    fig, axes = figures.new_figure(count, 2, width=7.5, height=3.2)
    parts = ("interface", "spring", "frame")
    summary = fig_tables.summary.set_index(["metric", SPRING])["mean"]
    for column, spring in enumerate(fig_tables.springs):
        for row, kind in enumerate(("positive", "negative")):
            values = np.array([abs(summary[(f"work_{p}_{kind}_J", spring)]) for p in parts])
            ax = axes[row, column]
            ax.pie(
                values,
                colors=[figures.COMPONENT_COLOURS[p] for p in parts],
                autopct="%1.0f%%",
                textprops={"fontsize": 6},
                startangle=90,
            )
            ax.set_title(f"{spring_label(spring)}\n{kind}", fontsize=7)
    fig.legend(parts, loc="outside lower center", ncols=3, fontsize=7)
    return fig


def share_y(panels) -> None:
    """Give panels a common y range."""
    low = min(ax.get_ylim()[0] for ax in panels)
    high = max(ax.get_ylim()[1] for ax in panels)
    for ax in panels:
        ax.set_ylim(low, high)


FIGURES: Mapping[str, object] = {
    "fig05_kinematics": kinematics,
    "fig06_kinetics": kinetics,
    "fig07_assistance": assistance,
    "fig08_power_by_spring": power_by_spring,
    "fig09_power_by_component": power_by_component,
    "fig10_work": work,
    "fig11_relative_work": relative_work,
}


MODEL_STYLES = {
    "measured": {"color": "black", "lw": 1.6, "ls": "-"},
    "baseline": {"color": "#D55E00", "lw": 1.2, "ls": "--"},
    "extended": {"color": "#0072B2", "lw": 1.2, "ls": "-."},
}


def discrepancy(predictions: pd.DataFrame, recordings: Mapping, reported: Mapping):
    """Measured vs rigid baseline vs extended model: peak moment and work loops."""
    fig, axes = figures.new_figure(3, 1, width=9.0, height=3.2)
    peaks = predictions.groupby([SPRING, "stride"]).max(numeric_only=True)
    medians = peaks.groupby(SPRING).median()
    ax = axes[0, 0]
    kn = medians.index.to_numpy() / 1000
    for model in MODEL_STYLES:
        ax.plot(
            kn, medians[f"{model}_moment_Nm"], marker="o", ms=3, label=model, **MODEL_STYLES[model]
        )
    paper = pd.DataFrame(reported["predictions"])
    ax.plot(
        paper[SPRING] / 1000,
        paper["peak_moment_Nm"],
        "s",
        mfc="none",
        color="#0072B2",
        label="extended, fitted to seed 000",
    )
    ax.set_yscale("log")
    ax.set(
        xlabel="spring stiffness (kN/m)",
        ylabel="peak knee moment (N·m)",
        title="peak moment (median over strides)",
    )
    ax.legend(fontsize=6)
    springs = sorted(predictions[SPRING].unique())
    for ax, spring in zip(axes[0, 1:], (springs[0], springs[-1]), strict=True):
        rows = predictions[predictions[SPRING] == spring]
        mean = rows.groupby("t_s").mean(numeric_only=True)
        angle = np.rad2deg(mean["phantom_knee_angle_rad"])
        for model in MODEL_STYLES:
            ax.plot(angle, mean[f"{model}_moment_Nm"], label=model, **MODEL_STYLES[model])
        ax.set(
            xlabel="phantom knee flexion (deg)",
            ylabel="knee moment (N·m)",
            title=f"work loop, {spring_label(spring)}",
        )
        top = 1.3 * mean["measured_moment_Nm"].max()
        ax.set_ylim(-0.05 * top, top)
    fig.suptitle(
        f"recordings — {verdict_line(recordings)}\nseed 000 medians — {verdict_line(reported)}",
        fontsize=7,
    )
    return fig


def verdict_line(report: Mapping) -> str:
    """Effects found and what is left unexplained, in a few words for a figure title."""
    found = ", ".join(f["effect"].replace("_", " ") for f in report["effects_found"]) or "none"
    left = report["unexplained"]
    if not left["flag"]:
        return f"effects found: {found}; nothing left unexplained"
    tentative = ", ".join(f["effect"].replace("_", " ") for f in report["tentative"])
    return (
        f"effects found: {found}"
        + (f" (tentative: {tentative})" if tentative else "")
        + f"; UNEXPLAINED: {left['observable']} residual vs {left['correlates_with']}"
    )
