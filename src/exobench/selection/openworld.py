"""The open-world validation of the engine, the same for every group: recordings written by a
generator apart from the group's twin and engine, each violating one relaxation of the group's
assumption table, scored against the truth.

A group supplies an :class:`Arm`: its table's relaxations and registry relaxations, the registry
relaxation every real rig of its kind holds (the phantom's interface compliance, the emulator's
cuff compliance), and which of its direct checks name a row. Cases draw the table's relaxations
that are not registry effects in turn (a term of the engine's library, or a row only a direct
check sees), each at a size drawn from the table's visible sizes, beside the kept registry
effect and, half the time, one more registry effect; a combined arm draws two to four registry
effects. A case's outcome is: named right (a named term, one of its alternatives or a reading
the data cannot tell from the model's is the fault, or a claimed change between trials is the
fault; for a row only a check sees, a check flags it or names it among the rows it cannot
tell apart), flagged only (unexplained, proposed or a check on the fault's own row, nothing
wrong named), missed (nothing said) or misattributed (a term, a registry effect, a change
between trials or a check's row named that the truth does not hold). A row that must
hold between trials is seen by the report's parameter stability where a group joins its rows to
the direct checks (:func:`exobench.selection.checks.with_stability`).
"""

from __future__ import annotations

from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass

import numpy as np
import pandas as pd

from exobench.selection.assumptions import Assumption, Relaxation

OUTCOMES = ("named right", "flagged only", "missed", "misattributed")


@dataclass(frozen=True)
class Arm:
    """A group's open world: its relaxations by term key, the registry effect each registry
    relaxation is, the relaxation every real rig holds (``kept``: the registry effect and its
    parameter the engine must keep claiming beside a fault), and ``named(table)``: per violated
    direct check that names a cause, the rows it cannot tell apart (the cause among them)."""

    relaxations: Mapping[str, tuple[Assumption, Relaxation]]
    registry: Mapping[str, str]
    kept: str
    named: Callable[[pd.DataFrame], list[tuple[str, ...]]]
    violated: Callable[[pd.DataFrame], list[str]]

    @property
    def families(self) -> list[str]:
        """The open world's faults: every relaxation that is not a registry effect."""
        return [key for key, (_, r) in self.relaxations.items() if not r.registry]

    @property
    def beside(self) -> list[str]:
        """The registry relaxations drawn beside a fault, and in the combined arm."""
        return [key for key in self.registry if key != self.kept]

    @property
    def kept_effect(self) -> tuple[str, str]:
        """The kept relaxation's registry effect and parameter."""
        return self.registry[self.kept], self.relaxations[self.kept][1].parameter


def violation(r: Relaxation, rng: np.random.Generator) -> dict[str, float]:
    """A relaxation at a random size from its visible range (log-uniform; a random side of
    neutral where it has two)."""
    size = float(np.exp(rng.uniform(*np.log(r.visible))))
    if r.signed:
        size = r.neutral + float(rng.choice([-1.0, 1.0])) * size
    return {r.parameter: size}


def with_requirements(arm: Arm, keys: Sequence[str], rng: np.random.Generator) -> dict:
    """Violations of the given relaxations and of every relaxation they need."""
    out: dict[str, dict] = {}
    for key in keys:
        for needed in (*arm.relaxations[key][1].requires, key):
            out.setdefault(needed, violation(arm.relaxations[needed][1], rng))
    return out


def draw_violations(arm: Arm, name: str, index: int,
                    rng: np.random.Generator) -> tuple[dict, str | None]:  # fmt: skip
    """A case's violations and fault: the open world's families in turn, beside the kept
    relaxation and half the time one more registry effect; or (``combined``) two to four
    registry effects."""
    if name == "combined":
        keys = [arm.kept, *rng.choice(arm.beside, int(rng.integers(1, 4)), replace=False)]
        return with_requirements(arm, keys, rng), None
    fault = arm.families[index % len(arm.families)]
    beside = [arm.kept, *rng.choice(arm.beside, int(rng.integers(0, 2)))]
    return with_requirements(arm, [*beside, fault], rng), fault


def hidden_effects(arm: Arm, violations: Mapping) -> dict[str, dict[str, float]]:
    """The registry effects a case holds, by the engine's names and parameters."""
    return {arm.registry[k]: v for k, v in violations.items() if k in arm.registry}


def hypotheses(report: Mapping) -> list[Mapping]:
    """The terms a report offers the lab: named, proposed while structure remains, or a reading
    the data cannot tell from what the model fits."""
    return [*report["discovery"]["named"], *report["discovery"].get("proposed", []),
            *report.get("readings", [])]  # fmt: skip


def names(entry: Mapping) -> set[str]:
    """A hypothesis's term (or a claimed effect's name) and what it lists as explaining the data
    as well (terms; for a claimed effect, the rows or relaxations it reads alike)."""
    return {entry.get("term", entry.get("effect")), *entry.get("alternatives", [])}


def among(arm: Arm, keys: set[str], relaxations: set[str]) -> bool:
    """Whether any of ``relaxations`` is one of ``keys`` (relaxation keys, or rows: then each of
    a row's relaxations)."""
    return any(k in keys or arm.relaxations[k][0].key in keys for k in relaxations
               if k in arm.relaxations)  # fmt: skip


def outcome(arm: Arm, fault: str, violations: Mapping, report: Mapping,
            table: pd.DataFrame, also: Sequence[str] = ()) -> str:  # fmt: skip
    """How a report and the direct checks meet the fault (module docstring); ``also``: the
    relaxations the case holds beyond its violations, unsized (a lab's reading of its controller
    departing from a row), which a report may name without naming wrong. A check flagging only
    a row the case holds beside its fault (a drop every case holds, a reading's departure) does
    not make the fault "flagged"."""
    row = arm.relaxations[fault][0].key
    held = {*violations, *also}
    hidden = {*hidden_effects(arm, violations), *(arm.registry[k] for k in also
                                                  if k in arm.registry)}  # fmt: skip
    # a constant's move between trials is claimed by its relaxation's key (selection.between):
    # right where it is the fault, not wrong where the case holds it or a row that reads alike
    wrong_effect = any(e["effect"] not in hidden and not among(arm, names(e), held)
                       for e in report["effects_found"])  # fmt: skip
    named = report["discovery"]["named"]
    right = [t for t in [*named, *report.get("readings", [])] if fault in names(t)]
    right += [e for e in report["effects_found"] if e["effect"] == fault]
    wrong_term = [t for t in named if t not in right and not names(t) & held]
    beside = {arm.relaxations[k][0].key for k in held if k != fault} - {row}
    flagged_rows = [r for r in arm.violated(table) if r not in beside]
    by_check = arm.named(table)
    # a check names rows, or of a row only the relaxations it cannot tell apart (term keys)
    rows_held = {row, *beside, *held}
    wrong_check = [rows for rows in by_check if not rows_held & set(rows)]
    seen = row in flagged_rows or any(row in rows for rows in by_check)
    if wrong_effect or wrong_term or wrong_check:
        return "misattributed"
    if right or (arm.relaxations[fault][1].checked and seen):
        return "named right"
    if report["unexplained"]["flag"] or report["discovery"].get("proposed") or flagged_rows:
        return "flagged only"
    return "missed"


def case_rows(arm: Arm, name: str, index: int, seed: int, violations: Mapping,
              fault: str | None, report: Mapping, table: pd.DataFrame,
              common: Mapping, also: Sequence[str] = ()) -> list[dict]:  # fmt: skip
    """One row for the fault (its outcome, the hypotheses offered and how many name it, the kept
    effect claimed beside it) and one per hidden registry parameter (its interval and
    coverage); ``common``: the group's own columns of every row; ``also``: as :func:`outcome`."""
    hidden = hidden_effects(arm, violations)
    claimed = {e["effect"]: e for e in report["effects_found"]}
    common = {"arm": name, "case": index, "seed": seed, **common,
              "hidden_effects": "+".join(sorted(hidden)) or "none", "fault": fault or "none",
              "named_terms": "+".join(t["term"] for t in report["discovery"]["named"]),
              "proposed_terms": "+".join(t["term"]
                                         for t in report["discovery"].get("proposed", [])),
              "checks_violated": "+".join(arm.violated(table)),
              "claimed_effects": "+".join(claimed),
              "unexplained_flag": bool(report["unexplained"]["flag"])}  # fmt: skip
    rows = []
    if fault:
        row, r = arm.relaxations[fault]
        offered = hypotheses(report)
        effect, parameter = arm.kept_effect
        kept = claimed.get(effect)
        truth = violations[arm.kept][parameter]
        low, high = kept["ci95"][parameter] if kept else (np.nan, np.nan)
        rows.append({**common, "kind": row.kind, "effect": fault, "parameter": r.parameter,
                     "truth": violations[fault][r.parameter],
                     "outcome": outcome(arm, fault, violations, report, table, also),
                     "hypotheses": len(offered),
                     "hypotheses_right": sum(fault in names(h) for h in offered),
                     "kept_claimed": kept is not None,
                     "kept_covered": bool(kept) and bool(low <= truth <= high),
                     "claimed": False, "covered": False})  # fmt: skip
    for effect, values in hidden.items():
        for parameter, truth in values.items():
            found = claimed.get(effect)
            low, high = found["ci95"][parameter] if found else (np.nan, np.nan)
            rows.append({**common, "kind": "registry", "effect": effect, "parameter": parameter,
                         "truth": truth, "claimed": found is not None,
                         "estimate": found["parameters"][parameter] if found else np.nan,
                         "ci_low": low, "ci_high": high,
                         "covered": bool(found) and bool(low <= truth <= high)})  # fmt: skip
    return rows


def _share(values) -> float:
    values = np.asarray(values, float)
    return float(values.mean()) if values.size else np.nan


def summary(rows: pd.DataFrame) -> pd.DataFrame:
    """Per fault family and over all: cases, the share of each outcome, hypothesis precision
    (of the hypotheses offered, the share naming the fault), and where a fault was left
    unexplained (flagged only) the share of cases whose kept effect was claimed and the 95 %
    coverage of those claims; the registry effects' detection and coverage per arm, beside a
    fault or combined; the combined cases claimed whole."""
    out = []
    faults = rows[rows["kind"] != "registry"].drop_duplicates("case")
    for name, group in [*faults.groupby("effect"), ("all families", faults)]:
        entry = {"arm": "open world", "row": name, "cases": len(group)}
        entry.update({o: _share(group["outcome"] == o) for o in OUTCOMES})
        offered = float(group["hypotheses"].sum())
        entry["hypotheses"] = int(offered)
        entry["precision"] = float(group["hypotheses_right"].sum()) / offered if offered else np.nan
        left = group[group["outcome"] == "flagged only"]
        entry["unexplained_cases"] = len(left)
        entry["kept_claimed"] = _share(left["kept_claimed"])
        entry["kept_coverage"] = _share(left.loc[left["kept_claimed"], "kept_covered"])
        out.append(entry)
    registry = rows[rows["kind"] == "registry"]
    for arm, group in registry.groupby("arm"):
        claimed = group[group["claimed"]]
        cases = group.groupby("case")["claimed"].all()
        out.append({"arm": arm, "row": "registry effects", "cases": int(cases.size),
                    "parameters": len(group), "detected": _share(group["claimed"]),
                    "coverage_95": _share(claimed["covered"]), "intervals": len(claimed),
                    "cases_claimed_whole": _share(cases)})  # fmt: skip
    return pd.DataFrame(out)


def outcome_panel(ax, arm: Arm, rows: pd.DataFrame, table: pd.DataFrame) -> None:
    """Open-world outcomes per row of the assumption table (its families' cases pooled; stacked
    shares) and, in the title, the hypothesis precision and the registry effects' 95 %
    coverage in the open-world and combined arms."""
    faults = rows[rows["kind"] != "registry"].drop_duplicates("case")
    row_of = {key: arm.relaxations[key][0].label for key in arm.families}
    grouped = faults.assign(row=faults["effect"].map(row_of)).groupby("row", sort=False)
    shares = pd.DataFrame({o: grouped["outcome"].apply(lambda s, o=o: float((s == o).mean()))
                           for o in OUTCOMES})  # fmt: skip
    counts = grouped.size()
    colours = {"named right": "#009E73", "flagged only": "#56B4E9", "missed": "#E69F00",
               "misattributed": "#D55E00"}  # fmt: skip
    y = np.arange(len(shares))
    left = np.zeros(len(shares))
    for name, colour in colours.items():
        ax.barh(y, shares[name].to_numpy(float), left=left, color=colour, label=name)
        left += shares[name].to_numpy(float)
    ax.set_yticks(y, [f"{r} ({int(counts[r])})" for r in shares.index], fontsize=6)
    ax.invert_yaxis()
    ax.set(xlim=(0, 1), xlabel="share of cases (cases per row in brackets)")
    registry = table[table["row"] == "registry effects"].set_index("arm")
    coverage = ", ".join(f"{arm_name} {row['coverage_95']:.0%} of {int(row['intervals'])}"
                         for arm_name, row in registry.iterrows())  # fmt: skip
    overall = table[(table["arm"] == "open world") & (table["row"] == "all families")]
    precision = float(overall["precision"].iloc[0]) if len(overall) else np.nan
    ax.set_title(f"the table's rows violated on independent recordings; hypothesis precision "
                 f"{precision:.0%}\n95 % coverage of registry effects: {coverage}",
                 fontsize=8)  # fmt: skip
    ax.legend(fontsize=6, loc="upper left", bbox_to_anchor=(1.01, 1.0))
