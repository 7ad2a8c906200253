"""Discovered terms: what the data earn beyond the registry, as hypotheses for the lab to check.

When the registry's selected model leaves structure unexplained, the problem's library of
correction terms (one per relaxed assumption of the rig: a channel's gain, offset, drift, lag or
crosstalk, a value off the rig's, a law an element was assumed not to have) is searched in two
stages. A cheap screen first: a Lasso path of the model's residual on every term's linearised
effect (one forward evaluation per term) ranks the whole library, and only the first
``screen_terms`` to enter go on. Those are searched the registry's way: forward selection on
held-out units, the fewest terms within one paired standard error of the best, from the
registry's model and, when that holds effects a fault may have faked, from the baseline too.
The registry is then selected again from the baseline with those terms in the model (a registry
effect the fault had hidden is found, one it had faked is not), and the combined model keeps
only what its intervals earn. A term is named only when the model with it leaves nothing
flagged and its interval excludes the neutral value; the terms that explain the data as well in
its place (their linearised effects alike, their refits as good) are named beside it.
"""

from __future__ import annotations

import warnings
from collections.abc import Mapping, Sequence
from dataclasses import replace

import numpy as np

from exobench.selection.fitting import fit
from exobench.selection.intervals import earned, estimate, resolved, settled
from exobench.selection.intervals import widened as stretch
from exobench.selection.model import (
    Data,
    Problem,
    Settings,
    observable_weight,
    ordered,
    residuals,
    unit_loss,
)
from exobench.selection.search import (
    forward_selection,
    held_out,
    one_se_rule,
    paired_se,
    probe_value,
)
from exobench.selection.structure import verdict_of
from exobench.selection.summary import term_statement
from exobench.selection.workers import mapped


def discover(problem: Problem, data: Data, scales, settings: Settings, model: dict,
             baseline: dict, best: dict | None = None) -> dict:  # fmt: skip
    """The term search on top of the registry's ``best`` model on its path (else the settled
    ``model``, :func:`settled`) and, when its combined model still leaves structure and the
    registry model holds effects, on top of the model's structural effects alone
    (:func:`structural`; a fault can fake registry effects, and terms added on top of those
    only compensate them): per root, the terms chosen, the
    registry selected again with them and the combined model's verdict; the search whose
    combined model leaves nothing flagged, else the lower held-out loss."""
    # the registry's fullest explanation (the lowest held-out loss on its path, not the 1-SE
    # pick: an effect small beside the unexplained structure is still part of what is known)
    registry = best if best is not None else {**model["chosen"], "values": model["values"]}
    first = extended(problem, data, scales, settings, registry) | {"root": "registry model"}
    first["registry_screen"] = first["screen"]
    if _rank(first)[0] == 0 or not model["effects"]:
        return first
    second = structural(problem, data, scales, settings, model, baseline)
    if tuple(second["effects"]) == tuple(model["effects"]):
        return first
    again = extended(problem, data, scales, settings, second) | {"root": second["root"]}
    return min((first, again | {"registry_screen": first["screen"]}), key=_rank)


def structural(problem: Problem, data: Data, scales, settings: Settings, model: dict,
               baseline: dict) -> dict:  # fmt: skip
    """The second root of the term search: the registry model's effects that a library term
    builds on (a compliance a friction or a drift belongs to), refitted alone, else the
    baseline; the model's other effects may be a fault's disguise."""
    needed = {r for term in problem.terms.values() for r in term.requires}
    effects = tuple(e for e in model["effects"] if e in needed)
    if not effects:
        return {**baseline, "values": baseline.get("values", {}), "root": "baseline"}
    values, _ = fit(problem, data, effects, scales, model["values"])
    root = held_out(problem, data, [effects], scales, settings)[0]
    return {**root, "values": values, "root": "the registry's " + ", ".join(effects)}


def _refit_task(problem, data, scales, effects, start) -> dict:
    """A model's full-data fit from ``start``."""
    return fit(problem, data, effects, scales, start)[0]


def misfit_factor(verdict: Mapping, observables=None) -> float:
    """√(1 + S²), S the largest structure a flagged residual test finds, in noise units (of the
    ``observables`` given: those an effect shows in): the residual's spread over the noise's
    where a model leaves structure."""
    sizes = [float(t.get("size", 0.0)) for t in verdict["tests"]
             if t["flag"] and (observables is None or t["observable"] in observables)]  # fmt: skip
    return float(np.sqrt(1.0 + max(sizes, default=0.0) ** 2))


def known_beside(problem: Problem, data: Data, scales, settings: Settings, model: dict,
                 extensions, verdict: Mapping) -> dict[str, dict[str, list[float]]]:  # fmt: skip
    """What is known though structure is left: the registry effects of a settled ``model``
    that are structural (those other effects and terms build on: a compliance, which a fault
    rarely fakes, where a loss or a delay may be a fault's disguise), that a check of the
    recordings located (the problem's ``located``) or that show in no observable a residual test
    of ``verdict`` flags (one observable's misfit, a controller departing from its table, says
    nothing of an effect it does not show), whose every estimate stays inside its 95 %
    interval whichever candidate extension (a term of ``extensions``) is added and the model
    refitted on all the data (a located one's need not: it is there whatever else is); each
    interval then stretched about its estimate by the misfit of the observables it shows in
    (:func:`misfit_factor`) and widened to hold those estimates; only effects it earns."""
    effects = tuple(model["effects"])
    extra = [t for t in extensions
             if all(r in effects for r in problem.entries[t].requires)]  # fmt: skip
    fits = mapped(_refit_task, [((*effects, t), model["values"]) for t in extra], problem, data,
                  scales)  # fmt: skip
    flagged = {t["observable"] for t in verdict["tests"] if t["flag"]}
    known = {r for entry in problem.entries.values() for r in entry.requires}
    known |= set(problem.located)
    known |= {e for e in effects if not flagged & set(problem.entries[e].observables)}
    out = {}
    for name in (e for e in effects if e in problem.registry and e in known):
        effect = problem.registry[name]
        # a term of the same element changes what its parameter means (a drifting stiffness
        # is the one at the trial's start): only the other candidates test it
        others = [f for t, f in zip(extra, fits, strict=True)
                  if name not in problem.entries[t].requires]  # fmt: skip
        widened = {}
        misfit = misfit_factor(verdict, effect.observables)
        stretched = stretch(problem, (name,), model["values"], model["intervals"], misfit)
        for p in effect.parameters:
            low, high = model["intervals"][p.name]
            estimates = [f[p.name] for f in others]
            # a located effect is there whatever else is: its interval holds every reading
            if name not in problem.located and not all(low <= e <= high for e in estimates):
                break
            low, high = stretched[p.name]
            widened[p.name] = [min(low, *estimates, np.inf), max(high, *estimates, -np.inf)]
        else:
            if earned(effect, widened):
                out[name] = widened
    return out


def patterns(verdict: Mapping) -> list[dict]:
    """The residual tests that find a pattern beyond their noise threshold, counted or not."""
    return [t for t in verdict["tests"] if t["statistic"] > t["threshold"]]


# A term's shape parameter the data may not fix (an artefact's phase) is profiled at this many
# values over its fit range: the model refitted with it held at each.
PROFILE_POINTS = 6


def _reading_task(problem, data, scales, settings, effects, start) -> tuple[dict, dict]:
    """A model's full-data estimates and 95 % intervals (bootstrap) from ``start``."""
    values, intervals, _ = estimate(problem, data, effects, scales, settings, False, start)
    return values, intervals


def _held_task(problem, data, scales, effects, start, held) -> tuple[dict, np.ndarray]:
    """A model's full-data fit with the parameters ``held`` at their values, and its per-unit
    loss."""
    terms = {n: pin(e, held) if any(p.name in held for p in e.parameters) else e
             for n, e in problem.terms.items()}  # fmt: skip
    values, _ = fit(replace(problem, terms=terms), data, effects, scales, start)
    values = {**values, **held}
    return values, unit_loss(residuals(problem, data, effects, values, scales))


def pin(effect, held: Mapping[str, float]):
    """An effect with the parameters ``held`` fixed at their values (not fitted)."""

    def transform(state, values, data):
        return effect.transform(state, {**values, **held}, data)

    free = tuple(p for p in effect.parameters if p.name not in held)
    return replace(effect, parameters=free, transform=transform)


def profiled(problem: Problem, data: Data, scales, effects, values: Mapping, term: str) -> dict:
    """What a reading's estimates span over the values of its term's shape parameters that fit
    as well (:data:`PROFILE_POINTS` over the fit range, each held and the rest refitted; those
    whose loss exceeds the best's by at most one paired standard error): per parameter, the
    lowest and highest estimate."""
    shapes = [p for p in problem.terms[term].parameters if p.shape]
    if not shapes:
        return {}
    grid = [{p.name: float(v)} for p in shapes
            for v in np.linspace(p.low, p.high, PROFILE_POINTS + 1)[:-1]]  # fmt: skip
    fits = mapped(_held_task, [(effects, values, held) for held in grid], problem, data, scales)
    own = unit_loss(residuals(problem, data, effects, values, scales))
    best = min([own, *(loss for _, loss in fits)], key=np.mean)
    near = [v for v, loss in fits if loss.mean() - best.mean() <= paired_se(loss, best)]
    return {name: [min(v[name] for v in near), max(v[name] for v in near)]
            for name in values} if near else {}  # fmt: skip


def readings(problem: Problem, data: Data, scales, settings: Settings, model: dict,
             verdict: Mapping, suspects: Sequence[str] = ()) -> list[dict]:  # fmt: skip
    """Other readings of what a settled ``model`` claims, where its held-out residuals hold a
    pattern beyond the noise (:func:`patterns`) that no test counts (the library ranked by the
    linear screen from the model, its first ``screen`` terms) or a direct check of the
    recordings saw a relaxation the model lacks (``suspects``, library terms): each term added
    and the model refitted on all the data, its intervals widened as the model's were (and to
    hold what a shape of the term the data do not fix gives, :func:`profiled`). A term whose
    own interval is earned (the data size it) and that moves a registry estimate of the model
    outside its interval is a reading the data cannot tell from the model's: the estimates it
    moves, with its intervals and the term's size."""
    if not problem.terms or settings.max_terms == 0:
        return []
    effects = tuple(model["effects"])
    candidates = [t for t in suspects if t in problem.terms and t not in effects
                  and all(r in effects for r in problem.terms[t].requires)]  # fmt: skip
    if patterns(verdict):
        screen = linear_screen(problem, data, scales, settings,
                               {"effects": effects, "values": model["values"]})  # fmt: skip
        candidates = list(dict.fromkeys([*screen["survivors"][: settings.screen], *candidates]))
    if not candidates:
        return []
    fits = mapped(_reading_task, [(settings, (*effects, t), model["values"]) for t in candidates],
                  problem, data, scales)  # fmt: skip
    out = []
    for term, (values, intervals) in zip(candidates, fits, strict=True):
        extended = tuple(ordered(problem, (*effects, term)))
        intervals = resolved(
            problem,
            extended,
            values,
            stretch(problem, extended, values, intervals, model["widening"]),
        )
        # the model's registry estimates this reading moves outside their intervals
        outside = [p.name for e in effects if e in problem.registry
                   for p in problem.registry[e].parameters
                   if not model["intervals"][p.name][0] <= values[p.name]
                   <= model["intervals"][p.name][1]]  # fmt: skip
        if outside and earned(problem.terms[term], intervals):
            # a shape the data do not fix: the intervals hold every estimate of its profile too
            for name, (low, high) in profiled(problem, data, scales, extended, values,
                                              term).items():  # fmt: skip
                intervals[name] = [min(low, intervals[name][0]), max(high, intervals[name][1])]
            moved = {n: {"estimate": values[n], "ci95": intervals[n]} for n in outside}
            params = problem.terms[term].parameters
            out.append({"term": term, "description": problem.terms[term].description,
                        "parameters": {p.name: values[p.name] for p in params},
                        "ci95": {p.name: intervals[p.name] for p in params},
                        "units": {p.name: p.unit for p in params}, "moves": moved})  # fmt: skip
    return out


def swaps(problem: Problem, data: Data, scales, settings: Settings, model: dict,
          settled_already: Sequence[str] = ()) -> list[dict]:  # fmt: skip
    """Readings in which a library term or another registry effect takes a claimed registry
    effect's place: for each effect of a settled ``model`` that no other effect builds on and no
    check of the recordings located, the terms and effects outside the model (none located)
    whose linearised effect is alike what the effect explains (cosine at least ``alike``; the
    ``screen`` most alike) and whose swapped model's full-data loss, and then held-out loss,
    exceed the model's by at most one paired standard error; each, where its own interval is
    earned, as a reading (:func:`readings`' shape) in which the effect sits at its neutral
    value (``settled_already``: effects another reading already leaves unclaimed, not
    tried)."""
    if not problem.terms or settings.max_terms == 0:
        return []
    effects, values = tuple(model["effects"]), model["values"]
    full = residuals(problem, data, effects, values, scales)
    masks = {obs: np.isfinite(r) for obs, r in full.items()}
    own, held = unit_loss(full), model["chosen"]["cv"]["loss"]
    built_on = {r for e in effects for r in problem.entries[e].requires}
    claimed = [e for e in effects if e in problem.registry and e not in built_on
               and e not in problem.located and e not in settled_already]  # fmt: skip
    entries = problem.entries
    names = [t for t, e in entries.items() if t not in effects and t not in problem.located
             and all(r in effects for r in e.requires)]  # fmt: skip
    if not claimed or not names:
        return []
    # the terms' linearised effects, once, at the model (not at each model without an effect)
    target = _vector(full, masks)
    columns = {}
    for term, parts in zip(names, mapped(_column_task, [(effects, values, t) for t in names],
                                         problem, data, scales), strict=True):  # fmt: skip
        column = _vector(parts[0][0], masks) - target
        norm = float(np.linalg.norm(column))
        if norm > 0.0:
            columns[term] = column / norm
    out = []
    for name in claimed:
        rest = tuple(e for e in effects if e != name)
        # what the effect explains: the residual without it less the model's
        explained = _vector(residuals(problem, data, rest, values, scales), masks) - target
        size = float(np.linalg.norm(explained))
        cosine = {t: abs(float(column @ explained)) / size for t, column in columns.items()
                  if name not in entries[t].requires and size > 0.0}  # fmt: skip
        # the most alike first, the ``screen`` first refitted (as a forward step's)
        alike = sorted((t for t, c in cosine.items() if c >= settings.alike),
                       key=lambda t: -cosine[t])[: settings.screen]  # fmt: skip
        if not alike:
            continue
        swapped = [tuple(ordered(problem, (*rest, t))) for t in alike]
        fits = mapped(_swap_task, [(e, values) for e in swapped], problem, data, scales)
        close = [i for i, (loss, _) in enumerate(fits)
                 if loss.mean() - own.mean() <= paired_se(loss, own)]  # fmt: skip
        scored = held_out(problem, data, [swapped[i] for i in close], scales, settings,
                          model["chosen"])  # fmt: skip
        kept = [i for i, sc in zip(close, scored, strict=True)
                if sc["cv"]["loss"].mean() - held.mean()
                <= paired_se(sc["cv"]["loss"], held)]  # fmt: skip
        readings_of = mapped(_reading_task, [(settings, swapped[i], fits[i][1]) for i in kept],
                             problem, data, scales)  # fmt: skip
        neutral = {p.name: {"estimate": p.neutral, "ci95": [p.neutral, p.neutral]}
                   for p in problem.registry[name].parameters if not p.shape}  # fmt: skip
        for i, (found, intervals) in zip(kept, readings_of, strict=True):
            term = alike[i]
            intervals = resolved(problem, swapped[i], found,
                                 stretch(problem, swapped[i], found, intervals,
                                         model["widening"]))  # fmt: skip
            if not earned(entries[term], intervals):
                continue
            params = entries[term].parameters
            out.append({"term": term, "description": entries[term].description,
                        "parameters": {p.name: found[p.name] for p in params},
                        "ci95": {p.name: intervals[p.name] for p in params},
                        "units": {p.name: p.unit for p in params}, "moves": neutral,
                        "in_place_of": name})  # fmt: skip
    return out


def holding_either(entries: list[dict], found: list[dict]) -> list[dict]:
    """Claimed registry effects (report entries) whose intervals hold what either reading gives
    (the model's and each of ``found``, :func:`readings`): each moved parameter's interval the
    hull of its own and the readings', and the readings it cannot be told from."""
    out = []
    for entry in entries:
        ci95, alternatives = dict(entry["ci95"]), []
        for reading in found:
            moved = {p: m for p, m in reading["moves"].items() if p in entry["parameters"]}
            for name, m in moved.items():
                low, high = ci95[name]
                ci95[name] = [min(low, m["ci95"][0]), max(high, m["ci95"][1])]
            if moved:
                alternatives.append({"term": reading["term"],
                                     "description": reading["description"],
                                     "parameters": {p: m["estimate"] for p, m in moved.items()},
                                     "ci95": {p: m["ci95"] for p, m in moved.items()}})  # fmt: skip
        out.append({**entry, "ci95": ci95, **({"cannot_tell": alternatives} if alternatives
                                              else {})})  # fmt: skip
    return out


# Two terms whose linearised effects are the same up to their size (cells carrying shares of one
# force) are one column of the screen.
DUPLICATE_COSINE = 1.0 - 1e-9


def linearised_step(parameter) -> float:
    """The step a term's linearised effect is taken over: from its neutral value to
    :func:`probe_value` (a term's effect need not be linear down to zero: friction sticks)."""
    return float(probe_value(parameter) - parameter.neutral)


def _vector(res: Mapping[str, np.ndarray], masks: Mapping[str, np.ndarray]) -> np.ndarray:
    """The least-squares residual vector on fixed samples: each observable's counted samples
    times √(its weight), not-a-number as 0 (a term may leave a sample undefined)."""
    parts = []
    for obs, mask in masks.items():
        values = np.where(np.isfinite(res[obs]), res[obs], 0.0)[mask]
        parts.append(values * np.sqrt(observable_weight(mask.sum())))
    return np.concatenate(parts)


def _column_task(problem, data, scales, effects, values, name) -> list[tuple]:
    """A term's linearised effects on the residuals of a model: its size's (one forward
    evaluation, from the model's residuals) and, where it has more parameters (an artefact's
    phase), each of theirs at the size's probe (one more each, from the probe's residuals):
    (residuals, those they are taken from, None for the model's, step, whether either way)."""
    term = problem.entries[name]
    first = term.parameters[0]
    step = linearised_step(first)
    start = {p.name: p.initial() for p in term.parameters[1:]}
    probed = {**start, **values, first.name: first.neutral + step}
    res = residuals(problem, data, (*effects, name), probed, scales)
    out = [(res, None, step, not first.log)]
    for p in term.parameters[1:]:
        nudge = linearised_step(p)
        moved = {**probed, p.name: p.initial() + nudge}
        out.append((residuals(problem, data, (*effects, name), moved, scales), res, nudge, True))
    return out


def linear_screen(problem: Problem, data: Data, scales, settings: Settings, root: dict) -> dict:
    """The library ranked by a Lasso path (LARS) of the ``root`` model's full-data residual on
    every term's linearised effect (the terms whose requirements the model holds; a signed
    term enters either way, another only in its own direction), the first ``screen_terms`` to
    enter kept; with each term's unit effect vector, which tells terms that act alike."""
    effects = tuple(root["effects"])
    values = root.get("values", {})
    base = residuals(problem, data, effects, values, scales)
    masks = {obs: np.isfinite(r) for obs, r in base.items()}
    target = _vector(base, masks)
    names = [n for n, term in problem.terms.items()
             if n not in effects and all(r in effects for r in term.requires)]  # fmt: skip
    moved = mapped(_column_task, [(effects, values, n) for n in names], problem, data, scales)
    columns, kept, either, directions = [], [], [], {}
    for name, parts in zip(names, moved, strict=True):
        for res, ref, step, both in parts:
            column = _vector(res, masks) - (target if ref is None else _vector(ref, masks))
            column = column / step
            size = float(np.linalg.norm(column))
            if np.isfinite(size) and size > 0.0:
                columns.append(column / size)
                kept.append(name)
                either.append(both)
                directions.setdefault(name, column / size)  # its size's effect
    if not kept:
        return {"survivors": [], "order": [], "directions": {}}
    # terms that act alike (the same effect up to its size) enter the path once, as the first
    # of them: which of them is meant is the alternatives' question, asked of the survivors
    cosines = np.abs(np.column_stack(columns).T @ np.column_stack(columns))
    first = [i for i in range(len(kept)) if not np.any(cosines[i, :i] > DUPLICATE_COSINE)]
    signed = [either[i] for i in first]
    # an unsigned term may only move away from its neutral value: its column enters positive
    matrix = np.column_stack(
        [columns[i] for i in first] + [-columns[i] for i, s in zip(first, signed, strict=True) if s]
    )
    owner = [kept[i] for i in first] + [kept[i] for i, s in zip(first, signed, strict=True) if s]
    from sklearn.exceptions import ConvergenceWarning  # here: only the screen needs it
    from sklearn.linear_model import lars_path

    with warnings.catch_warnings():  # collinear columns: LARS drops one and says so
        warnings.simplefilter("ignore", ConvergenceWarning)
        _, _, path = lars_path(matrix, -target, method="lasso", positive=True,
                               max_iter=4 * settings.screen_terms)  # fmt: skip
    entered = np.argmax(path != 0.0, axis=1)  # the step of the path each column enters at
    order = list(dict.fromkeys(owner[i] for i in np.argsort(entered, kind="stable")
                               if path[i].any()))  # fmt: skip
    return {
        "survivors": order[: settings.screen_terms],
        "order": order,
        "directions": directions,
    }


def _rank(search: dict) -> tuple[int, float]:
    """A search's order: flagged (or no terms) after clean, then by held-out loss."""
    if search["final"] is None:
        return (2, np.inf)
    return (int(search["verdict"]["flag"]), float(search["final"]["chosen"]["cv"]["loss"].mean()))


def extended(problem: Problem, data: Data, scales, settings: Settings, root: dict) -> dict:
    """Forward selection of library terms from a ``root`` model (the fewest within one paired
    standard error of the best), the registry selected again from the baseline with those
    terms in the model, settled, and the structure left in its held-out residuals."""
    screen = linear_screen(problem, data, scales, settings, root)
    # the survivors compete with the registry's effects the root lacks: a fault's term may need
    # one beside it (a drifting cell with an offset), found together step by step
    pool = [*screen["survivors"], *(e for e in problem.registry if e not in root["effects"])]
    path, tried = forward_selection(problem, data, scales, settings, held_out, options=pool,
                                    root=root, limit=settings.max_terms)  # fmt: skip
    pick = one_se_rule(path)
    terms = tuple(e for e in ordered(problem, pick["effects"]) if e in problem.terms)
    out = {"forward_path": [list(ordered(problem, p["effects"])) for p in path], "tried": tried,
           "terms": terms, "screen": screen}  # fmt: skip
    if not terms:
        return {**out, "final": None, "verdict": None, "named": ()}
    needed = tuple(
        ordered(problem, {*terms, *(r for e in terms for r in problem.entries[e].requires)})
    )
    values, _ = fit(problem, data, needed, scales, pick["values"])
    start = held_out(problem, data, [needed], scales, settings, pick)[0]
    rpath, rtried = forward_selection(problem, data, scales, settings, held_out,
                                      root={**start, "values": values}, linear=True)  # fmt: skip
    final = settled(problem, data, scales, settings, False, held_out, one_se_rule(rpath))
    final, gains = without_idle_terms(problem, data, scales, settings, final)
    verdict = verdict_of(problem, data, final, scales, settings)
    kept = tuple(e for e in final["effects"] if e in problem.terms)
    return {
        **out,
        "reselected_path": [list(ordered(problem, p["effects"])) for p in rpath],
        "tried": tried + rtried,
        "final": final,
        "gains": gains,
        "verdict": verdict,
        "kept": kept,
        "named": () if verdict["flag"] else kept,
    }


def without_idle_terms(problem: Problem, data: Data, scales, settings: Settings, final: dict):
    """The settled model without the terms that do not earn their place on held-out units:
    while a term removes less than ``min_gain`` of the held-out error the model without it
    leaves (two terms that do one job each remove nothing the other does not), the weakest is
    dropped (with what requires it) and the rest refitted, rescored and settled; the model and
    its terms' gains (:func:`term_gains`)."""
    while True:
        gains = term_gains(problem, data, scales, settings, final)
        weak = [t for t, g in gains.items() if g["gain_pct"] < 100.0 * settings.min_gain]
        if not weak:
            return final, gains
        drop = min(weak, key=lambda t: gains[t]["gain_pct"])
        effects = tuple(e for e in final["effects"]
                        if e != drop and drop not in problem.entries[e].requires)  # fmt: skip
        chosen = held_out(problem, data, [effects], scales, settings, final["chosen"])[0]
        final = settled(problem, data, scales, settings, False, held_out,
                        {**chosen, "values": final["values"]})  # fmt: skip


def term_gains(problem: Problem, data: Data, scales, settings: Settings, final: dict) -> dict:
    """For every term of a final model: the held-out loss of the model without it against the
    model with it (the share of the error the term removes)."""
    with_all = final["chosen"]["cv"]["loss"]
    terms = [e for e in final["effects"] if e in problem.terms]
    smaller = [tuple(e for e in final["effects"] if e != term) for term in terms]
    scored = held_out(problem, data, smaller, scales, settings, final["chosen"])
    return {
        term: {
            "loss_without": float(s["cv"]["loss"].mean()),
            "loss_with": float(with_all.mean()),
            "gain_pct": 100.0 * (1.0 - with_all.mean() / s["cv"]["loss"].mean()),
        }
        for term, s in zip(terms, scored, strict=True)
    }


def _swap_task(problem, data, scales, effects, start) -> tuple[np.ndarray, dict]:
    """Per-unit loss of a full-data fit (from ``start``) and the fit."""
    values, _ = fit(problem, data, effects, scales, start)
    return unit_loss(residuals(problem, data, effects, values, scales)), values


def alternatives(problem: Problem, data: Data, scales, settings: Settings, final: dict,
                 gains: Mapping, directions: Mapping[str, np.ndarray]) -> dict:  # fmt: skip
    """For every term of a final model, the other library terms that explain the data as well
    in its place: among those whose linearised effect is alike (cosine at least ``alike``, from
    the screen's ``directions``), the swapped model's full-data loss, and then its held-out
    loss, exceed the final model's by at most one paired standard error or by less than
    ``min_gain`` of what the term removes (a difference below any finding: three load cells
    carrying fixed shares of one force leave the same residual whichever reads wrong)."""
    effects = tuple(final["effects"])
    own, _ = _swap_task(problem, data, scales, effects, final["values"])
    held = final["chosen"]["cv"]["loss"]
    out: dict[str, list[str]] = {}
    for term in (e for e in effects if e in problem.terms):
        margin = settings.min_gain * max(gains[term]["loss_without"] - gains[term]["loss_with"],
                                          0.0)  # fmt: skip
        own_direction = directions.get(term)
        others = [u for u in problem.terms if u not in effects
                  and all(r in effects for r in problem.terms[u].requires)
                  and (own_direction is None or u not in directions
                       or abs(float(directions[u] @ own_direction)) >= settings.alike)]  # fmt: skip
        swaps = [tuple(ordered(problem, [*(e for e in effects if e != term), u])) for u in others]
        fits = mapped(_swap_task, [(s, final["values"]) for s in swaps], problem, data, scales)
        close = [i for i, (loss, _) in enumerate(fits)
                 if loss.mean() - own.mean() <= max(paired_se(loss, own), margin)]  # fmt: skip
        scored = held_out(problem, data, [swaps[i] for i in close], scales, settings,
                          final["chosen"])  # fmt: skip
        out[term] = [
            others[i]
            for i, s in zip(close, scored, strict=True)
            if s["cv"]["loss"].mean() - held.mean() <= max(paired_se(s["cv"]["loss"], held), margin)
        ]
    return out


def term_entry(problem: Problem, name: str, values: Mapping, intervals: Mapping,
               gain: Mapping, alike: list[str]) -> dict:  # fmt: skip
    """A discovered term as the report states it: the hypothesis in words (its element or
    channel, law, estimate with 95 % interval, the share of the error it removes and the terms
    that would serve as well: :func:`summary.term_statement`), its estimate, interval and unit."""
    term = problem.terms[name]
    params = term.parameters
    entry = {
        "term": name,
        "description": term.description,
        "observables": list(term.observables),
        "parameters": {p.name: values[p.name] for p in params},
        "units": {p.name: p.unit for p in params},
        "ci95": {p.name: intervals[p.name] for p in params},
        "neutral": {p.name: p.neutral for p in params},
        "gain": dict(gain),
        "alternatives": list(alike),
    }
    library = {n: {"description": e.description,
                   "parameters": [{"name": p.name, "meaning": p.meaning, "bounds": [p.low, p.high]}
                                  for p in e.parameters]}
               for n, e in problem.terms.items()}  # fmt: skip
    return {**entry, "statement": term_statement(entry, library)}
