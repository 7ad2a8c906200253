"""Direct checks of a rig's assumptions, the same for every group: what the recordings show with
no model at all, one verdict row per check.

A group's checks (its ``model.checks``) reduce its recordings to per-unit values of a quantity
(a stride, a step or a trial each); this module makes each into one row: the assumption (a row
key of the group's assumption table), the check, the quantity, its value over the units with a
95 % interval (Student's t over the units' own values), what the contract expects, the
tolerance, and the decision: "holds" (the interval lies within the tolerance of the expected
value), "violated" (it lies beyond it) or "undecided" (across the tolerance's edge, or nothing
to decide on). The rows' warning for summary.md's first screen and their section of it are
written here too.
"""

from __future__ import annotations

from collections.abc import Iterable, Mapping

import numpy as np
import pandas as pd
from scipy.special import fdtri, stdtrit  # F and Student's t quantiles (scipy.stats' own)

from exobench.selection.assumptions import Assumption
from exobench.selection.summary import interval_text

COLUMNS = ["assumption", "check", "quantity", "measured", "ci_low", "ci_high", "expected",
           "tolerance", "unit", "strides", "decision", "detail"]  # fmt: skip


def interval(values) -> tuple[float, float, float]:
    """Mean and 95 % interval (Student's t) of per-unit values."""
    values = np.asarray(values, float)
    values = values[np.isfinite(values)]
    if values.size < 2:
        mean = float(values.mean()) if values.size else np.nan
        return mean, np.nan, np.nan
    half = stdtrit(values.size - 1, 0.975) * values.std(ddof=1) / np.sqrt(values.size)
    return float(values.mean()), float(values.mean() - half), float(values.mean() + half)


def decision(low: float, high: float, expected: float, tolerance: float) -> str:
    """Whether an interval lies within the tolerance of the expected value, beyond it, or
    across its edge."""
    if not (np.isfinite(low) and np.isfinite(high)):
        return "undecided"
    if low > expected + tolerance or high < expected - tolerance:
        return "violated"
    if low >= expected - tolerance and high <= expected + tolerance:
        return "holds"
    return "undecided"


def row(assumption: str, check: str, quantity: str, values, expected: float, tolerance: float,
        unit: str, detail: str = "") -> dict:  # fmt: skip
    """One check's row from its per-unit values (``strides``: how many were counted)."""
    mean, low, high = interval(values)
    return {"assumption": assumption, "check": check, "quantity": quantity, "measured": mean,
            "ci_low": low, "ci_high": high, "expected": expected, "tolerance": tolerance,
            "unit": unit, "strides": int(np.isfinite(np.asarray(values, float)).sum()),
            "decision": decision(low, high, expected, tolerance), "detail": detail}  # fmt: skip


def stated(assumption: str, check: str, quantity: str, measured: float, expected: float,
           tolerance: float, unit: str, count: int, verdict: str, detail: str) -> dict:  # fmt: skip
    """A check's row without an interval (a count, a rank, or nothing in the files to decide
    on): its decision as the check states it, with the reason in ``detail``."""
    return {"assumption": assumption, "check": check, "quantity": quantity,
            "measured": measured, "ci_low": np.nan, "ci_high": np.nan, "expected": expected,
            "tolerance": tolerance, "unit": unit, "strides": int(count), "decision": verdict,
            "detail": detail}  # fmt: skip


def frame(rows: Iterable[dict]) -> pd.DataFrame:
    """The rows as the checks' table (:data:`COLUMNS`)."""
    return pd.DataFrame(list(rows), columns=COLUMNS)


def between_rows(stability: Mapping) -> list[dict]:
    """Each constant a report's parameter stability tested (:mod:`exobench.selection.stability`)
    as a check's row, the direct check of the table's rows that must hold between trials: its
    row, Welch's F against its critical value F(1 − α; df), the units of the trials compared,
    the decision (violated when flagged) and the departing trials in words."""
    rows = []
    for e in (e for e in stability["constants"] if e["tested"]):
        apart = "; ".join(f"{d['trial']} departs" for d in e["departing"]) if e["flag"] else ""
        rows.append({
            "assumption": e["assumption"], "check": "stability",
            "quantity": f"{e['name']} ({e['parameter']}) per trial: Welch's F against its "
            f"critical value (Holm-adjusted p {e['p_adjusted']:.2g})",
            "measured": e["statistic"], "ci_low": np.nan, "ci_high": np.nan,
            "expected": float(fdtri(*e["df"], 1.0 - stability["alpha"])), "tolerance": 0.0,
            "unit": "1",
            "strides": sum(t["units"] for t in e["trials"] if t["trial"] in e["used"]),
            "decision": "violated" if e["flag"] else "holds", "detail": apart,
        })  # fmt: skip
    return rows


def with_stability(table: pd.DataFrame, report: Mapping) -> pd.DataFrame:
    """The direct checks and, as the check of the rows that must hold between trials, the
    discrepancy report's parameter stability (:func:`between_rows`, one row per constant)."""
    rows = between_rows(report["stability"]) if report.get("stability") else []
    return pd.concat([table, frame(rows)], ignore_index=True) if rows else table


def violated(table: pd.DataFrame) -> list[str]:
    """The assumptions a check finds violated (table rows' keys, once each)."""
    return list(dict.fromkeys(table.loc[table["decision"] == "violated", "assumption"]))


def named(table: pd.DataFrame, rows: Iterable[Assumption]) -> list[tuple[str, ...]]:
    """The violated assumptions a check names as the cause: rows of the assumption table
    ``rows`` the check alone sees (their relaxations no model term has), each with the rows its
    check cannot tell it from (its ``alike``: the cause is one of them); the others say what
    departs, not why."""
    seen = {r.key: r.alike for r in rows if any(x.checked for x in r.relaxations)}
    return [(key, *seen[key]) for key in violated(table) if key in seen]


def implicated(table: pd.DataFrame, report: Mapping, rows: Iterable[Assumption],
               said: Iterable[tuple[str, str]] = ()) -> list[str]:  # fmt: skip
    """Per observable a flagged residual test of ``report`` finds structure in, the violated
    checks of ``table`` on assumption rows of ``rows`` that touch that observable and that
    nothing the report claims or names holds (none of the row's relaxations), but those
    (assumption, check) already ``said``: the rows its misfit implicates, in words."""
    held = {*(e["effect"] for e in report["effects_found"]),
            *(t["term"] for t in report["discovery"]["named"])}  # fmt: skip
    flagged = {t["observable"] for t in report["unexplained"]["tests"] if t["flag"]}
    by_key, said = {r.key: r for r in rows}, set(said)
    broken = table[table["decision"] == "violated"]
    out = []
    for obs in (o for o in report["observable_order"] if o in flagged):
        found = []
        for entry in broken.itertuples():
            row = by_key.get(entry.assumption)
            if row is None or obs not in row.observables or (row.key, entry.check) in said:
                continue
            if {held_name for r in row.relaxations
                for held_name in (r.registry, row.term(r.family))} & held:  # fmt: skip
                continue
            unit = "" if entry.unit == "1" else f" {entry.unit}"
            found.append(f"{row.key} ({entry.check}: {entry.quantity} {entry.measured:.3g}{unit} "
                         f"against {entry.expected:.3g} ± {entry.tolerance:.3g})")  # fmt: skip
        if found:
            plural = "s" if len(found) > 1 else ""
            out.append(f"the misfit of the {report['observable_names'][obs]} implicates the "
                       f"assumption row{plural} {'; '.join(found)}")  # fmt: skip
    return out


def _detail(entry) -> str:
    """A row's detail, or empty (a CSV read back gives NaN for an empty one)."""
    return entry if isinstance(entry, str) and entry else ""


def warning(table: pd.DataFrame) -> list[str]:
    """A warning for summary.md's first screen when a check finds an assumption broken: which
    assumption, what was seen (empty when every check holds or stays undecided)."""
    broken = table[table["decision"] == "violated"]
    if broken.empty:
        return []
    said = [_detail(r["detail"]) or r["quantity"] for _, r in broken.iterrows()]
    seen = "; ".join(f"{a}: {s}" for a, s in zip(broken["assumption"], said, strict=True))
    return [f"**Warning:** the recordings break {len(broken)} of the rig's assumptions ({seen}); "
            "every estimate below rests on them. Check the rig or the manifest first (the "
            "checks' table further down).", ""]  # fmt: skip


def markdown(table: pd.DataFrame, doc: str) -> list[str]:
    """The checks as a section of summary.md: one row per check, the violated first, each with
    its assumption (``doc``, the group's table in words), value, 95 % interval and decision."""
    if table.empty:
        return []
    rank = table["decision"].map({"violated": 0, "undecided": 1, "holds": 2})
    order = table.assign(rank=rank).sort_values("rank", kind="stable")
    held = int((table["decision"] == "holds").sum())
    lines = ["## What the recordings show directly, with no model", "",
             f"{held} of {len(table)} checks of the rig's assumptions hold "
             f"([assumption_checks.csv](assumption_checks.csv); the assumptions: {doc}).", "",
             "| assumption | quantity | measured [95 % interval] | expected | decision |",
             "|---|---|---|---|---|"]  # fmt: skip
    for _, r in order.iterrows():
        ends = [r["ci_low"], r["ci_high"]] if np.isfinite(r["ci_low"]) else None
        unit = "" if r["unit"] == "1" else f" {r['unit']}"
        shown = interval_text(r["measured"], ends, "1")  # digits that show the interval's width
        value = "—" if not np.isfinite(r["measured"]) else f"{shown}{unit}"
        expected = f"{r['expected']:.3g}" + (f" ± {r['tolerance']:.3g}" if r["tolerance"] else "")
        detail = _detail(r["detail"])
        verdict = r["decision"] + (f": {detail}" if detail else "")
        lines.append(f"| {r['assumption']} | {r['quantity']} | {value} | {expected}{unit} | "
                     f"{verdict} |")  # fmt: skip
    return [*lines, ""]
