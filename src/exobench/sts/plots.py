"""Figures of the sit-to-stand group: joint paths (figs. 3/5 of the pelvis–foot study), torques,
modules, thigh; each with its caption (one simulated motion, no strides: every panel states its
time window)."""

from __future__ import annotations

from collections.abc import Mapping, Sequence

import numpy as np
import pandas as pd
from matplotlib.lines import Line2D
from matplotlib.tri import Triangulation

from exobench import figures
from exobench.sts.kinematics import POINTS
from exobench.sts.loads import JOINTS
from exobench.studies import STS

POINT_COLOURS = {"C": "#D55E00", "B": "#0072B2", "A": "#009E73"}  # study fig. 3: red, blue, green
POINT_NAMES = {"C": "knee C", "B": "hip B", "A": "trunk A"}
# Colour names the quantity, line style the motion law.
ANGLE_COLOURS = {"phi1": "#009E73", "phi2": "#0072B2", "phi3": "#D55E00", "trunk": "#000000"}
LAW_STYLES = {
    "piecewise": {"color": "#000000", "ls": "-"},
    "smooth": {"color": "#E69F00", "ls": "--"},
}
LAW_NAMES = {
    "piecewise": "piecewise law (the study's eq. 4)",
    "smooth": "minimum-jerk law",
    "corrected": "corrected law onto the chair (knee and hip turning the human way)",
    "corrected_study_seat": "corrected law onto the study's seat height (its task)",
}
SHORT_NAMES = {"piecewise": "study's piecewise law", "smooth": "study's postures, minimum jerk",
               "corrected": "corrected law, chair",
               "corrected_study_seat": "corrected law, study's seat"}  # fmt: skip
THIGH_LAWS = ("piecewise", "corrected")
THIGH_STYLES = {"piecewise": {"color": "#0072B2", "ls": "-"},
                "corrected": {"color": "#D55E00", "ls": "--"}}  # fmt: skip
# column of fe_field.parquet, load case, colour-bar label, what is marked
FE_PANELS = (
    ("bending_von_mises_MPa", "bending", "von Mises (MPa)", "peak"),
    ("compression_von_mises_MPa", "compression", "von Mises (MPa)", "peak"),
    ("bending_displacement_mm", "bending", "displacement (mm)", "largest"),
)
CASE_TITLES = {"bending": "bending", "compression": "compression"}
SNAPSHOTS_S = (0.0, 0.5, 1.0, 1.5, 2.0)


def span(frame: pd.DataFrame) -> str:
    """The motion's time window as a panel states it, e.g. '0–2 s'."""
    return f"{frame['t_s'].iloc[0]:g}–{frame['t_s'].iloc[-1]:g} s"


def motion_text(frame: pd.DataFrame) -> str:
    """The window every panel shows: one simulated motion, its span and sample rate."""
    rate = 1.0 / float(np.median(np.diff(frame["t_s"].to_numpy())))
    return f"one simulated motion, {span(frame)} at {rate:g} Hz (a model: no strides)"


def posture_names(frame: pd.DataFrame) -> dict[float, str]:
    """First and last posture in words: 'upright' (B above C), 'seated' (thigh near level)."""
    names = {}
    for row in (frame.iloc[0], frame.iloc[-1]):
        thigh = np.degrees(
            np.arctan2(abs(row["xB_mm"] - row["xC_mm"]), row["yB_mm"] - row["yC_mm"])
        )
        names[float(row["t_s"])] = "upright" if thigh < 45.0 else "seated"
    return names


def direction_arrows(ax, frame: pd.DataFrame) -> None:
    """An arrow on each joint's path at mid-motion, pointing the way time runs."""
    middle = int(np.argmin(np.abs(frame["t_s"] - frame["t_s"].median())))
    step = max(len(frame) // 50, 1)
    before, after = (
        frame.iloc[max(middle - step, 0)],
        frame.iloc[min(middle + step, len(frame) - 1)],
    )
    for point in POINTS:
        ax.annotate(
            "",
            xy=(after[f"x{point}_mm"], after[f"y{point}_mm"]),
            xytext=(before[f"x{point}_mm"], before[f"y{point}_mm"]),
            arrowprops={"arrowstyle": "-|>", "color": POINT_COLOURS[point], "lw": 1.2,
                        "mutation_scale": 14},
        )  # fmt: skip


def paths(trajectories: Mapping[str, pd.DataFrame]):
    """Paths of C, B, A with stick figures, and trunk lean and coordinates against time."""
    fig, axes = figures.new_figure(ncols=2, width=8.0, height=3.8)
    ax = axes[0, 0]
    frame = trajectories["piecewise"]
    for point in POINTS:
        ax.plot(
            frame[f"x{point}_mm"],
            frame[f"y{point}_mm"],
            color=POINT_COLOURS[point],
            label=POINT_NAMES[point],
        )
    tops = []
    ends = posture_names(frame)
    for t in SNAPSHOTS_S:
        row = frame.iloc[int(np.argmin(np.abs(frame["t_s"] - t)))]
        xs = [0.0] + [row[f"x{p}_mm"] for p in POINTS]
        ys = [0.0] + [row[f"y{p}_mm"] for p in POINTS]
        ax.plot(xs, ys, color="0.6", lw=0.8, marker="o", ms=2)
        tops.append((f"{t:g} s", (xs[-1], ys[-1])))
    direction_arrows(ax, frame)
    ax.set(xlabel="x (mm)", ylabel="y (mm)")
    ax.set_title(
        f"joint paths, {span(frame)}, ankle D at the origin\n{LAW_NAMES['piecewise']}\n"
        + " → ".join(f"{name} at {t:g} s" for t, name in ends.items()),
        fontsize=8,
        loc="left",
    )
    ax.set_aspect("equal")
    ax.margins(x=0.2)  # room for the time labels right of the last postures
    ax.legend(loc="lower left", fontsize=7)
    ax = axes[0, 1]
    for law in LAW_STYLES:
        frame = trajectories[law]
        lean = np.degrees(frame["phi2_rad"] + frame["phi3_rad"] - frame["phi1_rad"])
        ax.plot(frame["t_s"], lean, color=ANGLE_COLOURS["trunk"], ls=LAW_STYLES[law]["ls"])
        for i in (1, 2, 3):
            ax.plot(
                frame["t_s"],
                np.degrees(frame[f"phi{i}_rad"]),
                color=ANGLE_COLOURS[f"phi{i}"],
                ls=LAW_STYLES[law]["ls"],
                lw=0.9,
            )
    start, end = posture_names(frame).values()
    ax.set(xlabel=f"time (s): {start} at {span(frame).split('–')[0]} s → {end} at "
                  f"{span(frame).split('–')[1]}", ylabel="angle (deg)")  # fmt: skip
    ax.set_title(f"coordinates and trunk lean, {span(frame)}, both laws", fontsize=8, loc="left")
    quantities = [f"φ{i} ({JOINTS[i - 1]})" for i in (1, 2, 3)] + ["trunk from vertical"]
    handles = [Line2D([], [], color=ANGLE_COLOURS[k]) for k in ANGLE_COLOURS] + [
        Line2D([], [], color="0.4", ls=LAW_STYLES[law]["ls"]) for law in LAW_STYLES
    ]
    ax.legend(
        handles, quantities + [LAW_NAMES[law] for law in LAW_STYLES], fontsize=6, loc="upper left"
    )
    figures.place_labels(axes[0, 0], tops, fontsize=7)
    first, last = posture_names(trajectories["piecewise"]).items()
    caption = (
        f"Sit-to-stand kinematics ({STS.key} figs. 3 and 5), "
        f"{motion_text(trajectories['piecewise'])}. Time runs from {first[1]} at {first[0]:g} s "
        f"to {last[1]} at {last[0]:g} s, as {STS.key}'s motion laws are written: the figure "
        "shows the motion in that direction (arrows on the paths), and a sit-to-stand follows "
        "the same postures in reverse. x is the study's Dx, to the right; the study never says "
        "which way the subject faces, so each reading is checked (``readings.json``).",
        "Panel (a): paths of the knee C, hip B and trunk point A with the ankle D at the origin, "
        "under "
        f"the piecewise-linear law of {STS.key} eq. (4), with stick figures D–C–B–A at "
        f"{', '.join(f'{t:g}' for t in SNAPSHOTS_S)} s (labelled at A). The minimum-jerk law "
        "passes through the same postures.",
        "Panel (b): joint coordinates φ1 (hip), φ2 (knee), φ3 (ankle) and the trunk's angle from "
        "the "
        "vertical towards +x (φ2 + φ3 − φ1) against time: colour names the quantity, solid lines "
        "are the "
        "piecewise law, dashed lines the minimum-jerk law through the same postures "
        "(``trajectories.parquet``, ``trajectories_smooth.parquet``; the independent check in "
        "``verification.json``).",
    )
    return fig, caption


def torques(loads: pd.DataFrame, comparison: Mapping):
    """Quasi-static and inverse-dynamic joint torques; piecewise spikes clipped and labelled."""
    fig, axes = figures.new_figure(ncols=3, width=9.0, height=3.4)
    smooth = loads[loads["law"] == "smooth"]
    for ax, joint in zip(axes[0], JOINTS, strict=True):
        for law in LAW_STYLES:
            frame = loads[loads["law"] == law]
            ax.plot(
                frame["t_s"],
                frame[f"{joint}_dynamic_Nm"],
                lw=1.0,
                label=f"inverse dynamics, {LAW_NAMES[law]}",
                **LAW_STYLES[law],
            )
        ax.plot(
            smooth["t_s"],
            smooth[f"{joint}_quasistatic_Nm"],
            color="#56B4E9",
            lw=2,
            alpha=0.7,
            label="quasi-static",
        )
        low = min(smooth[f"{joint}_dynamic_Nm"].min(), smooth[f"{joint}_quasistatic_Nm"].min())
        high = max(smooth[f"{joint}_dynamic_Nm"].max(), smooth[f"{joint}_quasistatic_Nm"].max())
        pad = 0.25 * (high - low)
        ax.set_ylim(low - pad, high + pad)
        peak = comparison["peaks"]["piecewise"][f"peak_dynamic_torque_{joint}_Nm"]
        ax.set_title(
            f"{joint}, {span(smooth)}\npiecewise spikes to {peak:.0f} N·m\n(clipped)",
            fontsize=8,
            loc="left",
        )
        ax.set(xlabel="time (s)", ylabel="extensor torque (N·m)")
    axes[0, 0].legend(fontsize=6, loc="upper left")
    caption = (
        f"Sit-to-stand joint loads under the design load at A, {motion_text(smooth)}.",
        "Panels (a) hip, (b) knee and (c) ankle: extensor torques by inverse dynamics under the "
        "piecewise law (solid) and the minimum-jerk law (dashed), and the quasi-static torque "
        "(thick). The piecewise law jumps in rate at 0, 1.5 and 2 s, so its torques spike (the "
        "peak is in each title; the axis is fitted to the minimum-jerk and quasi-static "
        "curves and clips the spikes). Peaks, impulses and the gain of the smooth law: "
        "``motion_comparison.json``.",
    )
    return fig, caption


def modules(table: pd.DataFrame, laws: Sequence[str]):
    """Required, module and user torques, configured and tuned: one row of panels per law."""
    fig, axes = figures.new_figure(ncols=3, nrows=len(laws), width=9.0, height=2.7 * len(laws))
    for row, law in enumerate(laws):
        rows = table[table["law"] == law]
        for ax, joint in zip(axes[row], JOINTS, strict=True):
            ax.plot(rows["t_s"], rows[f"{joint}_required_Nm"], color="#000000", label="required")
            for setting, colour in (("configured", "#56B4E9"), ("tuned", "#D55E00")):
                ax.plot(
                    rows["t_s"],
                    rows[f"{joint}_module_{setting}_Nm"],
                    color=colour,
                    ls="--",
                    label=f"module, {setting}",
                )
                ax.plot(rows["t_s"], rows[f"{joint}_user_{setting}_Nm"], color=colour,
                        label=f"user, {setting}")  # fmt: skip
            ax.set(xlabel="time (s)", ylabel="extensor torque (N·m)")
            ax.set_title(f"{joint}, {span(rows)}\n{SHORT_NAMES[law]}", fontsize=8, loc="left")
    axes[0, 0].legend(fontsize=6, loc="upper left")
    letters = "abcdefghijkl"
    caption = (
        f"Spring–damper modules, {motion_text(table[table['law'] == laws[0]])}; both laws "
        "on the same task (the study's seat height and timing).",
        *(f"Panels ({letters[3 * i]}) hip, ({letters[3 * i + 1]}) knee and ({letters[3 * i + 2]}) "
          f"ankle: the {LAW_NAMES[law]}." for i, law in enumerate(laws)),
        "In every panel: torque the motion requires (black), the module's torque (dashed) and "
        "what is left to the user (solid), for the configured modules (light blue) and the "
        "modules tuned by bounded least squares to minimise the user's torque on that law (red); "
        "preload, stiffness and damping in ``spring_damper.json``, the curves in "
        "``spring_damper.parquet``.",
    )  # fmt: skip
    return fig, caption


def thigh(loads: pd.DataFrame, check: Mapping):
    """The thigh link's bending moment and axial force along the motion, eq. (5) marked."""
    fig, axes = figures.new_figure(ncols=2, width=8.0, height=3.4)
    frame = loads[loads["law"] == "piecewise"]
    for law in THIGH_LAWS:
        rows = loads[loads["law"] == law]
        axes[0, 0].plot(
            rows["t_s"], rows["thigh_bending_moment_Nm"], label=LAW_NAMES[law], **THIGH_STYLES[law]
        )
        axes[0, 1].plot(rows["t_s"], rows["thigh_axial_force_N"], label=LAW_NAMES[law],
                        **THIGH_STYLES[law])  # fmt: skip
    axes[0, 0].axhline(
        check["max_bending_moment_Nm"], color="0.5", ls=":", label="eq. (5), horizontal thigh"
    )
    axes[0, 0].set(xlabel="time (s)", ylabel="bending moment at the knee (N·m)")
    axes[0, 1].set(xlabel="time (s)", ylabel="axial compression (N)")
    axes[0, 0].set_title(f"bending moment, {span(frame)}", fontsize=8, loc="left")
    axes[0, 1].set_title(f"axial force, {span(frame)}", fontsize=8, loc="left")
    axes[0, 1].legend(*axes[0, 0].get_legend_handles_labels(), fontsize=6, loc="lower left")
    caption = (
        f"Thigh link along the motion, {motion_text(frame)}, under the design load of "
        f"{check['design_load_N']:g} N at A.",
        "Panel (a): bending moment at the knee end (N·m); the dotted line is "
        f"{STS.key} eq. (5) (thigh horizontal). Panel (b): axial compression (N). Solid: the "
        "study's piecewise law (eq. 4); dashed: the corrected law onto the chair (the knee and "
        "hip turning the human way, the seat reached in balance). Stresses, safety factors, "
        "deflection, buckling and fatigue: ``beam_check.json``; the link by finite elements: "
        "``fe.json``.",
    )
    return fig, caption


def fe_contours(fe: Mapping, field: pd.DataFrame, mesh: pd.DataFrame):
    """Von Mises in bending and compression and bending displacement, peaks marked."""
    fig, axes = figures.new_figure(ncols=1, nrows=3, width=8.0, height=4.8)
    grid = Triangulation(field["x_mm"], field["y_mm"],
                         mesh[["vertex_0", "vertex_1", "vertex_2"]].to_numpy())  # fmt: skip
    finest = fe["finest"]
    for ax, (column, case, label, what) in zip(axes[:, 0], FE_PANELS, strict=True):
        shaded = ax.tripcolor(grid, field[column], shading="gouraud", cmap="viridis")
        fig.colorbar(shaded, ax=ax, label=label, aspect=8, pad=0.01)
        ax.grid(False)
        if what == "peak":
            peak = finest[case]["peak"]
            ax.plot([peak["x_mm"]], [peak["y_mm"]], marker="o", ms=6, mfc="none", color="#D55E00")
            said = f"peak {peak['MPa']:.1f} MPa, {peak['where']}"
        else:
            said = f"largest {finest[case]['max_displacement_mm']:.2f} mm"
        ax.set_title(f"{CASE_TITLES[case]}: {said}", fontsize=8, loc="left")
        ax.set(xlabel="x from the knee pin (mm)", ylabel="y (mm)")
        ax.set_aspect("equal", adjustable="datalim")  # to scale
    model = fe["model"]
    caption = (
        f"The thigh link by finite elements ({STS.key} fig. 9 a–c analogue): the configured "
        f"link under the design load of {model['load_N']:g} N through the hip pin, "
        f"{model['elements']}, {model['state']}, {model['support']} (a static model: no time "
        "window).",
        "Panel (a): von Mises stress in bending (the seated, horizontal thigh: the pin presses "
        "across the link); (b) in compression (the upright link: the pin pushes along it "
        "towards the knee); (c) displacement in bending. Each load reaches the hole as a cosine "
        "bearing pressure over the half the pin presses on; the circle marks the peak. Values "
        "averaged at the vertices of the finest mesh (``fe_field.parquet``, triangles in "
        "``fe_mesh.parquet``); the peaks, their convergence and the comparison with the beam "
        "formulas and the study's numbers: ``fe.json``.",
    )
    return fig, caption


def all_figures(trajectories, loads, comparison, module_torques, check, fe) -> dict:
    """Every sit-to-stand figure and caption by file name; modules on one task, the study's seat."""
    laws = [str(module_torques["law"].iloc[0]), "corrected_study_seat"]  # the same task
    return {
        "paths": paths(trajectories),
        "torques": torques(loads, comparison),
        "modules": modules(module_torques, laws),
        "thigh": thigh(loads, check),
        "fe": fe_contours(*fe),
    }
