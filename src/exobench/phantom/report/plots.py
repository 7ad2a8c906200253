"""Figures of W.S.B. et al.'s results (figures 5–11) from curves, summary and statistics tables,
each with its caption: every panel states its window and its strides."""

from __future__ import annotations

import re
from collections.abc import Mapping

import matplotlib
import numpy as np
import pandas as pd
from matplotlib.lines import Line2D
from matplotlib.patches import Patch

from exobench import figures
from exobench.phantom.chain.metrics import COMPONENTS
from exobench.phantom.rig import MARKERS, REQUIRED_ANALOGS
from exobench.phantom.study.statistics import SPRING
from exobench.studies import PHANTOM

BARS = "Bars: mean over the included strides; whiskers: ± 1 SD (stride-to-stride spread)."
OUTLIER_STYLE = {"ls": "none", "marker": "x", "color": "#D55E00", "ms": 4, "mew": 1.0}


def spring_label(spring: float) -> str:
    """Legend label of a spring, in kN/m."""
    return f"{spring / 1000:.1f} kN/m"


def count_text(counts) -> str:
    """Strides per spring as a panel states them: 'n = 150' or 'n = 131–133'."""
    low, high = int(min(counts)), int(max(counts))
    return f"n = {low}" if low == high else f"n = {low}–{high}"


class Figures:
    """Tables the figures draw from, the windows and stride counts their panels state, and the
    shared bar and curve helpers."""

    def __init__(
        self,
        curves: pd.DataFrame,
        summary: pd.DataFrame,
        marks: pd.DataFrame,
        protocol,
        alpha,
        outliers: pd.DataFrame | None = None,
    ):
        self.curves, self.summary, self.marks, self.alpha = curves, summary, marks, alpha
        self.outliers = (
            outliers if outliers is not None else pd.DataFrame(columns=["metric", SPRING, "value"])
        )
        self.springs = sorted(curves[SPRING].unique())
        self.colours = dict(
            zip(self.springs, figures.ordered_colours(len(self.springs)), strict=True)
        )
        self.clutch = (float(protocol["clutch_on_pct"]), float(protocol["clutch_off_pct"]))
        self.work_pct = 100.0 * float(protocol["work_window_s"]) / float(protocol["stride_time_s"])
        self.work_s = float(protocol["work_window_s"])
        self.mark_edges: dict[int, set] = {}
        self.spans: dict[int, list] = {}  # per panel, every value its bars and marks reach

    def curve(self, spring: float) -> pd.DataFrame:
        return self.curves[self.curves[SPRING] == spring]

    def curve_strides(self) -> str:
        """Strides behind the mean curves, per spring."""
        return count_text(self.curves.groupby(SPRING)["n_strides"].first())

    def metric_strides(self, metric: str) -> str:
        """Strides behind a metric's bars, per spring."""
        return count_text(self.summary.loc[self.summary["metric"] == metric, "n"])

    def clutch_text(self) -> str:
        return f"clutch window {self.clutch[0]:g}–{self.clutch[1]:g} % of the cycle"

    def clutch_short(self) -> str:
        return f"{self.clutch[0]:g}–{self.clutch[1]:g} % of cycle (clutch)"

    def work_text(self) -> str:
        return f"0–{self.work_pct:g} % of the cycle (first {self.work_s:g} s)"

    def work_short(self) -> str:
        return f"0–{self.work_pct:g} % of cycle"

    def shade_clutch(self, ax) -> None:
        ax.axvspan(*self.clutch, color="0.9", zorder=0, label="_clutch")

    def mean_curves(self, ax, signal: str, ylabel: str, window: float | None = None) -> None:
        """Mean curve of one signal for every spring, SD band, clutch window shaded; the title
        states the window and the strides."""
        self.shade_clutch(ax)
        for spring in self.springs:
            rows = self.curve(spring)
            if window is not None:
                rows = rows[rows["gait_cycle_pct"] <= window]
            x, mean, sd = rows["gait_cycle_pct"], rows[f"mean_{signal}"], rows[f"sd_{signal}"]
            ax.plot(x, mean, color=self.colours[spring], lw=1.2, label=spring_label(spring))
            ax.fill_between(x, mean - sd, mean + sd, color=self.colours[spring], alpha=0.12, lw=0)
        span = "0–100" if window is None else f"0–{window:g}"
        ax.set(xlabel="gait cycle (%)", ylabel=ylabel)
        panel_note(ax, f"mean ± SD, {span} % of cycle", f"{self.curve_strides()} per spring")

    def outlier_points(self, metric: str) -> tuple[np.ndarray, np.ndarray]:
        """Each stride flagged as an outlier in ``metric``: its spring's bar position and value."""
        rows = self.outliers[self.outliers["metric"] == metric]
        x = np.array([self.springs.index(s) for s in rows[SPRING]], float)
        return x, rows["value"].to_numpy(float)

    def mark_outliers(self, ax, metric: str) -> list:
        """Draw the strides flagged in ``metric`` (×) and return the panel's drawn values so far
        (zero, every whisker's end and every flagged value)."""
        x, values = self.outlier_points(metric)
        if x.size:
            ax.plot(x, values, **OUTLIER_STYLE)
        drawn = self.spans.setdefault(id(ax), [0.0])
        drawn += list(values)
        return drawn

    def outlier_note(self, metrics) -> str:
        """What the outlier marks are and how many the figure draws (the caption's sentence)."""
        count = int(self.outliers["metric"].isin(list(metrics)).sum())
        drawn = (
            f"×: the {count} stride values flagged as outliers in the panel's metrics"
            if count
            else "No stride is flagged as an outlier in these metrics"
        )
        return (
            f"{drawn} (``outliers.csv``: beyond the configured robust z of their spring's "
            "median, each with its reason; kept in the bars, as in the statistics). Every axis "
            "holds every bar, whisker and flagged stride: nothing is clipped."
        )

    def bars(self, ax, metric: str, ylabel: str, window: str, width: float = 0.8):
        """Mean ± SD bars per spring with W.S.B. et al.'s significance marks at the axes' edge and
        the strides flagged as outliers marked at their values; the title states the metric's
        window and its strides. The axis holds every whisker and outlier, with a margin."""
        rows = self.summary[self.summary["metric"] == metric].set_index(SPRING).loc[self.springs]
        marks = self.marks[self.marks["metric"] == metric].set_index(SPRING)["notation"]
        x = np.arange(len(self.springs))
        colours = [self.colours[s] for s in self.springs]
        ax.bar(
            x, rows["mean"], width, yerr=rows["sd"], color=colours, capsize=2, error_kw={"lw": 0.8}
        )
        drawn = self.mark_outliers(ax, metric)
        drawn += [*(rows["mean"] - rows["sd"]), *(rows["mean"] + rows["sd"])]
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
        panel_note(ax, f"mean ± SD, {window}", f"{self.metric_strides(metric)} per spring")
        low, high = float(np.nanmin(drawn)), float(np.nanmax(drawn))
        room, margin = 0.3 * (high - low), 0.05 * (high - low)
        ax.set_ylim(
            low - margin - room * ("bottom" in edges), high + margin + room * ("top" in edges)
        )
        return rows

    def notation(self) -> str:
        """What the significance marks mean, springs numbered by stiffness."""
        numbers = ", ".join(f"({i}) {s / 1000:.1f}" for i, s in enumerate(self.springs, 1))
        return (
            "Marks above a bar (below a negative one): (i) the spring's strides differ from "
            f"those of spring i, numbered by stiffness: {numbers} kN/m; (*) they differ from "
            f"every other spring. Two-sided Dunn tests with Bonferroni correction, p < "
            f"{self.alpha:g}, on the included strides (``stats/notation.csv``; p-values per "
            "metric in ``stats/dunn/``; Kruskal–Wallis across springs in ``stats/kruskal.csv``)."
        )

    def sources(self) -> str:
        return (
            "Included strides only (``strides/``, column ``included``); numbers in "
            "``summary.csv`` (median, quartiles, mean, SD, n per spring and metric)."
        )


def wrap_marks(mark: str, per_line: int = 2) -> str:
    """Significance marks two groups a line, e.g. (1)(2)(3) -> (1)(2) / (3)."""
    groups = re.findall(r"\([^)]*\)", mark)
    return "\n".join("".join(groups[i : i + per_line]) for i in range(0, len(groups), per_line))


def kinematics(t: Figures):
    """Figure 5: mean knee angles over the cycle and stance flexion (phantom, exoskeleton)."""
    fig, axes = figures.new_figure(2, 2, width=7.5, height=5.5)
    window = t.clutch_short()
    t.mean_curves(axes[0, 0], "phantom_knee_angle_deg", "phantom knee flexion (deg)")
    t.bars(axes[0, 1], "phantom_stance_flexion_deg", "phantom stance flexion (deg)", window)
    t.mean_curves(axes[1, 0], "exo_knee_angle_deg", "exoskeleton knee flexion (deg)")
    t.bars(axes[1, 1], "exo_stance_flexion_deg", "exoskeleton stance flexion (deg)", window)
    axes[0, 0].legend(fontsize=6, ncols=2)
    caption = (
        f"Figure 5 of {PHANTOM.key}, reproduced: knee kinematics per spring.",
        "Panels (a) and (c): phantom and exoskeleton knee flexion over the whole gait cycle: mean "
        "(line) "
        f"± SD (band) per spring; the {t.clutch_text()} is shaded.",
        "Panels (b) and (d): phantom and exoskeleton stance flexion, each stride's peak angle in "
        "the "
        f"{t.clutch_text()} minus its initial angle. {BARS}",
        t.notation(),
        t.outlier_note(["phantom_stance_flexion_deg", "exo_stance_flexion_deg"]),
        t.sources(),
    )
    return fig, caption


def kinetics(t: Figures):
    """Figure 6: mean knee moment over the cycle and peak stance moment."""
    fig, axes = figures.new_figure(2, 1, width=7.5, height=3.2)
    t.mean_curves(axes[0, 0], "knee_moment_Nm", "knee moment, extensor + (N·m)")
    t.bars(axes[0, 1], "peak_moment_Nm", "peak stance moment (N·m)", t.work_short())
    axes[0, 0].legend(fontsize=6, ncols=2)
    caption = (
        f"Figure 6 of {PHANTOM.key}, reproduced: net knee moment (extensor positive) per spring.",
        "Panel (a): knee moment over the whole gait cycle, mean (line) ± SD (band) per spring; the "
        f"{t.clutch_text()} is shaded.",
        f"Panel (b): peak stance moment, each stride's largest knee moment over {t.work_text()} "
        f"(``peak_moment_Nm`` in ``summary.csv``). {BARS}",
        t.notation(),
        t.outlier_note(["peak_moment_Nm"]),
        t.sources(),
    )
    return fig, caption


def assistance(t: Figures):
    """Figure 7: work loops (moment over angle) in the clutch window and stiffness."""
    fig, axes = figures.new_figure(2, 2, width=7.5, height=5.5)
    window = t.clutch_short()
    for row, (who, label) in enumerate((("phantom", "phantom"), ("exo", "exoskeleton"))):
        ax = axes[row, 0]
        for spring in t.springs:
            rows = t.curve(spring)
            rows = rows[rows["gait_cycle_pct"].between(*t.clutch)]
            ax.plot(
                rows[f"mean_{who}_knee_angle_deg"],
                rows["mean_knee_moment_Nm"],
                color=t.colours[spring],
                lw=1.0,
                label=spring_label(spring),
            )
        ax.set(xlabel=f"{label} knee flexion (deg)", ylabel="knee moment (N·m)")
        panel_note(ax, f"mean, {t.clutch_short()}", f"{t.curve_strides()} per spring")
        t.bars(axes[row, 1], f"{who}_stiffness_Nm_per_rad", f"{label} stiffness (N·m/rad)", window)
    axes[0, 0].legend(fontsize=6, ncols=2)
    caption = (
        f"Figure 7 of {PHANTOM.key}, reproduced: assistance of the exoskeleton per spring.",
        "Panels (a) and (c): phantom and exoskeleton work loops, mean knee moment against mean "
        "knee "
        f"flexion over the {t.clutch_text()} (outside it the clutch is open and the moment is "
        "zero).",
        "Panels (b) and (d): phantom and exoskeleton stiffness, each stride's least-squares slope "
        "of knee "
        "moment on knee angle from clutch engagement to the peak moment in the "
        f"{t.clutch_text()} (spring loading). {BARS}",
        t.notation(),
        t.outlier_note(["phantom_stiffness_Nm_per_rad", "exo_stiffness_Nm_per_rad"]),
        t.sources(),
    )
    return fig, caption


def power_by_spring(t: Figures):
    """Figure 8: mean ± SD power of every component in the work window, one panel a spring."""
    names = [spring_label(s) for s in t.springs]
    fig, panel = figures.new_mosaic(figures.grid_layout(names, 3), width=7.5, height=4.8)
    strides = t.curves.groupby(SPRING)["n_strides"].first()
    for name, spring in zip(names, t.springs, strict=True):
        ax = panel[name]
        t.shade_clutch(ax)
        rows = t.curve(spring)
        rows = rows[rows["gait_cycle_pct"] <= t.work_pct]
        for component in COMPONENTS:
            colour = figures.COMPONENT_COLOURS[component]
            x = rows["gait_cycle_pct"]
            mean, sd = rows[f"mean_power_{component}_W"], rows[f"sd_power_{component}_W"]
            ax.plot(x, mean, lw=1.0, color=colour, label=component)
            ax.fill_between(x, mean - sd, mean + sd, color=colour, alpha=0.12, lw=0)
        ax.axhline(0, color="0.5", lw=0.5)
        ax.set(xlabel="gait cycle (%)", ylabel="power (W)")
        panel_note(ax, f"{name}, {t.work_short()}", f"mean ± SD, n = {strides[spring]}")
    axes = [panel[name] for name in names]
    axes[0].legend(fontsize=6)
    share_y(axes)
    count = len(names)
    caption = (
        f"Figure 8 of {PHANTOM.key}, reproduced: power of each component, one panel per spring.",
        f"Panels (a)–({chr(96 + count)}): power of knee, exoskeleton, interface, spring and "
        f"frame over {t.work_text()}: mean (line) ± SD (band) over the included strides of the "
        f"spring (n in each panel's title); the {t.clutch_text()} is shaded, as in figure 9. "
        "Power is what a component delivers to the knee: negative = absorbed or dissipated. "
        "Interface = knee − exoskeleton, frame = exoskeleton − spring "
        f"({PHANTOM.key} eqs. 2.3–2.4).",
        "The curves are ``curves.parquet`` (mean and SD per spring and % of the cycle). "
        + t.sources(),
    )
    return fig, caption


def component_panels(width: float, height: float):
    """A figure with one panel per power component, three on the first row and the other two
    centred below (no empty panel)."""
    return figures.new_mosaic(figures.grid_layout(COMPONENTS, 3), width=width, height=height)


def power_by_component(t: Figures):
    """Figure 9: mean ± SD power of each component in the work window for every spring."""
    fig, panel = component_panels(7.5, 4.8)
    for component in COMPONENTS:
        ax = panel[component]
        t.mean_curves(ax, f"power_{component}_W", f"{component} power (W)", window=t.work_pct)
        ax.axhline(0, color="0.5", lw=0.5)
    panel[COMPONENTS[0]].legend(fontsize=6, ncols=2)
    caption = (
        f"Figure 9 of {PHANTOM.key}, reproduced: power of each spring, one panel per component.",
        "Panels (a) knee, (b) exoskeleton, (c) interface, (d) spring and (e) frame power over "
        f"{t.work_text()}: mean (line) ± SD (band) per spring over its included strides; the "
        f"{t.clutch_text()} is shaded. Negative power = absorbed or dissipated by the "
        "component.",
        "The curves are ``curves.parquet`` (mean and SD per spring and % of the cycle). "
        + t.sources(),
    )
    return fig, caption


def work(t: Figures):
    """Figure 10: positive and negative work bars per spring, net work as a white line."""
    fig, panel = component_panels(7.5, 5.2)
    for component in COMPONENTS:
        ax = panel[component]
        t.mark_outliers(ax, f"work_{component}_net_J")
        for kind in ("positive", "negative"):
            t.bars(ax, f"work_{component}_{kind}_J", f"{component} work (J)", t.work_short())
        net = t.summary[t.summary["metric"] == f"work_{component}_net_J"]
        net = net.set_index(SPRING).loc[t.springs, "mean"]
        for x, value in enumerate(net):
            ax.plot([x - 0.4, x + 0.4], [value, value], color="white", lw=2.0)
            ax.plot([x - 0.4, x + 0.4], [value, value], color="black", lw=0.6)
        ax.axhline(0, color="0.3", lw=0.6)
    caption = (
        f"Figure 10 of {PHANTOM.key}, reproduced: work of each component per spring.",
        "Panels (a) knee, (b) exoskeleton, (c) interface, (d) spring and (e) frame: positive work "
        "(returned to the knee, bar above zero) and negative work (absorbed, bar below zero) "
        f"of each stride over {t.work_text()}; the black line on white is the mean net work. "
        f"{BARS}",
        t.notation() + " Positive work's marks are at the top, negative work's at the bottom.",
        t.outlier_note(
            [f"work_{c}_{k}_J" for c in COMPONENTS for k in ("positive", "negative", "net")]
        ),
        t.sources(),
    )
    return fig, caption


def relative_work(t: Figures):
    """Figure 11: shares of interface, spring and frame in the positive and negative work."""
    count = len(t.springs)
    fig, axes = figures.new_figure(count, 2, width=7.5, height=3.4)
    parts = ("interface", "spring", "frame")
    summary = t.summary.set_index(["metric", SPRING])["mean"]
    strides = t.summary.set_index(["metric", SPRING])["n"]
    for column, spring in enumerate(t.springs):
        for row, kind in enumerate(("positive", "negative")):
            values = np.array([abs(summary[(f"work_{p}_{kind}_J", spring)]) for p in parts])
            ax = axes[row, column]
            ax.pie(
                values,
                colors=[figures.COMPONENT_COLOURS[p] for p in parts],
                autopct="%1.0f%%",
                pctdistance=0.7,
                textprops={"fontsize": 6},
                startangle=90,
            )
            n = strides[(f"work_interface_{kind}_J", spring)]
            ax.set_title(
                f"{spring_label(spring)}, {kind}\n0–{t.work_pct:g} %, n = {n}",
                fontsize=6,
                loc="left",
            )
    fig.legend(parts, loc="outside lower center", ncols=3, fontsize=7)
    caption = (
        f"Figure 11 of {PHANTOM.key}, reproduced: where the work goes, per spring.",
        f"Top row ((a)–({chr(96 + count)})): shares of interface, spring and frame in the "
        "positive work; bottom row: in the negative work. Each share is the mean over the "
        f"included strides (n in each title) of the component's work over {t.work_text()}, "
        "as a percentage of the three shares' sum of absolute means.",
        t.sources(),
    )
    return fig, caption


def panel_note(ax, window: str, strides: str) -> None:
    """A panel's title: its window on the first line, its strides on the second."""
    ax.set_title(f"{window}\n{strides}", fontsize=7, loc="left")


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


def trial_order(springs: Mapping[str, float]) -> list[str]:
    """Trials by spring rate, softest first (ties by name), not in test order."""
    return sorted(springs, key=lambda trial: (springs[trial], trial))


def trial_label(trial: str, springs: Mapping[str, float]) -> str:
    """A trial as the QC figure names it: its spring and its name, e.g. '3.4 kN/m (k03400)'."""
    return f"{spring_label(springs[trial])} ({trial})"


def event_counts(checks: Mapping[str, pd.DataFrame], trials, channels) -> dict[str, np.ndarray]:
    """Per trial (rows) and channel (columns): events filled, events left as gaps (or
    saturated) and glitches (events other than the file's own dropouts)."""
    table = pd.concat([checks[t].assign(trial=t) for t in trials], ignore_index=True)
    table = table[table["channel"].isin(channels)]

    def count(rows: pd.DataFrame) -> np.ndarray:
        trial = pd.Categorical(rows["trial"], categories=list(trials))
        channel = pd.Categorical(rows["channel"], categories=list(channels))
        return pd.crosstab(trial, channel, dropna=False).to_numpy(float)

    return {
        "filled": count(table[table["repair"] == "filled"]),
        "left": count(table[table["repair"] != "filled"]),
        "glitches": count(table[table["kind"] != "dropout"]),
    }


def quality_control(
    checks: Mapping[str, pd.DataFrame],
    strides: Mapping[str, pd.DataFrame],
    springs: Mapping[str, float],
    labels: Mapping[str, str] | None = None,
):
    """What the screening found per trial and channel (events filled, or left as gaps and
    saturated runs that exclude strides) and every trial's strides by inclusion or reason;
    trials by spring rate, channels under the lab's own labels where ``labels`` (contract name
    → label) gives them, a key for the marks drawn only."""
    trials, labels = trial_order(springs), dict(labels or {})
    names = [trial_label(t, springs) for t in trials]
    fig, axes = figures.new_figure(2, 1, width=10.5, height=0.3 * len(trials) + 3.2)
    channels = [*MARKERS, *REQUIRED_ANALOGS]
    counts = event_counts(checks, trials, channels)
    filled, left, glitches = counts["filled"], counts["left"], counts["glitches"]
    ax = axes[0, 0]
    shade = np.ma.masked_equal(glitches, 0)  # no glitch: left white
    ax.imshow(shade, cmap="Oranges", vmin=0, vmax=max(2.0, 2 * glitches.max()), aspect="auto")
    for (row, column), count in np.ndenumerate(filled + left):
        if count:
            text = f"{filled[row, column]:.0f}" + (
                f"/{left[row, column]:.0f}" if left[row, column] else ""
            )
            colour = "#D55E00" if left[row, column] else "black"
            ax.text(column, row, text, ha="center", va="center", fontsize=6, color=colour)
    ax.set_xticks(range(len(channels)), [labels.get(c, c) for c in channels], rotation=90,
                  fontsize=6)  # fmt: skip
    ax.set_yticks(range(len(trials)), names, fontsize=7)
    ax.set_xlim(-0.5, len(channels) - 0.5)
    ax.set_ylim(len(trials) - 0.5, -0.5)
    ax.grid(False)
    ax.set_title("events per trial and channel", fontsize=8)
    key = event_key(filled.any(), left.any(), glitches.any())
    if key:  # below the figure: clear of channel labels of any length
        fig.legend(handles=key, fontsize=7, loc="outside lower left", ncols=len(key),
                   title="panel (a)", title_fontsize=7)  # fmt: skip
    ax = axes[0, 1]
    reasons = pd.DataFrame(
        {t: strides[t]["exclusion_reason"].replace("", "included").value_counts()
         for t in trials}
    ).fillna(0.0).T.loc[trials]  # fmt: skip
    order = ["included", *sorted(c for c in reasons.columns if c != "included")]
    order = [reason for reason in order if reason in reasons and reasons[reason].any()]
    colours = ["#009E73", "#E69F00", "#56B4E9", "#CC79A7", "#D55E00", "#0072B2", "#999999"]
    start = np.zeros(len(trials))
    for index, reason in enumerate(order):
        ax.barh(names, reasons[reason], left=start, color=colours[index % len(colours)],
                label=reason, height=0.6)  # fmt: skip
        start += reasons[reason].to_numpy()
    ax.invert_yaxis()
    ax.tick_params(axis="y", labelsize=7)
    ax.set_xlabel("programmed strides")
    ax.set_title("strides: included or why excluded", fontsize=8)
    ax.legend(fontsize=6, loc="upper left", bbox_to_anchor=(1.0, 1.0))
    return fig


def event_key(filled: bool, left: bool, glitches: bool) -> list:
    """Legend entries of the QC events panel, for the marks it drew only."""
    key = []
    if filled:
        key.append(Line2D([], [], ls="none", marker="$n$", color="black", ms=7,
                          label="events filled by the gap fill"))  # fmt: skip
    if left:
        key.append(Line2D([], [], ls="none", marker="$/m$", color="#D55E00", ms=9,
                          label="after the slash: left as gaps or saturated"))  # fmt: skip
    if glitches:
        key.append(Patch(color=matplotlib.colormaps["Oranges"](0.5),
                         label="shade: glitches and saturated runs"))  # fmt: skip
    return key


def quality_control_caption(
    checks, strides, max_gap_frames: int, springs: Mapping[str, float], labels=None
) -> tuple[str, ...]:
    """Caption of ``qc.png``: what the panels count, and what the screening found."""
    table = pd.concat(checks.values(), ignore_index=True)
    found = table.groupby(["kind", "repair"]).size()
    listed = "; ".join(f"{n} {kind} ({repair})" for (kind, repair), n in found.items())
    excluded = sum(int((~s["included"]).sum()) for s in strides.values())
    programmed = sum(len(s) for s in strides.values())
    counts = event_counts(checks, trial_order(springs), [*MARKERS, *REQUIRED_ANALOGS])
    renamed = {k: v for k, v in dict(labels or {}).items() if k != v}
    return (
        "Quality control of the recordings: what the acquisition's glitch screening found in "
        f"{len(checks)} trials and what became of it. Found: {listed or 'nothing'}. Trials "
        "are ordered by spring rate (softest at the top), not in the order they were recorded"
        + (
            "; channels carry the lab's own labels (``phantom.rig.labels``: "
            + ", ".join(f"{label} for {name}" for name, label in renamed.items())
            + ")."
            if renamed
            else "."
        ),
        "Panel (a): per trial (rows) and channel (columns), the events found: glitches (spikes, "
        "ghost frames, jumps out and back, markers off their rigid segment, samples out of range "
        "or not a number), which are blanked and treated as gaps, the dropouts the file holds, "
        "and saturated load-cell runs. Each cell gives the number filled by the gap fill"
        + (
            f" and, after a slash (red), the number left as gaps longer than {max_gap_frames} "
            "frames at 100 Hz or saturated: the strides they touch are excluded"
            if counts["left"].any()
            else f" (none was left as a gap longer than {max_gap_frames} frames or saturated)"
        )
        + (
            ". The shade counts the glitches and saturated runs (not the dropouts)."
            if counts["glitches"].any()
            else "; no glitch or saturated run was found, only the file's own dropouts."
        ),
        f"Panel (b): every trial's programmed strides ({programmed}; {excluded} excluded), "
        "included or excluded by reason (ramp strides, gaps, saturation, low spring force).",
        "``qc/<trial>.parquet`` lists every event with its channel, kind, start and end, size, "
        "repair, strides and why they were excluded; the run's log has one line per trial.",
    )
