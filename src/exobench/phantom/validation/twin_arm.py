"""Validation of the discrepancy engine on many twin recordings with effects drawn at random.

Each case draws a hidden truth — no effect, one registry effect, or two — with magnitudes
log-uniform from a third of the documented detectable range up to its top (so that detection
limits can be seen), and a number of strides per trial. The twin writes RIG.md recordings, the
analysis chain reads them back as a lab's (C3D → filter → angles → strides → inverse dynamics →
kinetics) and the engine, told nothing, reports. Rows compare its report with the truth.
"""

from __future__ import annotations

import tempfile
from collections.abc import Mapping, Sequence
from pathlib import Path

import numpy as np
import pandas as pd

from exobench import phantom, selection
from exobench.errors import InputError
from exobench.phantom.model import discrepancy, effects
from exobench.phantom.rig import Rig
from exobench.phantom.validation import recordings


def draw_case(rng: np.random.Generator, strides_choices: Sequence[int]) -> dict:
    """A hidden truth: effect names -> {parameter: value}, and strides per trial."""
    chosen = selection.drawn_effects(effects.REGISTRY, rng)
    hidden = {name: magnitudes(effects.REGISTRY[name], rng) for name in chosen}
    return {"hidden": hidden, "strides": int(rng.choice(strides_choices))}


def magnitudes(effect: selection.Effect, rng, widen: float = 3.0) -> dict[str, float]:
    """Values of an effect's parameters: sizes log-uniform from ``widen`` times below the
    documented detectable range up to its top; effects with a sign (offsets, clock lags, gains)
    take a random one."""
    out = {}
    for p in effect.parameters:
        low, high = sorted(float(s) for s in p.strength(p.detectable))
        size = float(np.exp(rng.uniform(np.log(low / widen), np.log(high))))
        signed = not p.log or p.neutral == 1.0
        out[p.name] = p.value_at(size, float(rng.choice([-1.0, 1.0])) if signed else 1.0)
    return out


def run_case(index: int, base: Mapping, mean_cycle_deg, swing_fraction: float, rig: Rig,
             strides_choices: Sequence[int]) -> tuple[dict, dict]:  # fmt: skip
    """Draw, simulate, analyse one case: (truth, report)."""
    seed = int(base["seed"]) * 100_003 + index
    case = draw_case(np.random.default_rng([seed, 17]), strides_choices)
    config = recordings.twin_config(base, case["hidden"], case["strides"], seed)
    with tempfile.TemporaryDirectory() as tmp:
        manifest = recordings.write(Path(tmp), config, mean_cycle_deg, rig)
        parts = recordings.engine_parts(
            recordings.chain_tables(manifest, config, swing_fraction, rig)
        )
    block = phantom.settings(config)
    settings = {**block["discrepancy"], "engine": config["discrepancy"], "seed": seed}
    try:
        data, scales = discrepancy.observations(parts, settings, rig, block["chain"])
    except InputError as error:  # too few analysable strides: the engine refuses, says why
        refused = {"effects_found": [], "tentative": [], "unexplained": {"flag": False},
                   "cause": f"refused: {error}"}  # fmt: skip
        return {"case": index, "seed": seed, **case}, refused
    report = discrepancy.analyse(data, scales, settings, source=f"validation case {index}")
    return {"case": index, "seed": seed, **case}, report


def case_rows(truth: Mapping, report: Mapping) -> list[dict]:
    """One row per registry parameter: hidden truth, what the engine claimed, its interval."""
    case = {"case": truth["case"], "seed": truth["seed"], "strides_per_trial": truth["strides"]}
    return [
        {**case, **row}
        for row in selection.validation_rows(effects.REGISTRY, truth["hidden"], report)
    ]


def summary(rows: pd.DataFrame) -> pd.DataFrame:
    """Per effect and overall: detection rate, interval coverage, false-positive rate, and the
    detection limit (smallest magnitude detected in ≥ 80 % of the cases at or above it) per
    number of strides."""
    out = []
    cases = rows.drop_duplicates("case")
    none = cases[cases["hidden_effects"] == "none"]
    none_false = (
        rows[rows["case"].isin(none["case"])]
        .groupby("case")
        .agg(claimed=("claimed", "any"), flag=("unexplained_flag", "any"))
    )
    for name, group in [*rows.groupby("effect", sort=False), ("all", rows)]:
        present = group[group["hidden"]]
        detected = present[present["claimed"]]
        absent = group[~group["hidden"]]
        entry = {
            "effect": name,
            "cases_hidden": int(present["case"].nunique()),
            "detection_rate": _rate(present.groupby("case")["claimed"].all()),
            "coverage_95": _rate(detected["covered"]),
            "intervals": len(detected),
            "false_claim_rate": _rate(absent.groupby("case")["claimed"].any()),
        }
        if name != "all":
            for strides, sub in present.groupby("strides_per_trial"):
                entry[f"detection_limit_{strides}_strides"] = detection_limit(sub)
        out.append(entry)
    out.append(
        {
            "effect": "no-effect cases",
            "cases_hidden": len(none),
            "false_positive_rate": _rate(none_false["claimed"] | none_false["flag"]),
        }
    )
    return pd.DataFrame(out)


def _rate(values) -> float:
    values = np.asarray(values, bool)
    return float(values.mean()) if values.size else np.nan


def detection_limit(present: pd.DataFrame, level: float = 0.8) -> float:
    """The weakest effect (as a parameter value; a stiffness is weak when large, an offset
    when near 0) at and beyond which at least ``level`` of the hidden cases were claimed."""
    size = selection.detection_limit(effects.REGISTRY, present, level)
    if np.isnan(size):
        return np.nan
    effect = effects.REGISTRY[present["effect"].iloc[0]]
    parameter = next(p for p in effect.parameters if p.name == present["parameter"].iloc[0])
    return float(np.abs(parameter.value_at(size)))


def relative_size(effect: str, name: str, value: float) -> float:
    """Effect size over the top of the parameter's documented detectable range."""
    parameter = next(p for p in effects.REGISTRY[effect].parameters if p.name == name)
    return float(parameter.strength(value) / np.max(parameter.strength(parameter.detectable)))
