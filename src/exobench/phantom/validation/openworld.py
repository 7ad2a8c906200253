"""Validation on recordings the project's twin did not make: the open-world and combined arms.

The recordings come from :mod:`exobench.labsim`, a generator written from the rig contract and
the physics alone, apart from the twin and the engine. Two arms:
- **open world**: a fault the registry has no entry for (sensor, labelling or mechanical, one
  family drawn per case, its size drawn at random), with or without one or two registry effects
  beside it. Per case the engine's report is scored against the truth: the fault's term named
  (or listed as explaining the data as well), flagged unexplained without a wrong name, missed,
  or misattributed (a term or registry effect named that the truth does not hold);
- **combined**: two to four registry effects at the sizes a real rig has (soft tissue always),
  which the engine must claim with intervals that cover the truth.
"""

from __future__ import annotations

import tempfile
from collections.abc import Mapping, Sequence
from pathlib import Path

import numpy as np
import pandas as pd

from exobench import labsim, phantom
from exobench.errors import InputError
from exobench.phantom.model import discrepancy
from exobench.phantom.rig import Rig
from exobench.phantom.validation import recordings

# Fault families of the generator, their size ranges (a random sign where both sides are given)
# and the library terms that name each (a per-cell family: its own cell's term).
FAMILIES: dict[str, dict] = {
    "ankle_cell_gain": {"parameter": "gain", "sizes": (0.03, 0.10), "around": 1.0,
                        "terms": ("ankle_cell_{cell}_gain",), "kind": "sensor"},
    "ankle_cell_offset": {"parameter": "offset_N", "sizes": (1.5, 8.0), "around": 0.0,
                          "terms": ("ankle_force_offset",), "kind": "sensor"},
    "ankle_cell_drift": {"parameter": "rate_N_per_s", "sizes": (0.05, 0.3), "around": 0.0,
                         "terms": ("ankle_force_drift",), "kind": "sensor"},
    "spring_cell_drift": {"parameter": "rate_N_per_s", "sizes": (0.05, 0.3), "around": 0.0,
                          "terms": ("spring_cell_drift",), "kind": "sensor"},
    "spring_mislabelled": {"parameter": "factor", "sizes": (0.1, 0.35), "around": 1.0,
                           "terms": ("spring_rate_scale",), "kind": "labelling"},
    "pulley_radius": {"parameter": "factor", "sizes": (0.05, 0.15), "around": 1.0,
                      "terms": ("moment_arm_scale",), "kind": "labelling"},
    "shank_mass": {"parameter": "factor", "sizes": (0.08, 0.2), "around": 1.0,
                   "terms": ("shank_inertia_scale",), "kind": "labelling"},
    "phantom_knee_friction": {"parameter": "friction_Nm", "sizes": (0.05, 0.3), "around": None,
                              "terms": ("knee_coulomb",), "kind": "mechanical"},
    "phantom_knee_damping": {"parameter": "c_Nms_per_rad", "sizes": (0.02, 0.15),
                             "around": None, "terms": ("knee_viscous",), "kind": "mechanical"},
    "progressive_spring": {"parameter": "per_m", "sizes": (5.0, 20.0), "around": None,
                           "terms": ("spring_quadratic",), "kind": "mechanical"},
}  # fmt: skip
CELLS = ("LC_ANKLE_1", "LC_ANKLE_2", "LC_ANKLE_3")
# Registry effects at the sizes a real rig has (seed 000's rig: soft tissue always), for the
# combined arm and beside the faults.
REAL_SIZES: dict[str, dict[str, tuple[float, float]]] = {
    "interface_compliance": {"k_interface_Nm_per_rad": (40.0, 150.0)},
    "interface_damping": {"c_interface_Nms_per_rad": (0.3, 1.5)},
    "interface_stiffening": {"stiffening_per_rad2": (100.0, 800.0)},
    "frame_compliance": {"k_frame_Nm_per_rad": (300.0, 2500.0)},
    "frame_friction": {"friction_Nm": (0.1, 0.8)},
    "transmission_play": {"play_rad": (0.01, 0.05)},
    "clutch_timing": {"delay_s": (0.015, 0.06)},
}
OUTCOMES = ("named right", "flagged only", "missed", "misattributed")


def fault_of(family: str, rng: np.random.Generator) -> dict:
    """A fault of a family at a random size (and sign, and cell where it has one)."""
    spec = FAMILIES[family]
    size = float(np.exp(rng.uniform(*np.log(spec["sizes"]))))
    if spec["around"] is None:
        fault = {spec["parameter"]: size}
    else:
        fault = {spec["parameter"]: spec["around"] + float(rng.choice([-1.0, 1.0])) * size}
    if family.startswith("ankle_cell"):
        fault["channel"] = str(rng.choice(CELLS))
    return fault


def real_effects(rng: np.random.Generator, count: int) -> dict:
    """``count`` registry effects at real sizes: interface compliance and count − 1 others
    (log-uniform sizes)."""
    others = [e for e in REAL_SIZES if e != "interface_compliance"]
    names = ["interface_compliance", *rng.choice(others, count - 1, replace=False)]
    return {
        str(name): {p: float(np.exp(rng.uniform(*np.log(r)))) for p, r in REAL_SIZES[name].items()}
        for name in names
    }


def draw_case(arm: str, index: int, rng: np.random.Generator, strides_choices) -> dict:
    """A case of an arm: open world (the families in turn, with none, one or two registry
    effects beside the fault) or combined (two to four registry effects)."""
    strides = int(rng.choice(strides_choices))
    if arm == "combined":
        return {"effects": real_effects(rng, int(rng.integers(2, 5))), "faults": {},
                "strides": strides}  # fmt: skip
    family = list(FAMILIES)[index % len(FAMILIES)]
    beside = int(rng.choice([0, 1, 2]))
    return {"effects": real_effects(rng, beside) if beside else {},
            "faults": {family: fault_of(family, rng)}, "strides": strides}  # fmt: skip


def analysed(case: Mapping, base: Mapping, seed: int, cycle_csv: Path, swing_fraction: float,
             rig: Rig) -> dict:  # fmt: skip
    """The engine's report on the generator's recordings of a case (or a refusal, in the
    report's shape); the generator drives the phantom along the mean cycle in ``cycle_csv``."""
    config = recordings.twin_config(base, {}, case["strides"], seed)
    springs = recordings.SPRINGS_N_PER_M
    with tempfile.TemporaryDirectory() as tmp:
        manifest = labsim.write_study(
            Path(tmp), cycle_csv=Path(cycle_csv), springs_N_per_m=springs,
            strides=case["strides"] + 2, ramp_strides=1, effects=dict(case["effects"]),
            faults=dict(case["faults"]), seed=seed,
        )  # fmt: skip
        parts = recordings.chain_tables(manifest, config, swing_fraction, rig)
    block = phantom.settings(config)
    settings = {**block["discrepancy"], "engine": config["discrepancy"], "seed": seed}
    try:
        data, scales = discrepancy.observations(parts, settings, rig, block["chain"])
    except InputError as error:
        return {"effects_found": [], "tentative": [], "unexplained": {"flag": False},
                "discovery": {"named": [], "proposed": []},
                "cause": f"refused: {error}"}  # fmt: skip
    return discrepancy.analyse(data, scales, settings, source="open-world validation")


def expected_terms(faults: Mapping) -> set[str]:
    """The library terms that name a case's faults."""
    out = set()
    for family, fault in faults.items():
        cell = fault.get("channel", "LC_ANKLE_0")[-1]
        out.update(t.format(cell=cell) for t in FAMILIES[family]["terms"])
    return out


def outcome(case: Mapping, report: Mapping) -> str:
    """How the report meets the fault: named right (a named term is the fault's, or lists it
    as explaining the data as well), flagged only (unexplained or only proposed, nothing wrong
    named), missed (nothing said) or misattributed (a term or registry effect named that the
    truth does not hold)."""
    expected = expected_terms(case["faults"])
    named = report["discovery"]["named"]
    wrong_effect = any(e["effect"] not in case["effects"] for e in report["effects_found"])
    right = [t for t in named if {t["term"], *t["alternatives"]} & expected]
    wrong_term = [t for t in named if t not in right]
    if wrong_effect or wrong_term:
        return "misattributed"
    if right:
        return "named right"
    flagged = report["unexplained"]["flag"] or report["discovery"]["proposed"]
    return "flagged only" if flagged else "missed"


def case_rows(arm: str, index: int, seed: int, case: Mapping, report: Mapping) -> list[dict]:
    """One row per hidden registry parameter (its interval and coverage) and one for the
    fault, with the case's outcome."""
    common = {"arm": arm, "case": index, "seed": seed, "strides_per_trial": case["strides"],
              "hidden_effects": "+".join(sorted(case["effects"])) or "none",
              "fault": "+".join(case["faults"]) or "none",
              "outcome": outcome(case, report) if case["faults"] else "",
              "named_terms": "+".join(t["term"] for t in report["discovery"]["named"]),
              "claimed_effects": "+".join(e["effect"] for e in report["effects_found"]),
              "unexplained_flag": bool(report["unexplained"]["flag"])}  # fmt: skip
    rows = []
    for family, fault in case["faults"].items():
        spec = FAMILIES[family]
        rows.append({**common, "kind": spec["kind"], "effect": family,
                     "parameter": spec["parameter"], "truth": fault[spec["parameter"]],
                     "claimed": False, "covered": False})  # fmt: skip
    claimed = {e["effect"]: e for e in report["effects_found"]}
    for name, values in case["effects"].items():
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
             rig: Rig, strides_choices: Sequence[int]) -> tuple[dict, dict, int]:  # fmt: skip
    """Draw and analyse one case of an arm: (case, report, seed)."""
    seed = int(base["seed"]) * 100_003 + index + (50_000 if arm == "combined" else 0)
    case = draw_case(arm, index, np.random.default_rng([seed, 29]), strides_choices)
    return case, analysed(case, base, seed, cycle_csv, swing_fraction, rig), seed


def summary(rows: pd.DataFrame) -> pd.DataFrame:
    """Per fault family: cases and the share of each outcome; the registry effects' detection
    and 95 % coverage in each arm; the combined cases claimed whole."""
    out = []
    faults = rows[rows["kind"] != "registry"].drop_duplicates("case")
    for name, group in [*faults.groupby("effect"), ("all families", faults)]:
        entry = {"arm": "open world", "row": name, "cases": len(group)}
        entry.update({o: float((group["outcome"] == o).mean()) for o in OUTCOMES})
        out.append(entry)
    registry = rows[rows["kind"] == "registry"]
    for arm, group in registry.groupby("arm"):
        claimed = group[group["claimed"]]
        cases = group.groupby("case")["claimed"].all()
        out.append({"arm": arm, "row": "registry effects", "cases": int(cases.size),
                    "parameters": len(group), "detected": float(group["claimed"].mean()),
                    "coverage_95": float(claimed["covered"].mean()) if len(claimed) else np.nan,
                    "intervals": len(claimed),
                    "cases_claimed_whole": float(cases.mean())})  # fmt: skip
    return pd.DataFrame(out)


def outcome_panel(ax, table: pd.DataFrame) -> None:
    """Open-world outcomes per fault family (stacked shares) and, in the title, the registry
    effects' 95 % coverage in the open-world and combined arms."""
    families = table[(table["arm"] == "open world") & (table["row"] != "registry effects")]
    families = families.reset_index(drop=True)
    colours = {"named right": "#009E73", "flagged only": "#56B4E9", "missed": "#E69F00",
               "misattributed": "#D55E00"}  # fmt: skip
    y = np.arange(len(families))
    left = np.zeros(len(families))
    for name, colour in colours.items():
        share = families[name].to_numpy(float)
        ax.barh(y, share, left=left, color=colour, label=name)
        left += share
    names = [f"{r.replace('_', ' ')} ({int(n)})"
             for r, n in zip(families["row"], families["cases"], strict=True)]  # fmt: skip
    ax.set_yticks(y, names, fontsize=6)
    ax.invert_yaxis()
    ax.set(xlim=(0, 1), xlabel="share of cases (cases per family in brackets)")
    registry = table[table["row"] == "registry effects"].set_index("arm")
    coverage = ", ".join(f"{arm} {row['coverage_95']:.0%} of {int(row['intervals'])}"
                         for arm, row in registry.iterrows())  # fmt: skip
    ax.set_title(f"faults outside the registry (independent recordings)\n95 % coverage of "
                 f"registry effects: {coverage}", fontsize=8)  # fmt: skip
    ax.legend(fontsize=6, loc="upper left", bbox_to_anchor=(1.01, 1.0))
