"""Figures of the sit-to-stand group: joint paths (seed 001 figs. 3/5), torques, modules, thigh."""

from __future__ import annotations

from collections.abc import Mapping

import numpy as np
import pandas as pd

from exobench import figures
from exobench.sts.kinematics import POINTS
from exobench.sts.loads import JOINTS

POINT_COLOURS = {"C": "#D55E00", "B": "#0072B2", "A": "#009E73"}  # seed fig. 3: red, blue, green
POINT_NAMES = {"C": "knee C", "B": "hip B", "A": "trunk A"}
LAW_STYLES = {
    "piecewise": {"color": "#000000", "ls": "-"},
    "smooth": {"color": "#E69F00", "ls": "--"},
}
SNAPSHOTS_S = (0.0, 0.5, 1.0, 1.5, 2.0)


def paths(trajectories: Mapping[str, pd.DataFrame], png, pdf) -> None:
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
    for t in SNAPSHOTS_S:
        row = frame.iloc[int(np.argmin(np.abs(frame["t_s"] - t)))]
        xs = [0.0] + [row[f"x{p}_mm"] for p in POINTS]
        ys = [0.0] + [row[f"y{p}_mm"] for p in POINTS]
        ax.plot(xs, ys, color="0.6", lw=0.8, marker="o", ms=2)
        ax.annotate(
            f"{t:g} s", (xs[-1], ys[-1]), fontsize=7, xytext=(3, 3), textcoords="offset points"
        )
    ax.set(xlabel="x (mm)", ylabel="y (mm)", title="Joint paths, ankle D at the origin")
    ax.set_aspect("equal")
    ax.legend(loc="lower left", fontsize=7)
    ax = axes[0, 1]
    for law, frame in trajectories.items():
        lean = np.degrees(frame["phi2_rad"] + frame["phi3_rad"] - frame["phi1_rad"])
        ax.plot(frame["t_s"], lean, label=f"trunk angle from vertical, {law}", **LAW_STYLES[law])
        for i, colour in zip((1, 2, 3), ("#009E73", "#0072B2", "#D55E00"), strict=True):
            ax.plot(
                frame["t_s"],
                np.degrees(frame[f"phi{i}_rad"]),
                color=colour,
                ls=LAW_STYLES[law]["ls"],
                lw=0.9,
                label=f"φ{i} ({JOINTS[i - 1]}), {law}" if law == "piecewise" else None,
            )
    ax.set(xlabel="time (s)", ylabel="angle (deg)", title="Coordinates and trunk lean")
    ax.legend(fontsize=6, loc="upper left")
    figures.save(fig, png, pdf)


def torques(loads: pd.DataFrame, comparison: Mapping, png, pdf) -> None:
    """Quasi-static and inverse-dynamic joint torques; piecewise spikes clipped and labelled."""
    fig, axes = figures.new_figure(ncols=3, width=9.0, height=3.2)
    smooth = loads[loads["law"] == "smooth"]
    for ax, joint in zip(axes[0], JOINTS, strict=True):
        for law, frame in loads.groupby("law", sort=True):
            ax.plot(
                frame["t_s"],
                frame[f"{joint}_dynamic_Nm"],
                lw=1.0,
                label=f"inverse dynamics, {law}",
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
        ax.set_title(f"{joint} (piecewise spikes to {peak:.2g} N·m, clipped)", fontsize=8)
        ax.set(xlabel="time (s)", ylabel="extensor torque (N·m)")
    axes[0, 0].legend(fontsize=6, loc="upper left")
    figures.save(fig, png, pdf)


def modules(table: pd.DataFrame, png, pdf) -> None:
    """Required torque, module torque and the user's share, configured and tuned modules."""
    fig, axes = figures.new_figure(ncols=3, width=9.0, height=3.2)
    for ax, joint in zip(axes[0], JOINTS, strict=True):
        ax.plot(table["t_s"], table[f"{joint}_required_Nm"], color="#000000", label="required")
        for setting, colour in (("configured", "#56B4E9"), ("tuned", "#D55E00")):
            ax.plot(
                table["t_s"],
                table[f"{joint}_module_{setting}_Nm"],
                color=colour,
                ls="--",
                label=f"module, {setting}",
            )
            ax.plot(
                table["t_s"],
                table[f"{joint}_user_{setting}_Nm"],
                color=colour,
                label=f"user, {setting}",
            )
        ax.set(xlabel="time (s)", ylabel="extensor torque (N·m)", title=joint)
    axes[0, 0].legend(fontsize=6, loc="upper left")
    figures.save(fig, png, pdf)


def thigh(loads: pd.DataFrame, check: Mapping, png, pdf) -> None:
    """Bending moment and axial force of the thigh link along the motion, eq. (5) marked."""
    fig, axes = figures.new_figure(ncols=1, width=5.0, height=3.2)
    ax = axes[0, 0]
    frame = loads[loads["law"] == "piecewise"]
    ax.plot(
        frame["t_s"],
        frame["thigh_bending_moment_Nm"],
        color="#0072B2",
        label="bending moment at the knee (N·m)",
    )
    ax.plot(
        frame["t_s"], frame["thigh_axial_force_N"], color="#009E73", label="axial compression (N)"
    )
    ax.axhline(
        check["max_bending_moment_Nm"], color="0.5", ls=":", label="eq. (5), horizontal thigh"
    )
    ax.set(
        xlabel="time (s)",
        ylabel="N·m or N",
        title=f"Thigh link: peak {check['peak_stress_MPa']:.0f} MPa, "
        f"SF yield {check['safety_factor_yield']:.2f}",
    )
    ax.legend(fontsize=7)
    figures.save(fig, png, pdf)
