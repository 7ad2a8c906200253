"""Heer's numbers beside the project's: one row per number of the thesis the group computes.

Each row says what kind of agreement it can show (``role``): a *twin setting* (the twin or the
config was given Heer's observation, directly or through a value sized from it, so the number
comes back by construction), a *calibration target* (a free constant the thesis does not give
was chosen so that this number lands near Heer's), a *prediction* (nothing was chosen with the
number in mind) or, on a lab's recordings, a *lab measurement*. Only predictions test the
project. The tolerance is the number's rounding (half a unit of the last digit Heer gives) plus
the 95 % half-width of the project's value where that is a mean over steps; a row outside it, or
one the run cannot compute, says why (``reason``).
"""

from __future__ import annotations

import numpy as np
import pandas as pd

from exobench.emulator.study.heer_numbers import INPUTS, Context, number

COLUMNS = [
    "metric",
    "condition",
    "speed_m_per_s",
    "stiffness_Nm_per_rad",
    "heer_value",
    "section",
    "project_value",
    "unit",
    "relation",
    "error",
    "rel_error",
    "rounding",
    "interval_half_width",
    "tolerance",
    "within_tolerance",
    "role",
    "basis",
    "reason",
]
ROLES = ("twin setting", "calibration target", "prediction", "lab measurement")


LAB = (
    "measured on the lab's recordings, not Heer's subject and rig: a difference is a finding "
    "about the two, not an error of the workflow"
)


def rounding(text: str) -> float:
    """Half a unit of the last digit written: '0.634' → 0.0005, '314' → 0.5."""
    digits = text.strip().partition(".")[2]
    return 0.5 * 10.0 ** -len(digits)


def miss_reason(entry, ctx: Context, row, found, lab: bool) -> str:
    """Why a row misses: a lab's recordings are not Heer's; the twin's, as its entry says."""
    if lab:
        return LAB
    return entry.reason if isinstance(entry.reason, str) else entry.reason(ctx, row, found)


def compare(ctx: Context) -> pd.DataFrame:
    """One row per compared thesis number (every row of the reference but its inputs)."""
    rows = []
    for row in ctx.reported.itertuples(index=False):
        if row.metric in INPUTS:
            continue
        entry = number(row.metric)
        heer, rounded = float(row.value), rounding(row.value)
        row = row._replace(condition=None if pd.isna(row.condition) else int(row.condition))
        lab = entry.measured and not ctx.synthetic
        role = "lab measurement" if lab else entry.role(ctx, row)
        found = entry.compute(ctx, row)
        out = {
            "metric": row.metric,
            "condition": row.condition,
            "speed_m_per_s": row.speed_m_per_s,
            "stiffness_Nm_per_rad": row.stiffness_Nm_per_rad,
            "heer_value": heer,
            "section": row.source,
            "unit": row.unit,
            "relation": entry.relation,
            "rounding": rounded,
            "role": role,
        }
        if isinstance(found, str):
            rows.append(
                {
                    **out,
                    "project_value": np.nan,
                    "within_tolerance": False,
                    "basis": "not computed",
                    "reason": f"not computed: {found}",
                }
            )
            continue
        error = found.value - heer
        tolerance = rounded + found.half_width
        within = error <= tolerance if entry.relation == "≤" else abs(error) <= tolerance
        reason = "" if within else miss_reason(entry, ctx, row, found, lab)
        rows.append(
            {
                **out,
                "project_value": found.value,
                "error": error,
                "rel_error": error / abs(heer),
                "interval_half_width": found.half_width,
                "tolerance": tolerance,
                "within_tolerance": bool(within),
                "basis": found.basis,
                "reason": reason,
            }
        )
    table = pd.DataFrame(rows).reindex(columns=COLUMNS)
    return table.astype({"condition": "Int64"})


def prediction_line(table: pd.DataFrame, key: str) -> str:
    """The summary's line: how many of the thesis's numbers the project predicts, and hits."""

    def counted(role: str) -> tuple[int, int]:
        rows = table[(table["role"] == role) & table["project_value"].notna()]
        return len(rows), int(rows["within_tolerance"].sum())

    predicted, hits = counted("prediction")
    line = (
        f"Of the {len(table)} numbers of {key}'s in [heer_comparison.csv](heer_comparison.csv), "
        f"{predicted} are predictions of the project, {hits} of them within tolerance "
        "(rounding plus the 95 % interval)"
    )
    measured, agreeing = counted("lab measurement")
    if measured:
        line += f"; {measured} are lab measurements, {agreeing} of them within tolerance"
    set_up = [f"{n} {role}s" for role in ROLES[:2] if (n := counted(role)[0])]
    if set_up:
        line += (
            f"; {' and '.join(set_up)} were put into the twin or the config, or chosen to "
            "match, and are not counted as reproduced"
        )
    missing = int(table["project_value"].isna().sum())
    if missing:
        line += f"; {missing} could not be computed (the table says why)"
    return line + "."
