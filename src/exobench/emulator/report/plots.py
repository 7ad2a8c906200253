"""Figures of the emulator group (Heer figs. 6.3–6.5 reproduced, and the recorded spring activity
against Table 6.1), each with its caption: every panel states its window and its steps, Heer's
surviving values are drawn beside the project's, and the faults the analysis names are marked
(encoder faults, and recorded spring activity departing from Table 6.1, on the energy figure)."""

from __future__ import annotations

import itertools
import textwrap
from collections.abc import Mapping

import numpy as np
import pandas as pd
from matplotlib.lines import Line2D
from matplotlib.patches import Patch

from exobench import figures
from exobench.studies import EMULATOR

CYCLE_PCT = np.linspace(0.0, 100.0, 101)
ENERGY_WINDOW = (
    "heel strike to heel strike, over the clutch's engaged window (Heer's \"while the spring was "
    "active\": the recorded clutch flag, else Table 6.1's engage and release rebuilt offline from "
    "the encoder)"
)
GAP_COLUMNS = ("mean_energy_active_J", "mean_energy_J")
TORQUE_WINDOW = "where the desired torque is non-zero (the torque window)"
DODGE = 0.08  # N·m/rad between the speeds' step points on the energy panel
SPREAD = 0.3  # half the width of a condition's slot on the spread panel
FAULT_COLOUR = "#D55E00"
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
        offset_deg=[
            qc_trials[t].get("encoder_moved_deg", qc_trials[t]["encoder_offset_deg"])
            for t in bad["trial"]
        ],
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


def heer_energies(reported: pd.DataFrame) -> pd.DataFrame:
    """Heer's Table 6.3 cells that survive in the text (seed002_reported.csv)."""
    rows = reported[reported["metric"] == "mean_energy_per_step_J"]
    return rows[["condition", "speed_m_per_s", "stiffness_Nm_per_rad", "value"]]


def dodge(speeds, speed: float) -> float:
    """Horizontal offset (N·m/rad) of a speed's points, so that the speeds stand side by side."""
    speeds = sorted(speeds)
    return DODGE * (speeds.index(speed) - (len(speeds) - 1) / 2)


def spread_x(condition: int, count: int) -> np.ndarray:
    """Positions of a condition's ``count`` steps on the spread panel, evenly across its slot."""
    return condition + (np.linspace(-SPREAD, SPREAD, count) if count > 1 else np.zeros(count))


def gap_text(rows: pd.DataFrame, reported: pd.DataFrame) -> str:
    """The caption's sentence on the gap to Heer's energies, by each definition."""
    parts = []
    for cell in heer_energies(reported).itertuples():
        mine = rows[
            np.isclose(rows["speed_m_per_s"], cell.speed_m_per_s)
            & np.isclose(rows["stiffness_Nm_per_rad"], cell.stiffness_Nm_per_rad)
        ]
        if mine.empty:
            continue
        active, torque = (100.0 * (mine[c].iloc[0] / float(cell.value) - 1.0) for c in GAP_COLUMNS)
        parts.append(
            f"condition {cell.condition:.0f}: {active:+.1f} % (torque window {torque:+.1f} %)"
        )
    if not parts:
        return ""
    return (
        f"The project's means miss {EMULATOR.key}'s energies by " + "; ".join(parts) + " "
        "(``summary.md`` gives the cause)."
    )


def energy_per_step(
    summary: pd.DataFrame,
    steps: pd.DataFrame,
    conditions: pd.DataFrame,
    qc_trials: Mapping,
    reported: pd.DataFrame,
):
    """(a) Energy per step against stiffness: every step, the condition means joined per speed,
    Heer's Table 6.3 values, the conditions the analysis names circled; (b) each step about its
    condition's mean, ± 1 SD, so that the spread shows."""
    fig, axes = figures.new_figure(ncols=2, width=9.0, height=3.8)
    ax, spread = axes[0, 0], axes[0, 1]
    columns = ["trial", "mean_energy_active_J", "sd_energy_active_J", "mean_energy_J"]
    rows = numbered(conditions).merge(summary[columns])
    speeds = sorted(rows["speed_m_per_s"].unique())
    colours = dict(zip(speeds, figures.PALETTE, strict=False))
    for speed in speeds:
        mine = rows[rows["speed_m_per_s"] == speed]
        shift = dodge(speeds, speed)
        points = steps[steps["trial"].isin(mine["trial"])].merge(
            mine[["trial", "stiffness_Nm_per_rad"]]
        )
        ax.plot(
            points["stiffness_Nm_per_rad"] + shift,
            points["energy_active_J"],
            ".",
            ms=3,
            alpha=0.5,
            color=colours[speed],
        )
        ax.plot(
            mine["stiffness_Nm_per_rad"],
            mine["mean_energy_active_J"],
            "-o",
            ms=4,
            color=colours[speed],
            label=f"{speed:g} m/s: steps and mean, clutch window (Heer's)",
        )
        ax.plot(
            mine["stiffness_Nm_per_rad"],
            mine["mean_energy_J"],
            "--x",
            ms=4,
            lw=0.8,
            color=colours[speed],
            label=f"{speed:g} m/s: mean, torque window",
        )
    for cell in heer_energies(reported).itertuples():
        ax.plot(
            cell.stiffness_Nm_per_rad,
            cell.value,
            "D",
            ms=7,
            mfc="none",
            mew=1.4,
            color=colours.get(cell.speed_m_per_s, "#000000"),
            label=f"{EMULATOR.key}, condition {cell.condition:.0f} ({cell.speed_m_per_s:g} m/s)",
        )
    named = faults(qc_trials, conditions)
    departing = activity_departures(qc_trials, conditions)
    notes = {row.trial: [f"condition {row.condition}: {row.kinds}"] for row in named.itertuples()}
    for row in departing.itertuples():
        notes.setdefault(row.trial, [f"condition {row.condition}"]).append(departure_text(row))
    for row in rows[rows["trial"].isin(list(notes))].itertuples():
        ax.plot(
            row.stiffness_Nm_per_rad,
            row.mean_energy_active_J,
            "o",
            ms=11,
            mfc="none",
            mew=1.2,
            color=FAULT_COLOUR,
            label=textwrap.fill("circled: " + "; ".join(notes[row.trial]), 34),
        )
    ax.set(xlabel="emulated stiffness κ (N·m/rad)", ylabel="energy stored per step (J)")
    ax.set_title(
        f"every step and the mean per condition, heel strike to heel strike\n"
        f"{count_text(summary['n_steps'])} per condition",
        fontsize=7,
        loc="left",
    )
    ax.legend(loc="upper left", fontsize=6)
    for row in rows.itertuples():
        values = steps.loc[steps["trial"] == row.trial, "energy_active_J"].to_numpy()
        spread.plot(
            spread_x(row.condition, values.size),
            1000.0 * (values - row.mean_energy_active_J),
            ".",
            ms=3,
            color=colours[row.speed_m_per_s],
        )
    spread.errorbar(
        rows["condition"],
        np.zeros(len(rows)),
        yerr=1000.0 * rows["sd_energy_active_J"],
        fmt="none",
        ecolor="0.2",
        capsize=3,
        lw=0.8,
    )
    spread.set_xticks(rows["condition"], [f"{c}" for c in rows["condition"]])
    spread.set(
        xlabel=f"condition ({EMULATOR.key}'s order: speed, then κ)",
        ylabel="step minus its condition's mean (mJ)",
    )
    spread.set_title(
        f"spread of the steps, heel strike to heel strike\n"
        f"{count_text(summary['n_steps'])} per condition",
        fontsize=7,
        loc="left",
    )
    caption = (
        f"Energy stored in the emulated spring per step ({EMULATOR.key} fig. 6.3, reproduced): the "
        f"measured brace torque integrated over the brace angle, {ENERGY_WINDOW}; beside it the "
        f"same integral {TORQUE_WINDOW}. A spring-free condition (κ = 0) keeps the measured "
        "torque's energy over the clutch window, the transparency residual. "
        + gap_text(rows, reported),
        "(a) Small dots: every step of a condition over the clutch window "
        "(``energy_per_step.parquet``, ``energy_active_J``), the two speeds "
        f"side by side ({DODGE:g} N·m/rad apart); large dots joined per treadmill speed: the "
        "condition's mean over the clutch window (``summary.csv``, ``mean_energy_active_J``); "
        "crosses on dashed lines: the mean over the torque window (``mean_energy_J``); open "
        f"diamonds: {EMULATOR.key}'s Table 6.3 values "
        "that survive in the text (conditions 6 and 12, ``raw/reference/seed002_reported.csv``; "
        "``heer_comparison.csv`` sets them beside the project's with their role and tolerance). "
        "(b) Every step minus its condition's mean, in mJ, the steps of a condition spread "
        "across its slot in the order they were walked; whiskers: ± 1 SD over the condition's "
        "steps. The spread is a few mJ, too small to see on (a)'s scale.",
        "Circled on (a) and named in its legend: conditions the analysis names as faulty "
        "(``encoder_fault`` in ``qc.json``): "
        + (
            "; ".join(fault_text(row) for row in named.itertuples())
            + ". A count drop before the trial leaves ∫τ dθ unchanged but changes the torque "
            "the controller asked for; ``discrepancy.json`` (``reported_condition_12``) reads "
            f"{EMULATOR.key}'s condition 12 in closed form."
            if len(named)
            else "none in this run."
        ),
        f"Recorded spring activity against {EMULATOR.key}'s Table 6.1 rebuilt offline from the "
        "encoder (``qc.json``, ``table61_crosscheck``; per gait phase in "
        "``activity_vs_table61.png``): "
        + (
            "; ".join(
                f"condition {row.condition} ({row.speed_m_per_s:g} m/s, κ "
                f"{row.stiffness_Nm_per_rad:g}): {departure_text(row)}"
                for row in departing.itertuples()
            )
            + " (circled). A controller that does not do what Table 6.1 says is a "
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


# The motion-capture angle each block of the encoder figure draws: as recorded, and aligned to the
# encoder by the trial's own fit (qc.json: clock, zero, gain; count drops removed).
MOCAP_VIEWS = {
    "raw": ("mocap_angle_deg", "#56B4E9", "motion capture as recorded, mean ± 1 SD"),
    "aligned": (
        "anatomical_angle_deg",
        "#E69F00",
        "motion capture aligned to the encoder (qc.json), mean ± 1 SD",
    ),
}


def encoder_vs_mocap(
    samples: Mapping[str, pd.DataFrame], conditions: pd.DataFrame, qc_trials: Mapping
):
    """Mean encoder angle against motion capture (mean ± SD) over the cycle, per condition:
    first as motion capture recorded it, then aligned to the encoder."""
    rows = numbered(conditions)
    named = faults(qc_trials, conditions).set_index("trial")
    ncols = int(np.ceil(len(rows) / 2))
    per_view = 2 * ncols
    fig, axes = figures.new_figure(ncols=ncols, nrows=4, width=2.3 * ncols, height=10.0)
    for block, (view, (column, colour, _)) in enumerate(MOCAP_VIEWS.items()):
        panels = axes.flat[block * per_view : (block + 1) * per_view]
        for ax, row in zip(panels, rows.itertuples(), strict=False):
            frame = samples[row.trial]
            mocap = cycle_curves(frame, column)
            mean, sd = mocap.mean(axis=0), mocap.std(axis=0)
            encoder = cycle_curves(frame, "brace_angle_deg").mean(axis=0)
            ax.fill_between(CYCLE_PCT, mean - sd, mean + sd, color=colour, alpha=0.35, lw=0)
            ax.plot(CYCLE_PCT, mean, color=colour, lw=1.0)
            ax.plot(CYCLE_PCT, encoder, color="#000000", lw=1.0)
            note = (
                f"{view}: {row.speed_m_per_s:g} m/s, κ {row.stiffness_Nm_per_rad:g}\n"
                f"0–100 % of cycle, n = {len(mocap)} steps\n"
                f"means: encoder {np.mean(encoder):.1f}°, mocap {np.mean(mean):.1f}°"
            )
            if row.trial in named.index:
                note += "\nfault: " + named.loc[row.trial, "kinds"]
            ax.set_title(note, fontsize=6, loc="left")
            ax.tick_params(labelsize=6)
        for ax in panels[len(rows) :]:
            ax.set_visible(False)
    key = [Line2D([], [], color="#000000", lw=1.0, label="brace encoder, mean")]
    key += [
        Patch(color=colour, alpha=0.5, label=label) for _, colour, label in MOCAP_VIEWS.values()
    ]
    fig.legend(handles=key, loc="outside upper center", ncols=3, fontsize=7)
    fig.supylabel("knee flexion (deg)", fontsize=8)
    fig.supxlabel("gait cycle (%), 0–100 % from heel strike", fontsize=8)
    count = len(rows)
    caption = (
        f"Brace encoder against motion capture ({EMULATOR.key} fig. 6.5, reproduced), one panel "
        f"per condition in {EMULATOR.key}'s order (speed, then stiffness): panels "
        f"{letter_range(0, count)} with motion capture as recorded (the comparison of "
        f"{EMULATOR.key}'s figure), panels {letter_range(per_view, count)} with motion capture "
        "aligned to the encoder.",
        "Black line: mean brace encoder angle; coloured line and band: motion-capture knee "
        "angle, mean ± 1 SD; both over every complete step of the condition (n in each title), "
        "heel strike to heel strike resampled to 0–100 % of the cycle. Each title gives the "
        "two lines' means over the cycle. As recorded, motion capture keeps its "
        "own zero, gain and clock, so a small gap is usual; a count drop before a trial adds its "
        "size to that trial's gap. Aligned, the trial's own fit (``qc.json``: clock, zero, gain "
        "and cuff compliance with 95 % intervals; count drops found during the trial removed) "
        "takes a constant offset out, so a drop before the trial no longer shows: the summary "
        "finds it by comparing each trial's offset with the session's. A panel whose trial the "
        "analysis names as faulty says so in its title.",
    )
    return fig, caption


def activity_vs_table61(
    samples: Mapping[str, pd.DataFrame], conditions: pd.DataFrame, qc_trials: Mapping
):
    """Share of steps with the clutch engaged over the cycle by Table 6.1 (the recorded flag, else
    rebuilt offline: engage and release, no spring-law gate) against the share with torque
    desired, per speed and stiffness, κ = 0 included."""
    speeds = sorted(conditions["speed_m_per_s"].unique())
    fig, axes = figures.new_figure(
        ncols=max(len(speeds), 1), width=4.2 * max(len(speeds), 1), height=3.4
    )
    departing = activity_departures(qc_trials, conditions).set_index("trial")
    starts = {"clutch": [], "torque": []}
    for ax, speed in zip(axes.flat, speeds, strict=False):
        rows = conditions[conditions["speed_m_per_s"] == speed].sort_values("stiffness_Nm_per_rad")
        colours = figures.ordered_colours(len(rows))
        counts = []
        for colour, row in zip(colours, rows.itertuples(), strict=True):
            recorded = cycle_curves(samples[row.trial], "active")
            counts.append(len(recorded))
            clutch = cycle_curves(samples[row.trial], "clutch_window").mean(axis=0)
            torque = recorded.mean(axis=0)
            starts["clutch"].append(first_half(clutch))
            if row.stiffness_Nm_per_rad > 0:
                starts["torque"].append(first_half(torque))
            ax.plot(CYCLE_PCT, clutch, color=colour, lw=4.0, alpha=0.3, solid_capstyle="butt")
            ax.plot(
                CYCLE_PCT,
                torque,
                color=colour,
                lw=1.0,
                ls=":" if row.stiffness_Nm_per_rad == 0 else "-",
                label=f"κ = {row.stiffness_Nm_per_rad:g}",
            )
            if row.trial in departing.index:  # the phase bins where the recording departs
                for low, high in qc_trials[row.trial]["table61_crosscheck"][
                    "phases_disagreeing_pct"
                ]:
                    ax.axvspan(low, high, color=colour, alpha=0.12, lw=0)
        ax.set_title(
            f"{speed:g} m/s: 0–100 % of cycle\n{count_text(counts)} per condition",
            fontsize=7,
            loc="left",
        )
        ax.set(xlabel="gait cycle (%)", ylabel="share of steps")
        first = ax.legend(fontsize=6, title="N·m/rad", title_fontsize=6, loc="upper left")
        ax.add_artist(first)
        ax.legend(
            [Line2D([], [], color="0.4", lw=1.0), Line2D([], [], color="0.4", lw=4.0, alpha=0.3)],
            ["torque desired", "clutch engaged (Table 6.1)"],
            fontsize=6,
            loc="center left",
        )
    summary = "; ".join(
        f"condition {row.condition} ({row.speed_m_per_s:g} m/s, κ {row.stiffness_Nm_per_rad:g}): "
        + departure_text(row)
        for row in departing.reset_index().itertuples()
    )
    clutch_at = np.nanmean(starts["clutch"]) if starts["clutch"] else np.nan
    torque_at = np.nanmean(starts["torque"]) if starts["torque"] else np.nan
    caption = (
        f"When the emulated spring may act against {EMULATOR.key}'s Table 6.1 (virtual clutch: "
        "engage at a peak flexion above 40°, release at the next peak extension), one panel per "
        f"treadmill speed {letter_range(0, len(speeds))}, every condition in its own colour, "
        "κ = 0 dotted.",
        "Wide light line: share of the condition's steps with the clutch engaged, from the "
        "recorded clutch flag where the files have one, else Table 6.1's engage and release "
        "rebuilt offline from the encoder (not gated by the spring law): the window "
        f"{EMULATOR.key}'s energy integrates over (“while the spring was active”, about 75–100 % "
        "of the cycle). Thin line: share of steps with torque desired (the spring law "
        "τ = κ·max(0, θ_eq − θ) is non-zero only once the knee extends past θ_eq, so it starts "
        f"later; κ = 0 never asks for torque). Half the steps engaged by {clutch_at:.0f} % of the "
        f"cycle; torque desired from {torque_at:.0f} % (conditions with a spring). Every complete "
        "step, heel strike to heel strike resampled to 0–100 % of the cycle (n per condition in "
        "the titles). The energy per step integrates over the clutch window; the torque window's "
        "value stands beside it (``summary.csv``).",
        "Steps whose recorded activity departs from Table 6.1 with the spring law's gate by more "
        "than ``emulator.analysis.activity_tolerance_s`` (``qc.json``, ``table61_crosscheck``, "
        "per 10 % phase bin, shaded in the condition's colour): "
        + (summary + "." if summary else "none in this run."),
    )
    return fig, caption


def first_half(share: np.ndarray) -> float:
    """The first cycle % at which at least half the steps are in the window (NaN if never)."""
    above = np.flatnonzero(share >= 0.5)
    return float(CYCLE_PCT[above[0]]) if above.size else np.nan


def all_figures(summary, steps, samples, conditions, qc_trials, reported) -> dict:
    """Every emulator figure and its caption, by output name."""
    return {
        "energy_per_step": energy_per_step(summary, steps, conditions, qc_trials, reported),
        "angle_torque": angle_torque(samples, conditions),
        "encoder_vs_mocap": encoder_vs_mocap(samples, conditions, qc_trials),
        "activity_vs_table61": activity_vs_table61(samples, conditions, qc_trials),
    }
