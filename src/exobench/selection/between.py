"""A constant of the rig that moved between trials, refitted in the trials where it moved.

The model fits one value of each constant for the session. Where a sensor is re-zeroed before
some trials, that one value fits none of them well, and the observable the constant shows in
misfits in every trial that moved; the parameter stability (:mod:`.stability`) finds the trials
that depart. Where the model leaves structure and the stability flags a constant that the group
lets take one value per unit (``Problem.per_unit``: a linear parameter of a registry effect whose
transformation sets it), the constant is refitted as the session's value p and one shift d_i per
departing trial (p + d_i there, p elsewhere; where every trial departs, the one closest to the
others keeps p, so that p and the shifts stay apart). The entry is named after the table's row
(its ``between`` relaxation) and takes the place of the effect whose parameter it moves, in the
model the stability compared the trials in; that model is settled as any other (p does not
decide whether the data earn it, the shifts do: one earned shift is enough, as the constant
moved, and a trial whose shift the refit does not earn keeps p, the entry refitted once without
it). It replaces the one-value model where its held-out loss is lower by more than one paired
standard error: the term search and the claims then run on it, and the entry names the row with
the trials whose shift it earns.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import replace

import numpy as np

from exobench.selection.intervals import settled, sized
from exobench.selection.model import Data, Effect, Parameter, Problem, Settings, trial_labels
from exobench.selection.search import paired_se
from exobench.selection.structure import verdict_of
from exobench.selection.summary import short_name


def movable(problem: Problem, entry: Mapping) -> bool:
    """Whether a stability entry's constant is refitted per trial: flagged, with departing
    trials, sized by a linear parameter of a registry effect the group lets vary per unit."""
    return bool(entry["flag"] and entry["departing"] and entry["effect"] in problem.registry
                and entry["parameter"] in problem.per_unit and not entry["relative"])  # fmt: skip


def key(entry: Mapping) -> str:
    """The entry of a moved constant, by its row's change between trials (the table's term key
    ``row.between``)."""
    return f"{entry['assumption']}.between"


def moved_trials(entry: Mapping) -> list[str]:
    """The departing trials that get a shift: all of them, but where every compared trial
    departs the one whose difference from the others is smallest, which keeps the session's
    value."""
    trials = [d["trial"] for d in entry["departing"]]
    if set(trials) >= set(entry["used"]):
        keep = min(entry["departing"], key=lambda d: abs(d["difference"]))["trial"]
        trials.remove(keep)
    return trials


def shifted(problem: Problem, entry: Mapping) -> Effect:
    """A moved constant as one entry: its parameter p (the session's value, a shape parameter)
    is p + d_i in trial i's units (one value per unit, shaped (units, 1)), p elsewhere; the rows
    whose violation reads as the same change are its alternatives."""
    base = problem.registry[entry["effect"]]
    p = next(q for q in base.parameters if q.name == entry["parameter"])
    trials = moved_trials(entry)
    span = p.high - p.low
    shifts = tuple(
        Parameter(f"{p.name}@{t}", p.unit, -span, span, f"trial {t}'s shift of {p.meaning}",
                  log=False, start=0.0, detectable=p.detectable, negligible=entry["size_floor"],
                  resolution=p.resolution)
        for t in trials
    )  # fmt: skip

    def transform(state, values, data):
        trial = trial_labels(problem, data)
        value = np.full(data.units, float(values[p.name]))
        for t, s in zip(trials, shifts, strict=True):
            value[trial == t] += values[s.name]
        return base.transform(state, {**values, p.name: value[:, None]}, data)

    alike = next(c.alike for c in problem.constants if c.row == entry["assumption"])
    read = f"; read alike: {', '.join(alike)}" if alike else ""
    return Effect(
        key(entry),
        f"{short_name(base.description)} moved in {', '.join(trials)} ({entry['name']}, one value "
        f"per trial where it departs from the session's{read})",
        (replace(p, shape=True), *shifts),
        base.observables,
        transform,
        alternatives=alike,
        any_size=True,
    )


def starts(entry: Mapping) -> dict[str, float]:
    """Start values of a moved constant's entry: p at the value of the trials that keep it (the
    others' of the departures, or the kept trial's estimate), each shift at its trial's
    estimate less p."""
    estimate = {t["trial"]: t["estimate"] for t in entry["trials"]}
    trials = moved_trials(entry)
    kept = [t for t in entry["used"] if t not in trials]
    session = (entry["departing"][0]["others"] if len(kept) > 1 or not entry["departing"]
               else estimate[kept[0]])  # fmt: skip
    name = entry["parameter"]
    return {name: session} | {f"{name}@{t}": estimate[t] - session for t in trials}


def settle(problem: Problem, data: Data, scales, settings: Settings, score, model: Mapping,
           stable: Mapping, fuller: Mapping) -> tuple[Problem, dict, dict] | None:  # fmt: skip
    """The problem with each moved constant's entry (:func:`shifted`, beside the effect whose
    parameter it moves), the settled model in which the entry takes that effect's place (the
    model the stability compared the trials in, from the one-value model's and ``fuller``'s
    estimates and the stability's per-trial ones) and its verdict, where the data earn a shift
    and its held-out loss is lower than ``model``'s by more than one paired standard error;
    else None."""
    moved = [e for e in stable["constants"] if movable(problem, e)]
    if not moved:
        return None
    wider, refitted = refit(problem, data, scales, settings, score, model, stable, fuller, moved)
    # a shift the refit does not earn leaves its trial the session's value: refitted once more
    kept = [trimmed(wider, e, refitted["intervals"]) if key(e) in refitted["effects"] else e
            for e in moved]  # fmt: skip
    if kept != moved:
        wider, refitted = refit(problem, data, scales, settings, score, model, stable, fuller,
                                kept)  # fmt: skip
    if not set(map(key, kept)) & set(refitted["effects"]):
        return None
    before, after = model["chosen"]["cv"]["loss"], refitted["chosen"]["cv"]["loss"]
    if np.mean(before - after) <= paired_se(before, after):
        return None
    return wider, refitted, verdict_of(wider, data, refitted, scales, settings)


def refit(problem: Problem, data: Data, scales, settings: Settings, score, model: Mapping,
          stable: Mapping, fuller: Mapping, moved: list) -> tuple[Problem, dict]:  # fmt: skip
    """The problem with the ``moved`` constants' entries and its settled model in which each takes
    its effect's place (:func:`settle`)."""
    registry: dict[str, Effect] = {}
    for name, effect in problem.registry.items():
        registry[name] = effect
        registry |= {key(e): shifted(problem, e) for e in moved if e["effect"] == name}
    wider = replace(problem, registry=registry)
    replaced = {e["effect"] for e in moved}
    effects = (*(e for e in stable["model"] if e not in replaced), *map(key, moved))
    start = {**fuller.get("values", {}), **model["values"]}
    for e in moved:
        start |= starts(e)
    chosen = score(wider, data, [effects], scales, settings, model["chosen"])[0]
    return wider, settled(wider, data, scales, settings, False, score,
                          {**chosen, "values": start})  # fmt: skip


def trimmed(problem: Problem, entry: Mapping, intervals: Mapping) -> Mapping:
    """A moved constant's stability entry with only the departing trials whose shift the refit
    earns (:func:`intervals.sized`; the entry itself where every one is)."""
    shifts = [p for p in problem.registry[key(entry)].parameters if not p.shape]
    earned = {p.name.split("@", 1)[1] for p in shifts if sized(p, intervals[p.name])}
    if len(earned) == len(shifts):
        return entry
    return {**entry, "departing": [d for d in entry["departing"] if d["trial"] in earned]}
