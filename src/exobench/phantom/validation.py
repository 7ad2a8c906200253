"""Validation of the discrepancy engine on many twin recordings with effects drawn at random.

Each case draws a hidden truth — no effect, one registry effect, or two — with magnitudes
log-uniform from a third of the documented detectable range up to its top (so that detection
limits can be seen), and a number of strides per trial. The twin writes RIG.md recordings, the
analysis chain reads them back as a lab's (C3D → filter → angles → strides → inverse dynamics →
kinetics) and the engine, told nothing, reports. Rows compare its report with the truth.
"""

from __future__ import annotations

import copy
import tempfile
from collections.abc import Mapping, Sequence
from pathlib import Path

import numpy as np
import pandas as pd

from exobench import phantom, selection
from exobench.errors import InputError
from exobench.phantom import (
    acquire,
    angles,
    c3d,
    discrepancy,
    effects,
    filtering,
    inverse_dynamics,
    kinetics,
    segmentation,
    twin,
)
from exobench.phantom.rig import Rig

SPRINGS_N_PER_M = (3400.0, 9200.0, 21700.0)


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


def twin_config(base: Mapping, hidden: Mapping, strides: int, seed: int) -> dict:
    """Workflow config whose phantom twin has exactly the hidden effects (plus sensor noise)."""
    config = copy.deepcopy(dict(base))
    config["seed"] = int(seed)
    block = config["phantom"]
    block["protocol"].update(
        strides=int(strides) + 2,
        ramp_strides=1,
        springs_N_per_m=list(SPRINGS_N_PER_M),
        test_order_N_per_m=list(SPRINGS_N_PER_M),
    )
    for name, entry in block["twin"]["effects"].items():
        if name in effects.REGISTRY or name in ("drive_compliance", "clutch_miss"):
            entry["enabled"] = False
    for name, values in hidden.items():
        block["twin"]["effects"][name] = {"enabled": True, **values}
    return config


def recordings(folder: Path, config: Mapping, mean_cycle_deg: np.ndarray, rig: Rig) -> Path:
    """Write the twin's recordings of a config (RIG.md files only) and return the manifest."""
    settings = phantom.settings(config)
    trials = twin.simulate_trials(mean_cycle_deg, rig, settings, {})
    twin.write_recordings(
        trials, folder, {"rule": "validation"}, int(settings["protocol"]["ramp_strides"])
    )
    return folder / "manifest.csv"


def chain_tables(manifest_path: Path, config: Mapping, swing_fraction: float, rig: Rig):
    """(trial, spring, kinetics, strides) of every trial, by the workflow's own analysis stages
    (the recordings screened for glitches as the acquisition rule screens them)."""
    settings = phantom.settings(config)
    parts = []
    for _, row in c3d.read_manifest(manifest_path).iterrows():
        path = manifest_path.parent / row["file"]
        markers, analog, _ = acquire.screened_trial(path, {}, settings["chain"])
        filtered = filtering.filter_trial(markers, analog, settings["chain"], str(path))
        ang = angles.knee_angles(filtered)
        strides = segmentation.segment(
            filtered, ang, int(row["ramp_strides"]), swing_fraction, settings["chain"],
            float(settings["protocol"]["min_spring_force_N"]), f"trial {row['trial']} ({path})",
        )  # fmt: skip
        moments = inverse_dynamics.knee_kinetics(ang, filtered, rig)
        table = kinetics.kinetics_table(ang, moments, filtered, strides)
        parts.append((row["trial"], float(row["spring_stiffness_N_per_m"]), table, strides))
    return parts


def run_case(index: int, base: Mapping, mean_cycle_deg, swing_fraction: float, rig: Rig,
             strides_choices: Sequence[int]) -> tuple[dict, dict]:  # fmt: skip
    """Draw, simulate, analyse one case: (truth, report)."""
    seed = int(base["seed"]) * 100_003 + index
    case = draw_case(np.random.default_rng([seed, 17]), strides_choices)
    config = twin_config(base, case["hidden"], case["strides"], seed)
    with tempfile.TemporaryDirectory() as tmp:
        manifest = recordings(Path(tmp), config, mean_cycle_deg, rig)
        parts = chain_tables(manifest, config, swing_fraction, rig)
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


def figure(rows: pd.DataFrame, table: pd.DataFrame, openworld_table: pd.DataFrame):
    """Coverage and detection rate per effect (with the 90–98 % target band), detection as a
    function of effect size, per number of strides, and the open-world and combined arms on the
    independent generator's recordings (:func:`openworld.outcome_panel`)."""
    from exobench import figures
    from exobench.phantom import openworld

    fig, axes = figures.new_figure(3, 1, width=13.0, height=3.6)
    openworld.outcome_panel(axes[0, 2], openworld_table)
    per = table[table["effect"].isin(list(effects.REGISTRY))].reset_index(drop=True)
    ax = axes[0, 0]
    x = np.arange(len(per))
    ax.axhspan(0.90, 0.98, color="0.9", label="coverage target 90–98 %")
    ax.bar(x - 0.2, per["coverage_95"], width=0.4, color="#0072B2", label="95 % interval coverage")
    ax.bar(x + 0.2, per["detection_rate"], width=0.4, color="#E69F00", label="detection rate")
    ax.plot(x, per["false_claim_rate"], "kx", label="false-claim rate")
    ax.set_xticks(x, [e.replace("_", " ") for e in per["effect"]], rotation=60, ha="right",
                  fontsize=6)  # fmt: skip
    none = table[table["effect"] == "no-effect cases"].iloc[0]
    ax.set(ylim=(0, 1.05), ylabel="share of cases",
           title=f"false positives, no-effect data: {none['false_positive_rate']:.0%}\n"
           f"({int(none['cases_hidden'])} cases)")  # fmt: skip
    ax.legend(fontsize=6, loc="lower left")
    ax = axes[0, 1]
    present = rows[rows["hidden"]]
    colours = figures.ordered_colours(present["strides_per_trial"].nunique())
    for colour, (strides, group) in zip(colours, present.groupby("strides_per_trial"), strict=True):
        size = [
            relative_size(effect, name, value)
            for effect, name, value in zip(group["effect"], group["parameter"], group["truth"],
                                           strict=True)
        ]  # fmt: skip
        jitter = np.linspace(-0.04, 0.04, len(size))
        ax.plot(size, group["claimed"].astype(float) + jitter, "o", ms=3, color=colour,
                label=f"{strides} strides per trial")  # fmt: skip
    ax.set_xscale("log")
    ax.set(xlabel="effect size / top of its documented detectable range",
           ylabel="claimed (1) or not (0)", title="detection against effect size")  # fmt: skip
    ax.legend(fontsize=6)
    return fig
