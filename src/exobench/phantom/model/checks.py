"""Direct checks of the rig's assumptions: what the recordings show with no model at all.

Some rows of the assumption table (docs/assumptions.md) need no fit: the markers alone give the
segment lengths, the ankle's path and whether the bars stay parallel to their segments with the
clutch open; the swing alone gives the knee moment with nothing engaged; the channels alone show
whether one follows another it should not; the manifest's spring rates against the measured
exoskeleton stiffness show whether two trials were swapped. Each check is one row of
:mod:`exobench.selection.checks` (the emulator's checks share it): the value over the included
strides with a 95 % interval, what the contract expects, the tolerance and the decision.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence

import numpy as np
import pandas as pd

from exobench.phantom.model.assumptions import TABLE
from exobench.phantom.rig import ANALOG_RATE_HZ, LOAD_CELLS, Rig
from exobench.selection import checks as shared
from exobench.selection.checks import row

# The kinetics columns the checks read (the job reads only these: 11 of the table's 30).
KINETICS_COLUMNS = ["stride", "t_s", "gait_cycle_pct", "knee_moment_Nm", "phantom_knee_angle_rad",
                    "exo_knee_angle_rad", "spring_force_N", "ankle_force_y_N",
                    *(f"{cell}_N" for cell in LOAD_CELLS)]  # fmt: skip


def windows(kinetics: pd.DataFrame, strides: pd.DataFrame, pct: Sequence[float]) -> pd.DataFrame:
    """The kinetics samples of the included strides within a window of the gait cycle (%)."""
    included = set(strides.loc[strides["included"], "stride"])
    pct_low, pct_high = (float(p) for p in pct)
    keep = kinetics["stride"].isin(included) & kinetics["gait_cycle_pct"].between(
        pct_low, pct_high, inclusive="left")  # fmt: skip
    return kinetics[keep]


def per_stride(frame: pd.DataFrame, values: np.ndarray, how: str = "mean") -> np.ndarray:
    """A sample quantity reduced per stride (mean or root mean square), strides in order."""
    series = pd.Series(values**2 if how == "rms" else values, index=frame["stride"].to_numpy())
    reduced = series.groupby(level=0).mean().to_numpy()
    return np.sqrt(reduced) if how == "rms" else reduced


def stride_regression(frame: pd.DataFrame, y: np.ndarray, columns: Sequence[np.ndarray]):
    """Least-squares coefficients of y on the columns within each stride (all centred per
    stride), (strides, columns): the normal equations from per-stride sums, solved at once."""
    index = frame["stride"].to_numpy()
    data = pd.DataFrame({"y": y, **{f"x{i}": x for i, x in enumerate(columns)}})
    centred = (data - data.groupby(index).transform("mean")).to_numpy()
    x, target = centred[:, 1:], centred[:, :1]
    k = x.shape[1]
    products = np.concatenate(
        [x[:, :, None] * x[:, None, :], x[:, :, None] * target[:, None, :]], axis=2
    ).reshape(len(x), -1)
    sums = pd.DataFrame(products).groupby(index).sum().to_numpy().reshape(-1, k, k + 1)
    gram, cross = sums[:, :, :-1], sums[:, :, -1]
    solvable = np.abs(np.linalg.det(gram)) > 0
    out = np.full(cross.shape, np.nan)
    out[solvable] = np.linalg.solve(gram[solvable], cross[solvable][:, :, None])[:, :, 0]
    return out


def geometry(angles: pd.DataFrame, kinetics: pd.DataFrame, strides: pd.DataFrame):
    """Joint centres (mm) at the samples of the included strides' engaged and free parts."""
    frame = windows(kinetics, strides, (0.0, 100.0))
    index = np.round(frame["t_s"].to_numpy() * ANALOG_RATE_HZ).astype(int)
    times = np.round(angles["t_s"].to_numpy() * ANALOG_RATE_HZ).astype(int)
    rows = np.searchsorted(times, index)
    joints = {j: angles[[f"{j}_x_m", f"{j}_y_m"]].to_numpy()[rows] * 1000.0
              for j in ("hip", "knee", "ankle")}  # fmt: skip
    return frame, joints


def marker_checks(parts: Sequence[Mapping], rig: Rig, settings: Mapping) -> list[dict]:
    """Segment lengths, the knee's centre on its axis (the knee-to-ankle distance must not
    follow the knee angle: markers off the axis make it), the ankle's path and the bars'
    angle with the clutch open. A knee centre off its axis biases the lengths and the phantom's
    angle: the length and bar checks then say so instead of deciding."""
    thigh, shank, wobble, offset, bars = [], [], [], [], []
    for part in parts:
        frame, joints = geometry(part["angles"], part["kinetics"], part["strides"])
        shank_mm = np.linalg.norm(joints["ankle"] - joints["knee"], axis=1)
        thigh.append(per_stride(frame, np.linalg.norm(joints["knee"] - joints["hip"], axis=1)))
        shank.append(per_stride(frame, shank_mm))
        centred = shank_mm - np.repeat(per_stride(frame, shank_mm),
                                       frame.groupby("stride").size().to_numpy())  # fmt: skip
        wobble.append(per_stride(frame, centred, "rms"))
        offset.append(per_stride(frame, joints["ankle"][:, 0] - joints["hip"][:, 0]))
        swing = windows(part["kinetics"], part["strides"], settings["swing_pct"])
        gap = swing["exo_knee_angle_rad"] - swing["phantom_knee_angle_rad"]
        bars.append(per_stride(swing, np.rad2deg(gap.to_numpy())))
    length_tol = float(settings["length_tolerance_mm"])
    axis = row(
        "knee_markers",
        "knee_axis",
        "knee-to-ankle distance's change over the stride (RMS)",
        np.concatenate(wobble),
        0.0,
        float(settings["knee_axis_tolerance_mm"]),
        "mm",
    )
    rows = [
        row("segment_lengths", "segment_lengths", "hip to knee (thigh)", np.concatenate(thigh),
            1000.0 * rig.thigh_length_m, length_tol, "mm"),
        row("segment_lengths", "segment_lengths", "knee to ankle (shank)", np.concatenate(shank),
            1000.0 * rig.shank_length_m, length_tol, "mm"),
        axis,
        row("ankle_path", "ankle_path", "ankle anterior of the hip", np.concatenate(offset), 0.0,
            float(settings["ankle_offset_tolerance_mm"]), "mm"),
        row("bars", "bars_parallel", "exoskeleton minus phantom knee angle, clutch open",
            np.concatenate(bars), 0.0, float(settings["bar_angle_tolerance_deg"]), "deg"),
    ]  # fmt: skip
    if axis["decision"] != "holds":
        for entry in rows:
            if entry["check"] in ("segment_lengths", "bars_parallel") and (
                    entry["decision"] == "violated"):  # fmt: skip
                entry["decision"] = "undecided"
                entry["detail"] = "the knee's centre is not on its axis (knee markers)"
    return rows


def swing_checks(parts: Sequence[Mapping], settings: Mapping) -> list[dict]:
    """The knee moment with the clutch open (its mean, and half its difference between the
    knee flexing and extending: a spring, a loss or an offset of the phantom's own), and the
    channels that should not follow others: LC_SPRING against the ankle force with the clutch
    open, each ankle cell's departure from its share of their sum against LC_SPRING while it
    is loaded (beside the sum and its rate, so that a gain or a lag of the cell is not taken
    for it)."""
    mean, loop, spring, cells = [], [], [], {cell: [] for cell in LOAD_CELLS}
    for part in parts:
        swing = windows(part["kinetics"], part["strides"], settings["swing_pct"])
        moment = swing["knee_moment_Nm"].to_numpy()
        flexing = np.gradient(swing["phantom_knee_angle_rad"].to_numpy()) > 0
        mean.append(per_stride(swing, moment))
        loop.append(0.5 * (per_stride(swing, np.where(flexing, moment, np.nan))
                           - per_stride(swing, np.where(flexing, np.nan, moment))))  # fmt: skip
        spring.append(stride_regression(swing, swing["spring_force_N"].to_numpy(),
                                        [swing["ankle_force_y_N"].to_numpy()])[:, 0])  # fmt: skip
        engaged = windows(part["kinetics"], part["strides"], settings["window_pct"])
        total = engaged[[f"{c}_N" for c in LOAD_CELLS]].to_numpy().sum(axis=1)
        rate = np.gradient(total) * ANALOG_RATE_HZ
        for cell in LOAD_CELLS:
            values = engaged[f"{cell}_N"].to_numpy()
            share = np.nanmedian(values / np.where(total, total, np.nan))
            regressors = [engaged["spring_force_N"].to_numpy(), total, rate]
            cells[cell].append(stride_regression(engaged, values - share * total,
                                                 regressors)[:, 0])  # fmt: skip
    moment_tol, share_tol = (float(settings[k]) for k in ("swing_moment_tolerance_Nm",
                                                            "crosstalk_tolerance"))  # fmt: skip
    return [
        row("clutch_open", "swing_moment", "knee moment with the clutch open (mean)",
            np.concatenate(mean), 0.0, moment_tol, "N·m"),
        row("clutch_open", "swing_moment", "knee moment with the clutch open (flexing minus "
            "extending, half)",
            np.concatenate(loop), 0.0, moment_tol, "N·m"),
        row("channels_apart", "channels_apart", "LC_SPRING per newton of ankle force, clutch open",
            np.concatenate(spring), 0.0, share_tol, "N/N"),
        *(row("channels_apart", "channels_apart",
              f"{cell} off its share of the ankle force, per newton of LC_SPRING",
              np.concatenate(values), 0.0, share_tol, "N/N")
          for cell, values in cells.items()),
    ]  # fmt: skip


def spring_order(parts: Sequence[Mapping]) -> list[dict]:
    """The manifest's spring rates against the exoskeleton stiffness measured per trial
    (median over included strides): Kendall's τ = 1 − 2·(pairs out of order)/(pairs), the value
    decided on: "violated" below 1, naming the pairs out of order."""
    rates = np.array([float(p["spring"]) for p in parts])
    measured = np.array([
        float(np.nanmedian(p["metrics"].loc[p["metrics"]["included"],
                                            "exo_stiffness_Nm_per_rad"]))
        for p in parts
    ])  # fmt: skip
    if len(parts) < 2 or not np.all(np.isfinite(measured)):
        return []
    names = [str(p["trial"]) for p in parts]
    swapped = [f"{names[i]} and {names[j]}" for i in range(len(parts))
               for j in range(i + 1, len(parts))
               if (rates[i] - rates[j]) * (measured[i] - measured[j]) < 0]  # fmt: skip
    pairs = len(parts) * (len(parts) - 1) // 2
    tau = 1.0 - 2.0 * len(swapped) / pairs  # Kendall's τ: (in order − swapped) / pairs
    detail = ("the manifest's rates and the measured stiffness rise in the same order"
              if not swapped else "measured stiffness out of the manifest's order: "
              + "; ".join(swapped))  # fmt: skip
    return [shared.stated("spring", "spring_order",
                          "Kendall rank correlation of manifest rate and measured exoskeleton "
                          "stiffness (1: every pair in order)",
                          tau, 1.0, 0.0, "1", len(parts), "violated" if swapped else "holds",
                          detail)]  # fmt: skip


def checks(parts: Sequence[Mapping], rig: Rig, settings: Mapping) -> pd.DataFrame:
    """Every direct check of the recordings, one row each (:data:`COLUMNS`)."""
    rows = [*marker_checks(parts, rig, settings), *swing_checks(parts, settings),
            *spring_order(parts)]  # fmt: skip
    return shared.frame(rows)


def named(table: pd.DataFrame) -> list[tuple[str, ...]]:
    """The violated assumptions a check names as the cause: rows the check alone sees (their
    relaxations no model term has), each with the rows it cannot tell it from; the others say
    what departs, not why (a knee moment with the clutch open comes from any of several
    rows)."""
    return shared.named(table, TABLE)


def markdown(table: pd.DataFrame) -> list[str]:
    """The checks as a section of summary.md (the assumptions: docs/assumptions.md)."""
    return shared.markdown(table, "docs/assumptions.md")
