"""Validation helpers shared by the groups: drawing hidden effects, and comparing a report
with the truth."""

from __future__ import annotations

from collections.abc import Mapping

import numpy as np
import pandas as pd

from exobench.selection.fitting import fit
from exobench.selection.model import Effect, ordered
from exobench.selection.stability import stability


def drawn_effects(registry: Mapping[str, Effect], rng: np.random.Generator) -> list[str]:
    """The hidden effects of a validation case: none, one or two registry entries (p = 0.2,
    0.55, 0.25), with the entries they require."""
    names = list(registry)
    kind = rng.choice(["none", "single", "pair"], p=[0.2, 0.55, 0.25])
    chosen: list[str] = []
    if kind != "none":
        chosen.append(str(rng.choice(names)))
    if kind == "pair":
        chosen.append(str(rng.choice([n for n in names if n not in chosen])))
    for name in list(chosen):
        chosen += [r for r in registry[name].requires if r not in chosen]
    return chosen


def detection_limit(registry: Mapping[str, Effect], present, level: float = 0.8) -> float:
    """The weakest size (distance from the neutral value) at and beyond which at least ``level``
    of a parameter's hidden validation cases (rows of :func:`validation_rows`) were claimed;
    NaN if none."""
    effect = registry[present["effect"].iloc[0]]
    parameter = next(p for p in effect.parameters if p.name == present["parameter"].iloc[0])
    size = parameter.strength(present["truth"].to_numpy())
    order = np.argsort(size)
    hits = present["claimed"].to_numpy()[order]
    share_above = np.cumsum(hits[::-1])[::-1] / np.arange(hits.size, 0, -1)
    ok = np.flatnonzero(share_above >= level)
    return float(size[order][ok[0]]) if ok.size else np.nan


def validation_rows(registry: Mapping[str, Effect], hidden: Mapping[str, Mapping[str, float]],
                    report: Mapping) -> list[dict]:  # fmt: skip
    """One row per registry parameter of a validation case: the hidden truth against what the
    engine claimed (or only proposed) and its 95 % interval."""
    claimed = {e["effect"]: e for e in report["effects_found"]}
    tentative = {e["effect"] for e in report["tentative"]}
    rows = []
    for name, effect in registry.items():
        found = claimed.get(name)
        for p in effect.parameters:
            value = hidden.get(name, {}).get(p.name, np.nan)
            low, high = found["ci95"][p.name] if found else (np.nan, np.nan)
            rows.append({
                "hidden_effects": "+".join(sorted(hidden)) or "none",
                "effect": name,
                "parameter": p.name,
                "unit": p.unit,
                "hidden": name in hidden,
                "truth": value,
                "claimed": found is not None,
                "tentative": name in tentative,
                "estimate": found["parameters"][p.name] if found else np.nan,
                "ci_low": low,
                "ci_high": high,
                "covered": bool(found) and bool(low <= value <= high),
                "unexplained_flag": bool(report["unexplained"]["flag"]),
                "refused": report["cause"].startswith("refused"),
            })  # fmt: skip
    return rows


def stability_case(group: str, index: int, seed: int, problem, data, scales, settings,
                   effects, trials: np.ndarray, change: tuple) -> list[dict]:  # fmt: skip
    """A stability validation case: the twin's ``effects`` fitted to all the data (what a right
    selection leaves), the parameter stability of the trials (each unit's in ``trials``) and
    its rows (:func:`stability_rows`) against the truth ``change`` = (constant, the changed
    trial's place among the trials, size)."""
    effects = tuple(ordered(problem, effects))
    model = {"effects": effects, "values": fit(problem, data, effects, scales)[0]}
    result = stability(problem, data, scales, settings, model)
    names = list(dict.fromkeys(trials))
    units = int(np.min(np.unique(trials, return_counts=True)[1]))
    constant, trial, size = change
    return stability_rows(group, index, seed, units, constant,
                          None if trial is None else str(names[trial]), size, result)  # fmt: skip


def drawn_change(rng: np.random.Generator, spreads: Mapping[str, tuple[float, float]],
                 trials: int) -> tuple[str | None, int | None, float]:  # fmt: skip
    """A stability case's hidden truth: every other case none; else one constant (a key of
    ``spreads``, its row's visible spread between trials), one trial of ``trials`` and a size
    log-uniform from a quarter of the smallest visible spread to the largest, either sign (so
    that the detection limit shows)."""
    if rng.random() < 0.5:
        return None, None, 0.0
    constant = str(rng.choice(sorted(spreads)))
    low, high = spreads[constant]
    size = float(np.exp(rng.uniform(np.log(low / 4.0), np.log(high))))
    return constant, int(rng.integers(trials)), float(rng.choice([-1.0, 1.0])) * size


def stability_rows(group: str, index: int, seed: int, units: int, constant: str | None,
                   trial: str | None, size: float, result: Mapping) -> list[dict]:  # fmt: skip
    """One row per constant tested: the truth (the constant changed in the case, if any, its
    trial and size) beside the test's outcome (p, adjusted p, flag, the trials it named)."""
    rows = []
    for entry in result["constants"]:
        if not entry["tested"]:
            continue
        changed = entry["assumption"] == constant
        named = [d["trial"] for d in entry["departing"]] if entry["flag"] else []
        rows.append({
            "group": group, "case": index, "seed": seed, "units_per_trial": units,
            "case_changed": constant or "none", "constant": entry["assumption"],
            "changed": changed, "changed_trial": trial if changed else "",
            "size": size if changed else 0.0, "statistic": entry["statistic"], "p": entry["p"],
            "p_adjusted": entry["p_adjusted"], "flag": entry["flag"], "named": "+".join(named),
            "named_right": bool(changed and entry["flag"] and named == [trial]),
        })  # fmt: skip
    return rows


def stability_summary(rows: pd.DataFrame, spreads: Mapping[str, tuple[float, float]]):
    """Per group and constant: over the cases where nothing changed, the share flagged (the
    false-alarm rate, against the stated level) and the shares of raw p below 0.01 and 0.05
    (a calibrated test: 1 % and 5 %); over the cases where it changed, the share flagged and
    named with its trial, by size (below the smallest visible spread, up to the middle of the
    visible range, beyond), and the cases where another constant was flagged instead."""
    out = []
    for (group, constant), part in rows.groupby(["group", "constant"], sort=True):
        calm = part[part["case_changed"] == "none"]
        changed = part[part["changed"]]
        low, high = spreads[constant]
        size = np.abs(changed["size"].to_numpy())
        bands = {
            "below visible": size < low,
            "visible, lower half": (size >= low) & (size < 0.5 * (low + high)),
            "visible, upper half": size >= 0.5 * (low + high),
        }
        entry = {
            "group": group, "constant": constant, "null_cases": len(calm),
            "false_flags": int(calm["flag"].sum()), "false_flag_rate": _mean(calm["flag"]),
            "p_below_0.01": _mean(calm["p"] < 0.01), "p_below_0.05": _mean(calm["p"] < 0.05),
            "changed_cases": len(changed),
            "flagged_other_constant": int(part[(part["case_changed"] != "none")
                                               & ~part["changed"]]["flag"].sum()),
        }  # fmt: skip
        for band, keep in bands.items():
            entry[f"cases {band}"] = int(keep.sum())
            entry[f"named right, {band}"] = _mean(changed["named_right"].to_numpy()[keep])
        out.append(entry)
    return pd.DataFrame(out)


def _mean(values) -> float:
    values = np.asarray(values, float)
    return float(values.mean()) if values.size else np.nan
