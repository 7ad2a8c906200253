"""Figures of the emulator group (Heer figs. 6.3–6.5 reproduced), each with its caption: every
panel states its window and its steps, and the faults the analysis names are annotated (encoder
faults, and recorded spring activity departing from Table 6.1, on the energy figure)."""

from __future__ import annotations

import itertools
import textwrap
from collections.abc import Mapping

import numpy as np
import pandas as pd
from matplotlib.lines import Line2D

from exobench import figures
from exobench.studies import EMULATOR

CYCLE_PCT = np.linspace(0.0, 100.0, 101)
ENERGY_WINDOW = "heel strike to heel strike, while the spring was active as recorded"
FAULT_NAMES = {
    "drop": "encoder count drop in the trial",
    "drop_before_trial": "encoder count drop before the trial",
}


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


def count_text(counts, unit: str = "steps") -> str:
    """Steps per condition as a panel states them: 'n = 23 steps' or 'n = 22–27 steps'."""
    low, high = int(min(counts)), int(max(counts))
    return f"n = {low} {unit}" if low == high else f"n = {low}–{high} {unit}"


def letter_range(first: int, count: int) -> str:
    """Panel letters first … first + count − 1 as a caption names them: '(a)' or '(a)–(f)'."""
    low, high = chr(97 + first), chr(96 + first + count)
    return f"({low})" if count == 1 else f"({low})–({high})"


def numbered(conditions: pd.DataFrame) -> pd.DataFrame:
    """Conditions in Heer's order (speed, then stiffness) with their number from 1."""
    rows = conditions.sort_values(["speed_m_per_s", "stiffness_Nm_per_rad"])
    return rows.assign(condition=np.arange(1, len(rows) + 1))


def faults(qc_trials: Mapping[str, Mapping], conditions: pd.DataFrame) -> pd.DataFrame:
    """Trials the analysis names as faulty (``encoder_fault`` in qc.json): condition, kinds,
    encoder offset against the session."""
    rows = numbered(conditions)
    bad = rows[[bool(qc_trials[t]["encoder_fault"]) for t in rows["trial"]]]
    return bad.assign(
        kinds=[
            ", ".join(FAULT_NAMES.get(k, k.replace("_", " ")) for k in qc_trials[t]["fault_kinds"])
            for t in bad["trial"]
        ],
        offset_deg=[qc_trials[t]["encoder_offset_deg"] for t in bad["trial"]],
    )


def activity_departures(qc_trials: Mapping[str, Mapping], conditions: pd.DataFrame):
    """Conditions whose recorded spring activity departs from Table 6.1 in some steps
    (``table61_crosscheck`` in qc.json): condition, share of steps, the gait phases."""
    rows = numbered(conditions)
    checks = [qc_trials[t]["table61_crosscheck"] for t in rows["trial"]]
    return rows.assign(
        share=[c.get("share_of_steps_disagreeing") or 0.0 for c in checks],
        phases=[
            ", ".join(f"{low:g}–{high:g} %" for low, high in c.get("phases_disagreeing_pct", []))
            for c in checks
        ],
    ).query("share > 0")


def departure_text(row) -> str:
    """One Table 6.1 departure as the energy figure names it."""
    return f"activity departs from Table 6.1 in {100 * row.share:.0f} % of steps" + (
        f" ({row.phases} of the cycle)" if row.phases else ""
    )


def fault_text(row) -> str:
    """One fault as the figures name it."""
    offset = "" if row.offset_deg is None else f" ({row.offset_deg:+.1f}° against the session)"
    return (
        f"condition {row.condition} ({row.speed_m_per_s:g} m/s, κ {row.stiffness_Nm_per_rad:g}): "
        f"{row.kinds}{offset}"
    )


def energy_per_step(summary: pd.DataFrame, conditions: pd.DataFrame, qc_trials: Mapping):
    """Mean ± SD energy stored per step against spring stiffness, one line per speed; the
    conditions the analysis names as faulty annotated."""
    fig, axes = figures.new_figure(width=5.0, height=3.6)
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
    ax.set_title(
        f"mean ± SD per step, heel strike to heel strike\n"
        f"{count_text(summary['n_steps'])} per condition",
        fontsize=7,
    )
    ax.legend(title="treadmill speed", loc="upper left", fontsize=7, title_fontsize=7)
    named = faults(qc_trials, conditions)
    departing = activity_departures(qc_trials, conditions)
    notes = {row.trial: [f"condition {row.condition}: {row.kinds}"] for row in named.itertuples()}
    for row in departing.itertuples():
        notes.setdefault(row.trial, [f"condition {row.condition}"]).append(departure_text(row))
    marked = numbered(conditions).set_index("trial").loc[list(notes)]
    energy = summary.set_index("trial")
    for row in marked.reset_index().itertuples():
        ax.plot(
            row.stiffness_Nm_per_rad,
            energy.loc[row.trial, "mean_energy_J"],
            "o",
            ms=9,
            mfc="none",
            color="#D55E00",
        )
    figures.place_labels(
        ax,
        [
            (
                textwrap.fill("; ".join(notes[row.trial]), 24),
                (row.stiffness_Nm_per_rad, energy.loc[row.trial, "mean_energy_J"]),
            )
            for row in marked.reset_index().itertuples()
        ],
        fontsize=6,
        color="#D55E00",
    )
    caption = (
        f"Energy stored in the emulated spring per step ({EMULATOR.key} fig. 6.3, reproduced): the "
        f"measured brace torque integrated over the brace angle, {ENERGY_WINDOW} (desired "
        "torque non-zero, or the recorded clutch flag).",
        "Points: mean over the steps of a condition (n per condition in the title, "
        "``summary.csv``); whiskers: ± 1 SD over those steps. Lines join the conditions of one "
        "treadmill speed.",
        "Circled and labelled: conditions the analysis names as faulty (``encoder_fault`` in "
        "``qc.json``). "
        + (
            "; ".join(fault_text(row) for row in named.itertuples())
            + ". A count drop before the trial leaves ∫τ dθ unchanged but changes the torque "
            "the controller asked for; ``discrepancy.json`` (``reported_condition_12``) reads "
            f"{EMULATOR.key}'s condition 12 in closed form."
            if len(named)
            else "None in this run."
        ),
        f"Recorded spring activity against {EMULATOR.key}'s Table 6.1 rebuilt offline from the "
        "encoder (``qc.json``, ``table61_crosscheck``): "
        + (
            "; ".join(
                f"condition {row.condition} ({row.speed_m_per_s:g} m/s, κ "
                f"{row.stiffness_Nm_per_rad:g}): {departure_text(row)}"
                for row in departing.itertuples()
            )
            + " (circled and labelled). A controller that does not do what Table 6.1 says is a "
            "finding, not noise: the energy follows the activity as recorded."
            if len(departing)
            else "every step of every condition agrees with it."
        ),
    )
    return fig, caption


def angle_torque(samples: Mapping[str, pd.DataFrame], conditions: pd.DataFrame):
    """Mean brace angle, desired and delivered torque over the gait cycle per condition."""
    speeds = sorted(conditions["speed_m_per_s"].unique())
    fig, axes = figures.new_figure(ncols=len(speeds), nrows=2, width=4.0 * len(speeds), height=5.8)
    for col, speed in enumerate(speeds):
        rows = conditions[conditions["speed_m_per_s"] == speed].sort_values("stiffness_Nm_per_rad")
        colours = figures.ordered_colours(len(rows))
        steps = []
        for colour, row in zip(colours, rows.itertuples(), strict=True):
            frame = samples[row.trial]
            angle = cycle_curves(frame, "brace_angle_deg")
            steps.append(len(angle))
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
        note = f"{speed:g} m/s: mean, 0–100 % of cycle\n{count_text(steps)} per condition"
        axes[0, col].set_title(note, fontsize=7, loc="left")
        axes[1, col].set_title(note, fontsize=7, loc="left")
        axes[0, col].set(ylabel="brace knee flexion (deg)")
        axes[1, col].set(xlabel="gait cycle (%)", ylabel="torque (N·m)")
        axes[0, col].legend(fontsize=6, title="N·m/rad", title_fontsize=6)
        axes[1, col].legend(
            [Line2D([], [], color="0.4"), Line2D([], [], color="0.4", ls="--")],
            ["delivered (load cell)", "desired (controller)"],
            fontsize=6,
        )
    top, bottom = letter_range(0, len(speeds)), letter_range(len(speeds), len(speeds))
    caption = (
        f"Brace angle and torque over the gait cycle ({EMULATOR.key} fig. 6.4, reproduced), one "
        "column per treadmill speed.",
        f"Panels {top}: brace encoder knee flexion; panels {bottom}: delivered torque (load cell, "
        "solid) "
        "and the controller's desired torque (dashed). Each line is the mean over every "
        "complete step of a condition (heel strike to heel strike, resampled to 0–100 % of the "
        "cycle; n per condition in the titles); colour = emulated stiffness κ.",
    )
    return fig, caption


def encoder_vs_mocap(
    samples: Mapping[str, pd.DataFrame], conditions: pd.DataFrame, qc_trials: Mapping
):
    """Mean encoder angle against motion capture (mean ± SD) over the cycle, per condition."""
    rows = numbered(conditions)
    named = faults(qc_trials, conditions).set_index("trial")
    ncols = int(np.ceil(len(rows) / 2))
    fig, axes = figures.new_figure(ncols=ncols, nrows=2, width=2.3 * ncols, height=5.0)
    for ax, row in zip(axes.flat, rows.itertuples(), strict=False):
        frame = samples[row.trial]
        mocap = cycle_curves(frame, "anatomical_angle_deg")
        mean, sd = mocap.mean(axis=0), mocap.std(axis=0)
        ax.fill_between(CYCLE_PCT, mean - sd, mean + sd, color="#56B4E9", alpha=0.4, lw=0)
        ax.plot(
            CYCLE_PCT, cycle_curves(frame, "brace_angle_deg").mean(axis=0), color="#000000", lw=1.0
        )
        note = (
            f"{row.speed_m_per_s:g} m/s, κ {row.stiffness_Nm_per_rad:g}\n"
            f"0–100 % of cycle, n = {len(mocap)} steps"
        )
        if row.trial in named.index:
            note += "\nfault: " + named.loc[row.trial, "kinds"]
        ax.set_title(note, fontsize=6, loc="left")
        ax.tick_params(labelsize=6)
    for ax in axes.flat[len(rows) :]:
        ax.set_visible(False)
    fig.supylabel("knee flexion (deg)", fontsize=8)
    fig.supxlabel("gait cycle (%), 0–100 % from heel strike", fontsize=8)
    caption = (
        f"Brace encoder against motion capture ({EMULATOR.key} fig. 6.5, reproduced): "
        f"panels {letter_range(0, len(rows))}, one per condition in {EMULATOR.key}'s order "
        "(speed, then stiffness).",
        "Line: mean brace encoder angle; band: motion-capture knee angle, mean ± 1 SD; both "
        "over every complete step of the condition (n in each title), heel strike to heel "
        "strike resampled to 0–100 % of the cycle. The alignment of the two sensors (clock, "
        "zero, gain, cuff compliance with 95 % intervals) and the count drops are in "
        "``qc.json``; a panel whose trial the analysis names as faulty says so in its title.",
    )
    return fig, caption


def all_figures(summary, samples, conditions, qc_trials) -> dict:
    """Every emulator figure and its caption, by output name."""
    return {
        "energy_per_step": energy_per_step(summary, conditions, qc_trials),
        "angle_torque": angle_torque(samples, conditions),
        "encoder_vs_mocap": encoder_vs_mocap(samples, conditions, qc_trials),
    }
