"""Discovered terms: what the data earn beyond the registry, as hypotheses for the lab to check.

When the registry's selected model leaves structure unexplained, the problem's library of
correction terms (built from what the recording holds, without a physical story: a channel's
gain, offset or drift, a scale on a nominal rig constant, a rate term of a joint) is searched
the registry's way: forward selection on held-out units, the fewest terms within one paired
standard error of the best, from the registry's model and, when that holds effects a fault may
have faked, from the baseline too. The registry is then selected again from the baseline with
those terms in the model (a registry effect the fault had hidden is found, one it had faked is
not), and the combined model keeps only what its intervals earn. A term is named only when the
model with it leaves nothing flagged and its interval excludes the neutral value; the terms
that explain the data as well in its place are named beside it.
"""

from __future__ import annotations

from collections.abc import Mapping

import numpy as np

from exobench.selection.fitting import fit
from exobench.selection.intervals import settled
from exobench.selection.model import Data, Problem, Settings, ordered, residuals, unit_loss
from exobench.selection.search import forward_selection, held_out, one_se_rule, paired_se
from exobench.selection.structure import verdict_of
from exobench.selection.workers import mapped


def discover(problem: Problem, data: Data, scales, settings: Settings, model: dict,
             baseline: dict) -> dict:  # fmt: skip
    """The term search on top of a settled registry ``model`` (:func:`settled`) and, when its
    combined model still leaves structure and the registry model holds effects, on top of the
    ``baseline`` as well (a sensor fault can fake registry effects, and terms added on top of
    those only compensate them): per root, the terms chosen, the registry selected again with
    them and the combined model's verdict; the search whose combined model leaves nothing
    flagged, else the lower held-out loss."""
    registry = {**model["chosen"], "values": model["values"]}
    first = extended(problem, data, scales, settings, registry) | {"root": "registry model"}
    if _rank(first)[0] == 0 or not model["effects"]:
        return first
    bare = {**baseline, "values": baseline.get("values", {})}
    again = extended(problem, data, scales, settings, bare) | {"root": "baseline"}
    return min((first, again), key=_rank)


def _rank(search: dict) -> tuple[int, float]:
    """A search's order: flagged (or no terms) after clean, then by held-out loss."""
    if search["final"] is None:
        return (2, np.inf)
    return (int(search["verdict"]["flag"]), float(search["final"]["chosen"]["cv"]["loss"].mean()))


def extended(problem: Problem, data: Data, scales, settings: Settings, root: dict) -> dict:
    """Forward selection of library terms from a ``root`` model (the fewest within one paired
    standard error of the best), the registry selected again from the baseline with those
    terms in the model, settled, and the structure left in its held-out residuals."""
    path, tried = forward_selection(problem, data, scales, settings, held_out,
                                    options=list(problem.terms), root=root,
                                    limit=settings.max_terms)  # fmt: skip
    pick = one_se_rule(path)
    terms = tuple(e for e in ordered(problem, pick["effects"]) if e in problem.terms)
    out = {"forward_path": [list(ordered(problem, p["effects"])) for p in path], "tried": tried,
           "terms": terms}  # fmt: skip
    if not terms:
        return {**out, "final": None, "verdict": None, "named": ()}
    values, _ = fit(problem, data, terms, scales, pick["values"])
    start = held_out(problem, data, [terms], scales, settings, pick)[0]
    rpath, rtried = forward_selection(problem, data, scales, settings, held_out,
                                      root={**start, "values": values})  # fmt: skip
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
    while a term removes less than ``min_share`` of the held-out error the model without it
    leaves (two terms that do one job each remove nothing the other does not), the weakest is
    dropped (with what requires it) and the rest refitted, rescored and settled; the model and
    its terms' gains (:func:`term_gains`)."""
    while True:
        gains = term_gains(problem, data, scales, settings, final)
        weak = [t for t, g in gains.items() if g["gain_pct"] < 100.0 * settings.min_share]
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
                 gains: Mapping) -> dict:  # fmt: skip
    """For every term of a final model, the other library terms that explain the data as well
    in its place: the swapped model's full-data loss, and then its held-out loss, exceed the
    final model's by at most one paired standard error or by less than ``min_share`` of what
    the term removes (a difference below any finding: three load cells carrying fixed shares
    of one force leave the same residual whichever reads wrong)."""
    effects = tuple(final["effects"])
    own, _ = _swap_task(problem, data, scales, effects, final["values"])
    held = final["chosen"]["cv"]["loss"]
    out: dict[str, list[str]] = {}
    for term in (e for e in effects if e in problem.terms):
        margin = settings.min_share * max(gains[term]["loss_without"] - gains[term]["loss_with"],
                                          0.0)  # fmt: skip
        others = [u for u in problem.terms if u not in effects
                  and all(r in effects for r in problem.terms[u].requires)]  # fmt: skip
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
    """A discovered term as the report states it: the hypothesis in plain words, its estimate,
    95 % interval and unit, the gain it brings and the terms that would serve as well."""
    term = problem.terms[name]
    params = term.parameters
    sizes = "; ".join(
        f"{p.meaning} {values[p.name]:.3g} [{intervals[p.name][0]:.3g}, "
        f"{intervals[p.name][1]:.3g}]{'' if p.unit == '1' else ' ' + p.unit}"
        for p in params
    )
    statement = (
        f"Hypothesis for the lab to check: {term.description} ({sizes}; it removes "
        f"{gain['gain_pct']:.0f} % of the remaining held-out error)"
    )
    if alike:
        statement += "; " + " or ".join(problem.terms[a].description for a in alike)
        statement += " would explain the data as well"
    return {
        "term": name,
        "description": term.description,
        "observables": list(term.observables),
        "parameters": {p.name: values[p.name] for p in params},
        "units": {p.name: p.unit for p in params},
        "ci95": {p.name: intervals[p.name] for p in params},
        "neutral": {p.name: p.neutral for p in params},
        "gain": dict(gain),
        "alternatives": list(alike),
        "statement": statement + ".",
    }
