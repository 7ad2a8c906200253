"""A constant of the rig that moved between trials, refitted in the trials where it moved.

The model fits one value of each constant for the session. Where a sensor is re-zeroed before
some trials, that one value fits none of them well, and the observable the constant shows in
misfits in every trial that moved; the parameter stability (:mod:`.stability`) finds the trials
that depart. Where the model leaves structure and the stability flags a constant that the group
lets take one value per unit (``Problem.per_unit``, a linear parameter of a registry effect),
the constant gets one shift per departing trial: its value there is the session's plus the
trial's own d_i, elsewhere the session's. The shifts enter as one entry named after the
table's row (its ``between`` relaxation), placed after the effect whose parameter they move,
and the model with them is settled as any other (an unearned shift drops the entry). It
replaces the one-value model when it leaves structure in fewer observables: the observables the
move explained then support claims again, and the entry names the row with its trials.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import replace

import numpy as np

from exobench.selection.intervals import settled
from exobench.selection.model import Data, Effect, Parameter, Problem, Settings
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


def shifted(problem: Problem, entry: Mapping) -> Effect:
    """A moved constant's shift in each departing trial as one entry: its parameter p is
    p + d_i in trial i's units (one value per unit, shaped (units, 1)), p elsewhere; the rows
    whose violation reads as the same change are its alternatives."""
    base = problem.registry[entry["effect"]]
    p = next(q for q in base.parameters if q.name == entry["parameter"])
    trials = [d["trial"] for d in entry["departing"]]
    span = p.high - p.low
    shifts = tuple(
        Parameter(f"{p.name}@{t}", p.unit, -span, span, f"trial {t}'s shift of {p.meaning}",
                  log=False, start=0.0, detectable=p.detectable, negligible=entry["size_floor"],
                  resolution=p.resolution)
        for t in trials
    )  # fmt: skip

    def transform(state, values, data):
        trial = np.asarray(problem.trials(data) if problem.trials else data.trial)
        value = np.full(data.units, float(values.get(p.name, p.neutral)))
        for t, s in zip(trials, shifts, strict=True):
            value[trial == t] += values[s.name]
        return base.transform(state, {**values, p.name: value[:, None]}, data)

    alike = next(c.alike for c in problem.constants if c.row == entry["assumption"])
    read = f"; read alike: {', '.join(alike)}" if alike else ""
    return Effect(
        key(entry),
        f"{short_name(base.description)} moved in {', '.join(trials)} ({entry['name']}, one value "
        f"per trial where it departs from the session's{read})",
        shifts,
        base.observables,
        transform,
        alternatives=alike,
    )


def settle(problem: Problem, data: Data, scales, settings: Settings, score, model: Mapping,
           stable: Mapping) -> tuple[Problem, dict, dict] | None:  # fmt: skip
    """The problem with each moved constant's shifts (:func:`shifted`, after the effect they
    move), the settled model holding them and the effect they move (from the one-value model's
    estimates and the stability's departures) and its verdict, where the data earn a shift and
    the model predicts the held-out units better than ``model``; else None."""
    moved = [e for e in stable["constants"] if movable(problem, e)]
    if not moved:
        return None
    registry: dict[str, Effect] = {}
    for name, effect in problem.registry.items():
        registry[name] = effect
        registry |= {key(e): shifted(problem, e) for e in moved if e["effect"] == name}
    wider = replace(problem, registry=registry)
    # the session's value is fitted too (from the other trials'), the shifts from it
    added = tuple(dict.fromkeys([*(e["effect"] for e in moved), *map(key, moved)]))
    start = dict(model["values"])
    for e in moved:
        start.setdefault(e["parameter"], e["departing"][0]["others"])
        start |= {f"{e['parameter']}@{d['trial']}": d["difference"] for d in e["departing"]}
    effects = tuple(dict.fromkeys([*model["effects"], *added]))
    chosen = score(wider, data, [effects], scales, settings, model["chosen"])[0]
    refitted = settled(wider, data, scales, settings, False, score, {**chosen, "values": start})
    kept = set(map(key, moved)) & set(refitted["effects"])
    if not kept or loss(refitted) >= loss(model):
        return None
    return wider, refitted, verdict_of(wider, data, refitted, scales, settings)


def loss(model: Mapping) -> float:
    """A settled model's mean held-out loss per unit."""
    return float(model["chosen"]["cv"]["loss"].mean())
