"""Validation on recordings the project's twin did not make: the open-world and combined arms.

The recordings come from :mod:`exobench.phantom.validation.labsim`, a generator written from the rig
contract, the assumption table's law lines (docs/assumptions.md) and the physics alone, apart from
the twin and the engine. Two arms:
- **open world**: the fault families are the table's own relaxations that are not registry
  effects (a term of the engine's library, or a row only a direct check sees), taken in turn,
  each violated at a size drawn from the table's visible sizes, beside the interface compliance
  every real rig has and, half the time, one more registry effect at a real size. Per case the
  engine's report and the direct checks are scored against the truth: named right (a named
  term, or one of its alternatives, is the fault; for a row only a check sees, that check
  flags it; the rows that must hold between trials are checked by the report's parameter
  stability, which must name the constant), flagged only (unexplained, proposed or a check
  on the fault's own row, with nothing wrong named), missed (nothing said) or misattributed
  (a term, a registry effect or a check's row named that the truth does not hold). Beside:
  the hypotheses offered and how many name the truth, and whether the interface compliance
  was claimed (and covered) where the fault was left unexplained;
- **combined**: two to four registry effects at the sizes a real rig has (soft tissue always),
  which the engine must claim with intervals that cover the truth.
"""

from __future__ import annotations

import tempfile
from collections.abc import Mapping, Sequence
from pathlib import Path

import numpy as np
import pandas as pd

from exobench import phantom
from exobench.errors import InputError
from exobench.phantom.model import assumptions, checks, discrepancy
from exobench.phantom.rig import Rig
from exobench.phantom.validation import labsim, recordings
from exobench.selection import checks as direct_checks

RELAXATIONS = assumptions.relaxations()
REGISTRY = assumptions.registry_terms()
# The open world's fault families: every relaxation that is not a registry effect.
FAMILIES = [key for key, (_, r) in RELAXATIONS.items() if not r.registry]
# Registry relaxations beside a fault (interface compliance always) and in the combined arm.
BESIDE = [key for key in REGISTRY if key != "interface.elastic"]
OUTCOMES = ("named right", "flagged only", "missed", "misattributed")


def violation(key: str, rng: np.random.Generator) -> dict[str, float]:
    """A relaxation at a random size from its visible range (log-uniform; a random side of
    neutral where it has two)."""
    r = RELAXATIONS[key][1]
    size = float(np.exp(rng.uniform(*np.log(r.visible))))
    if r.signed:
        size = r.neutral + float(rng.choice([-1.0, 1.0])) * size
    return {r.parameter: size}


def with_requirements(keys: Sequence[str], rng: np.random.Generator) -> dict[str, dict]:
    """Violations of the given relaxations and of every relaxation they need."""
    out: dict[str, dict] = {}
    for key in keys:
        for needed in (*RELAXATIONS[key][1].requires, key):
            out.setdefault(needed, violation(needed, rng))
    return out


def draw_case(arm: str, index: int, rng: np.random.Generator, strides_choices) -> dict:
    """A case of an arm: open world (the families in turn, beside the interface compliance and
    half the time one more registry effect) or combined (two to four registry effects)."""
    strides = int(rng.choice(strides_choices))
    if arm == "combined":
        keys = ["interface.elastic", *rng.choice(BESIDE, int(rng.integers(1, 4)), replace=False)]
        return {"violations": with_requirements(keys, rng), "fault": None, "strides": strides}
    family = FAMILIES[index % len(FAMILIES)]
    beside = ["interface.elastic", *rng.choice(BESIDE, int(rng.integers(0, 2)))]
    violations = with_requirements([*beside, family], rng)
    return {"violations": violations, "fault": family, "strides": strides}


def hidden_effects(case: Mapping) -> dict[str, dict[str, float]]:
    """The registry effects a case holds, by the engine's names and parameters."""
    return {REGISTRY[key]: values for key, values in case["violations"].items() if key in REGISTRY}


def analysed(case: Mapping, base: Mapping, seed: int, cycle_csv: Path, swing_fraction: float,
             rig: Rig) -> tuple[dict, pd.DataFrame]:  # fmt: skip
    """The engine's report and the direct checks on the generator's recordings of a case (or a
    refusal, in the report's shape); the generator drives the phantom along the mean cycle in
    ``cycle_csv``."""
    config = recordings.twin_config(base, {}, case["strides"], seed)
    with tempfile.TemporaryDirectory() as tmp:
        manifest = labsim.write_study(
            Path(tmp), cycle_csv=Path(cycle_csv), springs_N_per_m=recordings.SPRINGS_N_PER_M,
            strides=case["strides"] + 2, ramp_strides=1, violations=dict(case["violations"]),
            seed=seed,
        )  # fmt: skip
        parts = recordings.chain_tables(manifest, config, swing_fraction, rig)
    block = phantom.settings(config)
    settings = {**block["discrepancy"], "engine": config["discrepancy"], "seed": seed}
    table = checks.checks(parts, rig, {**block["checks"], "swing_pct": settings["noise_pct"],
                                       "window_pct": settings["window_pct"]})  # fmt: skip
    try:
        data, scales = discrepancy.observations(recordings.engine_parts(parts), settings, rig,
                                                block["chain"])  # fmt: skip
    except InputError as error:
        return {"effects_found": [], "tentative": [], "unexplained": {"flag": False},
                "discovery": {"named": [], "proposed": []},
                "cause": f"refused: {error}"}, table  # fmt: skip
    report = discrepancy.analyse(data, scales, settings, source="open-world validation")
    # the rows that must hold between trials are checked by the report's parameter stability
    return report, direct_checks.with_stability(table, report)


def hypotheses(report: Mapping) -> list[Mapping]:
    """The terms a report offers the lab: named, or proposed while structure remains."""
    return [*report["discovery"]["named"], *report["discovery"].get("proposed", [])]


def names(entry: Mapping) -> set[str]:
    """A hypothesis's term and the terms listed as explaining the data as well."""
    return {entry["term"], *entry.get("alternatives", [])}


def outcome(case: Mapping, report: Mapping, table: pd.DataFrame) -> str:
    """How a report and the direct checks meet the fault (module docstring)."""
    fault = case["fault"]
    row = RELAXATIONS[fault][0].key
    wrong_effect = any(e["effect"] not in hidden_effects(case) for e in report["effects_found"])
    named = report["discovery"]["named"]
    right = [t for t in named if fault in names(t)]
    wrong_term = [t for t in named if t not in right]
    flagged_rows = direct_checks.violated(table)
    wrong_check = [r for r in checks.named(table) if r != row]
    if wrong_effect or wrong_term or wrong_check:
        return "misattributed"
    if right or (RELAXATIONS[fault][1].checked and row in flagged_rows):
        return "named right"
    if report["unexplained"]["flag"] or report["discovery"].get("proposed") or flagged_rows:
        return "flagged only"
    return "missed"


def case_rows(arm: str, index: int, seed: int, case: Mapping, report: Mapping,
              table: pd.DataFrame) -> list[dict]:  # fmt: skip
    """One row for the fault (its outcome, the hypotheses offered and how many name it, the
    interface compliance claimed beside it) and one per hidden registry parameter (its
    interval and coverage)."""
    hidden = hidden_effects(case)
    claimed = {e["effect"]: e for e in report["effects_found"]}
    common = {"arm": arm, "case": index, "seed": seed, "strides_per_trial": case["strides"],
              "hidden_effects": "+".join(sorted(hidden)) or "none",
              "fault": case["fault"] or "none",
              "named_terms": "+".join(t["term"] for t in report["discovery"]["named"]),
              "proposed_terms": "+".join(t["term"] for t in report["discovery"].get("proposed",
                                                                                      [])),
              "checks_violated": "+".join(direct_checks.violated(table)),
              "claimed_effects": "+".join(claimed),
              "unexplained_flag": bool(report["unexplained"]["flag"])}  # fmt: skip
    rows = []
    if case["fault"]:
        row, r = RELAXATIONS[case["fault"]]
        offered = hypotheses(report)
        interface = claimed.get("interface_compliance")
        truth = case["violations"]["interface.elastic"]["k_interface_Nm_per_rad"]
        low, high = interface["ci95"]["k_interface_Nm_per_rad"] if interface else (np.nan,) * 2
        rows.append({**common, "kind": row.kind, "effect": case["fault"],
                     "parameter": r.parameter,
                     "truth": case["violations"][case["fault"]][r.parameter],
                     "outcome": outcome(case, report, table), "hypotheses": len(offered),
                     "hypotheses_right": sum(case["fault"] in names(h) for h in offered),
                     "interface_claimed": interface is not None,
                     "interface_covered": bool(interface) and bool(low <= truth <= high),
                     "claimed": False, "covered": False})  # fmt: skip
    for name, values in hidden.items():
        for parameter, truth in values.items():
            found = claimed.get(name)
            low, high = found["ci95"][parameter] if found else (np.nan, np.nan)
            rows.append({**common, "kind": "registry", "effect": name, "parameter": parameter,
                         "truth": truth, "claimed": found is not None,
                         "estimate": found["parameters"][parameter] if found else np.nan,
                         "ci_low": low, "ci_high": high,
                         "covered": bool(found) and bool(low <= truth <= high)})  # fmt: skip
    return rows


def run_case(arm: str, index: int, base: Mapping, cycle_csv: Path, swing_fraction: float,
             rig: Rig, strides_choices: Sequence[int]):  # fmt: skip
    """Draw and analyse one case of an arm: (case, report, direct checks, seed)."""
    seed = int(base["seed"]) * 100_003 + index + (50_000 if arm == "combined" else 0)
    case = draw_case(arm, index, np.random.default_rng([seed, 29]), strides_choices)
    report, table = analysed(case, base, seed, cycle_csv, swing_fraction, rig)
    return case, report, table, seed


def _share(values) -> float:
    values = np.asarray(values, float)
    return float(values.mean()) if values.size else np.nan


def summary(rows: pd.DataFrame) -> pd.DataFrame:
    """Per fault family and over all: cases, the share of each outcome, hypothesis precision
    (of the hypotheses offered, the share naming the fault), and where a fault was left
    unexplained (flagged only) the share of cases whose interface compliance was claimed and
    the 95 % coverage of those claims; the registry effects' detection and coverage per arm;
    the combined cases claimed whole."""
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
        entry["interface_claimed"] = _share(left["interface_claimed"])
        entry["interface_coverage"] = _share(left.loc[left["interface_claimed"],
                                                      "interface_covered"])  # fmt: skip
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


def outcome_panel(ax, rows: pd.DataFrame, table: pd.DataFrame) -> None:
    """Open-world outcomes per row of the assumption table (its families' cases pooled; stacked
    shares) and, in the title, the hypothesis precision and the registry effects' 95 %
    coverage in the open-world and combined arms."""
    faults = rows[rows["kind"] != "registry"].drop_duplicates("case")
    row_of = {key: RELAXATIONS[key][0].label for key in FAMILIES}
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
    coverage = ", ".join(f"{arm} {row['coverage_95']:.0%} of {int(row['intervals'])}"
                         for arm, row in registry.iterrows())  # fmt: skip
    overall = table[(table["arm"] == "open world") & (table["row"] == "all families")]
    precision = float(overall["precision"].iloc[0]) if len(overall) else np.nan
    ax.set_title(f"the table's rows violated on independent recordings; hypothesis precision "
                 f"{precision:.0%}\n95 % coverage of registry effects: {coverage}",
                 fontsize=8)  # fmt: skip
    ax.legend(fontsize=6, loc="upper left", bbox_to_anchor=(1.01, 1.0))
