"""Validation helpers shared by the groups: drawing hidden effects, and comparing a report
with the truth."""

from __future__ import annotations

from collections.abc import Mapping

import numpy as np

from exobench.selection.model import Effect


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
