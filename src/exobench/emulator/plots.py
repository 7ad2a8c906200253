"""Figures of the emulator group (seed 002 figs. 6.3–6.5 analogues)."""

from __future__ import annotations

import itertools
from collections.abc import Mapping

import numpy as np
import pandas as pd

from exobench import figures

CYCLE_PCT = np.linspace(0.0, 100.0, 101)


def cycle_curves(samples: pd.DataFrame, column: str) -> np.ndarray:
    """``column`` of every complete step resampled to 0–100 % of the gait cycle (steps × 101)."""
    hs = np.flatnonzero(samples["heel_strike"].to_numpy())
    values = samples[column].to_numpy()
    return np.array(
        [
            np.interp(CYCLE_PCT, np.linspace(0.0, 100.0, b - a), values[a:b])
            for a, b in itertools.pairwise(hs)
        ]
    ).reshape(-1, len(CYCLE_PCT))


def energy_per_step(summary: pd.DataFrame, png, pdf) -> None:
    """Mean ± SD energy stored per step against spring stiffness, one line per speed."""
    fig, axes = figures.new_figure(width=4.5, height=3.2)
    ax = axes[0, 0]
    for colour, (speed, rows) in zip(
        figures.PALETTE, summary.groupby("speed_m_per_s"), strict=False
    ):
        rows = rows.sort_values("stiffness_Nm_per_rad")
        ax.errorbar(
            rows["stiffness_Nm_per_rad"],
            rows["mean_energy_J"],
            yerr=rows["sd_energy_J"],
            marker="o",
            capsize=3,
            color=colour,
            label=f"{speed:g} m/s",
        )
    ax.set(xlabel="emulated stiffness κ (N·m/rad)", ylabel="energy stored per step (J)")
    ax.legend(title="treadmill speed")
    figures.save(fig, png, pdf)


def angle_torque(samples: Mapping[str, pd.DataFrame], conditions: pd.DataFrame, png, pdf):
    """Mean brace angle, desired and delivered torque over the gait cycle per condition."""
    speeds = sorted(conditions["speed_m_per_s"].unique())
    fig, axes = figures.new_figure(ncols=len(speeds), nrows=2, width=4.0 * len(speeds), height=5.5)
    for col, speed in enumerate(speeds):
        rows = conditions[conditions["speed_m_per_s"] == speed].sort_values("stiffness_Nm_per_rad")
        colours = figures.ordered_colours(len(rows))
        for colour, row in zip(colours, rows.itertuples(), strict=True):
            frame = samples[row.trial]
            angle = cycle_curves(frame, "brace_angle_deg")
            axes[0, col].plot(
                CYCLE_PCT,
                angle.mean(axis=0),
                color=colour,
                label=f"κ = {row.stiffness_Nm_per_rad:g}",
            )
            axes[1, col].plot(
                CYCLE_PCT, cycle_curves(frame, "brace_torque_Nm").mean(axis=0), color=colour
            )
            axes[1, col].plot(
                CYCLE_PCT,
                cycle_curves(frame, "desired_torque_Nm").mean(axis=0),
                color=colour,
                ls="--",
            )
        axes[0, col].set(title=f"{speed:g} m/s", ylabel="brace knee flexion (deg)")
        axes[1, col].set(xlabel="gait cycle (%)", ylabel="torque (N·m): delivered —, desired --")
        axes[0, col].legend(fontsize=6, title="N·m/rad", title_fontsize=6)
    figures.save(fig, png, pdf)


def encoder_vs_mocap(samples: Mapping[str, pd.DataFrame], conditions: pd.DataFrame, png, pdf):
    """Mean encoder angle against motion capture (mean ± SD) over the cycle, per condition."""
    rows = conditions.sort_values(["speed_m_per_s", "stiffness_Nm_per_rad"])
    ncols = int(np.ceil(len(rows) / 2))
    fig, axes = figures.new_figure(ncols=ncols, nrows=2, width=2.2 * ncols, height=4.5)
    for ax, row in zip(axes.flat, rows.itertuples(), strict=False):
        frame = samples[row.trial]
        mocap = cycle_curves(frame, "anatomical_angle_deg")
        mean, sd = mocap.mean(axis=0), mocap.std(axis=0)
        ax.fill_between(CYCLE_PCT, mean - sd, mean + sd, color="#56B4E9", alpha=0.4, lw=0)
        ax.plot(
            CYCLE_PCT, cycle_curves(frame, "brace_angle_deg").mean(axis=0), color="#000000", lw=1.0
        )
        ax.set_title(f"{row.speed_m_per_s:g} m/s, κ {row.stiffness_Nm_per_rad:g}", fontsize=7)
        ax.tick_params(labelsize=6)
    for ax in axes.flat[len(rows) :]:
        ax.set_visible(False)
    fig.supylabel("knee flexion (deg)", fontsize=8)
    fig.supxlabel(
        "gait cycle (%): brace encoder (line), motion capture mean ± SD (band)", fontsize=8
    )
    figures.save(fig, png, pdf)


def activity_crosscheck(qc_trials: Mapping[str, Mapping], conditions: pd.DataFrame, png, pdf):
    """Share of steps whose recorded activity departs from Table 6.1, per gait phase and trial."""
    rows = conditions.sort_values(["speed_m_per_s", "stiffness_Nm_per_rad"])
    checks = [qc_trials[trial]["table61_crosscheck"] for trial in rows["trial"]]
    edges = checks[0]["by_phase"]["phase_pct"] if checks else []
    width = np.diff(edges).mean() if len(edges) > 1 else 10.0
    share = np.array([c["by_phase"]["share_of_steps"] for c in checks]).reshape(len(checks), -1)
    fig, axes = figures.new_figure(width=5.5, height=0.35 * max(len(checks), 4) + 1.2)
    ax = axes[0, 0]
    image = ax.imshow(
        share,
        aspect="auto",
        cmap="viridis",
        vmin=0.0,
        vmax=1.0,
        extent=(0.0, len(edges) * width, len(checks) - 0.5, -0.5),
    )
    labels = [
        f"{r.speed_m_per_s:g} m/s, κ {r.stiffness_Nm_per_rad:g}: "
        + (f"{100 * c['share_of_steps_disagreeing']:.0f} %" if c["n_steps"] else "no steps")
        for r, c in zip(rows.itertuples(), checks, strict=True)
    ]
    ax.set_yticks(range(len(checks)), labels, fontsize=6)
    ax.grid(False)
    ax.set(xlabel="gait cycle (%) from heel strike")
    ax.set_title("recorded spring activity vs Table 6.1 (share of steps disagreeing)", fontsize=8)
    fig.colorbar(image, ax=ax, label="share of steps")
    figures.save(fig, png, pdf)
