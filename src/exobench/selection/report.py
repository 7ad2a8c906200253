"""The discrepancy report: the selection, the estimates, the gain, the verdict and the cause,
with the same keys for every group."""

from __future__ import annotations

from collections.abc import Mapping, Sequence

import numpy as np

from exobench.selection.beside import located_sizes, supported
from exobench.selection.between import key, movable, settle
from exobench.selection.blocks import block_searches, named_blocks, remaining
from exobench.selection.discovery import (
    alternatives,
    discover,
    holding_either,
    known_beside,
    patterns,
    readings,
    swaps,
    term_entry,
)
from exobench.selection.intervals import earned, settled
from exobench.selection.model import Data, Problem, Settings, ordered
from exobench.selection.search import forward_selection, held_out, in_sample, one_se_rule
from exobench.selection.stability import stability
from exobench.selection.structure import verdict_of
from exobench.selection.summary import (
    between_trials,
    headline,
    pattern,
    short_name,
    term_statement,
    unit_text,
    unsized_text,
)
from exobench.selection.workers import worker_pool


def _joined(parts: Sequence[str]) -> str:
    return parts[0] if len(parts) == 1 else ", ".join(parts[:-1]) + " and " + parts[-1]


def observable_name(problem: Problem, obs: str) -> str:
    """An observable in words (its key where the group gives no name)."""
    return problem.names.get(obs, obs.replace("_", " "))


def rmse_change(problem: Problem, gain: Mapping) -> str:
    """'held-out knee moment RMSE 24.2 → 0.029 N·m': the error of the observable the extended
    model improves most (:func:`headline`), under the baseline and the extended model."""
    rows = [(observable_name(problem, obs), gain["baseline_rmse"][f"{obs}_{unit}"],
             gain["extended_rmse"][f"{obs}_{unit}"], unit)
            for obs, unit in ((o, problem.units[o]) for o in problem.measured)]  # fmt: skip
    name, before, after, unit = headline(rows)
    kind = "held-out " if gain["held_out"] else ""
    return f"{kind}{name} RMSE {before:.3g} → {after:.3g} {unit_text(unit)}"


def cause_sentence(problem: Problem, found: Sequence[str], tentative: Sequence[str],
                   gain: Mapping, verdict: Mapping, terms: Sequence[Mapping] = (),
                   searched: bool = False, weak: Sequence[Mapping] = (),
                   others: Sequence[Mapping] = (),
                   bases: Mapping[str, list] | None = None, tried: bool = True,
                   structure: bool | None = None) -> str:  # fmt: skip
    """What the baseline gets wrong and why (registry effects claimed, discovered terms named as
    hypotheses), and what is left unexplained, or which estimates the data cannot tell from a
    term (``others``: :func:`discovery.readings`); every sentence opens with the baseline's
    name as its subject and lists effects by their descriptions (noun phrases), the verbs
    agreeing with their number; the library is said to be searched only when it was
    (``searched``); a claim beside unexplained structure that rests on part of the evidence
    (``bases``: effect → the observables it was estimated from, none when a check of the
    recordings sized it) says so, and so does one no candidate term was tried against
    (``tried`` false); ``structure``: the registry's model left structure, which terms named on
    blocks of observables alone (``found_on``) may explain (default: the verdict's flag)."""
    subject = f"The {problem.baseline_name}"
    change = rmse_change(problem, gain)
    structure = verdict["flag"] if structure is None else structure
    if found:
        named = _joined([problem.registry[e].description for e in found])
        pronoun = "them" if len(found) > 1 else "it"
        held = held_clause(problem, found, bases or {}, tried) if structure else ""
        text = f"{subject} misses the data because of {named}{held}; with {pronoun}, {change}."
        if tentative:
            unclaimed = _joined([problem.registry[e].description for e in tentative])
            verb = "are" if len(tentative) > 1 else "is"
            text += f" {unclaimed[0].upper()}{unclaimed[1:]} {verb} fitted too but not claimed "
            text += ("while structure remains." if verdict["flag"]
                     else "beside the structure the registry left." if structure
                     else "as another reading explains the data as well.")  # fmt: skip
    elif terms and structure and not verdict["flag"]:
        text = f"{subject} misses the data by more than any registry effect explains."
    elif terms and not verdict["flag"]:
        text = (f"{subject} misses the data by more than any registry effect explains; with "
                f"the correction below, {change}.")  # fmt: skip
    elif not verdict["flag"] and tentative:  # each effect fitted has a reading as good
        named = _joined([problem.registry[e].description for e in tentative])
        verbs = ("improve", "are") if len(tentative) > 1 else ("improves", "is")
        text = (f"{subject} misses the data; {named} {verbs[0]} the fit ({change}) but "
                f"{verbs[1]} not claimed as another reading explains the data as "
                "well.")  # fmt: skip
    elif not verdict["flag"]:
        return f"none: the {problem.baseline_name} explains the data"
    elif tentative:
        named = _joined([problem.registry[e].description for e in tentative])
        verbs = ("improve", "are", "none of them explains") if len(tentative) > 1 else (
            "improves", "is", "it does not explain")  # fmt: skip
        text = (
            f"{subject} misses the data; {named} {verbs[0]} the fit ({change}) but {verbs[1]} "
            f"not claimed while structure remains that {verbs[2]}."
        )
    else:
        text = (
            f"No effect in the registry explains the data better than the {problem.baseline_name}."
        )
    library = {name: entry_spec(e) for name, e in problem.terms.items()}
    whole = [t for t in terms if "found_on" not in t] if not verdict["flag"] else []
    apart = [t for t in terms if "found_on" in t]  # named on a block of observables alone
    if whole or apart:
        text += " " + " ".join(term_statement(t, library) for t in [*whole, *apart])
    placed = [r for r in others if r.get("in_place_of")]
    if verdict["flag"]:
        text += " " + unexplained_sentence(problem, verdict, searched, weak)
        if placed:  # what a claim beside it cannot be told from
            text += " " + readings_sentence(problem, verdict, placed)
    elif others:
        text += " " + readings_sentence(problem, verdict, others)
    return text


def found_on(problem: Problem, entry: Mapping, observables: Sequence[str],
             library: Mapping) -> dict:  # fmt: skip
    """A term entry named on a block of observables alone (:mod:`exobench.selection.blocks`):
    the block (``found_on``) and, in words, why the misfit elsewhere does not touch it
    (``basis``), in its statement too (``library``: the report's term library)."""
    shown = _joined([observable_name(problem, o) for o in observables])
    basis = (f", found on the {shown} alone, which no registry effect or term joins to the "
             "other observables")  # fmt: skip
    term = {**entry, "found_on": list(observables), "basis": basis}
    return {**term, "statement": term_statement(term, library)}


def held_clause(problem: Problem, found: Sequence[str], bases: Mapping[str, list],
                tried: bool = True) -> str:  # fmt: skip
    """Why effects claimed beside unexplained structure are known: their estimates hold
    whichever candidate term is added (``tried``: any was), or (``bases``) they rest on part of
    the evidence."""
    holding = [e for e in found if e not in bases]
    if len(holding) == len(found) and not tried:
        return ", claimed beside the misfit with no candidate term to test them against"
    if len(holding) == len(found):
        return (", whose estimates hold whichever candidate term is added" if len(found) > 1
                else ", whose estimate holds whichever candidate term is added")  # fmt: skip
    if len(found) == 1:
        return f", {basis_phrase(problem, bases[found[0]])}"
    clauses = [f"{short_name(problem.registry[e].description)} {basis_phrase(problem, bases[e])}"
               for e in found if e in bases]  # fmt: skip
    if holding:
        verb = "hold" if len(holding) > 1 else "holds"
        named = _joined([short_name(problem.registry[e].description) for e in holding])
        clauses.insert(0, f"{named} {verb} whichever candidate term is added")
    return f" ({'; '.join(clauses)})"


def basis_phrase(problem: Problem, observables: Sequence[str]) -> str:
    """How a claim beside unexplained structure was sized: from which observables alone, or by
    the check of the recordings that located it."""
    if not observables:
        return "sized by the check of the recordings that located it, not by the misfitting model"
    return f"estimated from the {_joined([observable_name(problem, o) for o in observables])} alone"


def readings_sentence(problem: Problem, verdict: Mapping, others: Sequence[Mapping]) -> str:
    """Which claimed estimates the data cannot tell from a term (:func:`discovery.readings`),
    and what that term would account for: a pattern beyond the noise, or what a direct check
    of the recordings saw; and which effects a term explains as well in their place
    (:func:`discovery.swaps`)."""
    placed = [r for r in others if r.get("in_place_of")]
    text = " ".join(
        f"The data cannot tell {short_name(problem.registry[r['in_place_of']].description)} "
        f"from {short_name(r['description'])}, which explains them as well in its place: its "
        "interval holds either reading."
        for r in placed
    )
    others = [r for r in others if not r.get("in_place_of")]
    if not others:
        return text
    names = _joined(list(dict.fromkeys(p for r in others for p in r["moves"])))
    terms = " or ".join(short_name(r["description"]) for r in others)
    seen = _joined([f"the {observable_name(problem, t['observable'])} "
                    f"{pattern(t['correlates_with'])}" for t in patterns(verdict)])  # fmt: skip
    what = (f"a pattern beyond the noise that the residual tests find too small to count "
            f"({seen})" if seen else "what a direct check of the recordings sees")  # fmt: skip
    return (
        f"{text} The data cannot tell {names} from {terms}, which would account for {what}: "
        "their intervals hold either reading."
    ).strip()


def unexplained_sentence(problem: Problem, verdict: Mapping, searched: bool = False,
                         weak: Sequence[Mapping] = ()) -> str:  # fmt: skip
    """What is left unexplained, in words: which observable, against what, by how much, what
    was tried (the registry; the library of terms too when it was searched) and the closest
    candidate terms, with the share they remove, when none removes enough to be offered."""
    tried = "no registry effect or term of the library" if searched else "no registry effect"
    text = (
        f"Left unexplained: the held-out residual of the "
        f"{observable_name(problem, verdict['observable'])} {pattern(verdict['correlates_with'])} "
        f"(statistic "
        f"{verdict['statistic']:.3g} against a noise threshold of {verdict['threshold']:.3g}); "
        f"{tried} accounts for it"
    )
    if weak:
        closest = _joined([f"{short_name(w['description'])} removes {w['gain_pct']:.0f} %"
                           for w in weak])  # fmt: skip
        text += f" (the closest terms leave most of it: {closest})"
    return text + "."


def analyse(problem: Problem, data: Data, scales: Mapping[str, float], settings: Settings,
            source: str, suspects: Sequence[str] = ()) -> dict:  # fmt: skip
    """The discrepancy report: candidates, selection, effects with 95 % intervals, gain,
    unexplained structure and the cause, with the same keys for every group (``suspects``:
    library terms whose relaxation a direct check of the recordings saw, weighed as other
    readings of the claimed estimates, :func:`discovery.readings`)."""
    with worker_pool(problem, data, scales, settings.workers):
        return _report(problem, data, scales, settings, source, suspects)


def _report(problem: Problem, data: Data, scales, settings: Settings, source: str,
            suspects: Sequence[str] = ()) -> dict:  # fmt: skip
    """:func:`analyse` with its worker processes running."""
    few = data.units < settings.min_units_cv
    score = in_sample if few else held_out
    path, tried = forward_selection(problem, data, scales, settings, score, linear=True)
    chosen = min(path, key=lambda p: p["score"]) if few else one_se_rule(path)
    model = settled(problem, data, scales, settings, few, score, chosen)
    verdict = verdict_of(problem, data, model, scales, settings)
    # the registry's fullest model on its path and the whole registry (but effects seen only in
    # exact observables): candidates for comparing the trials in, where something is left
    fullest = {"effects": tuple(path[-1]["effects"]), "values": path[-1].get("values", {})}
    every = tuple(n for n, e in problem.registry.items() if set(e.observables) - set(problem.exact))
    fuller = [fullest, {**fullest, "effects": every}]
    early, moved = None, None
    if verdict["flag"] and not few and problem.per_unit:  # a constant moved between trials
        early = stability(problem, data, scales, settings, model, fuller, True)
        moved = settle(problem, data, scales, settings, score, model, early, fullest)
        if moved:
            problem, model, verdict = moved
    compared_in = model
    search, others, apart = None, [], []
    if verdict["flag"] and problem.terms and settings.max_terms > 0 and not few:
        # rooted at the registry's best on its path, or at the model refitted between trials
        best = None if moved else min(path, key=lambda p: p["cv"]["loss"].mean())
        search = discover(problem, data, scales, settings, model, path[0], best)
        if search["final"] is not None and not search["verdict"]["flag"]:  # terms or not
            model, verdict = search["final"], search["verdict"]
        else:  # each block of observables no entry joins to the others, alone
            apart = block_searches(problem, data, scales, settings, model, verdict)
    entries = effect_entries(problem, model)
    if not verdict["flag"] and not few:  # a pattern too small to count, a term in an effect's
        # place: other readings
        others = readings(problem, data, scales, settings, model, verdict, suspects)
        others += swaps(problem, data, scales, settings, model, unearned(problem, entries, others))
    effects = tuple(e for e in model["effects"] if e in problem.registry)
    chosen = model["chosen"]
    baseline = path[0]
    gain = {
        "held_out": not few,
        "baseline_loss": float(baseline["cv"]["loss"].mean()),
        "extended_loss": float(chosen["cv"]["loss"].mean()),
        "reduction_pct": 100.0
        * (1.0 - chosen["cv"]["loss"].mean() / baseline["cv"]["loss"].mean()),
        "baseline_rmse": rmse_by_observable(problem, baseline["cv"]["residuals"], scales),
        "extended_rmse": rmse_by_observable(problem, chosen["cv"]["residuals"], scales),
    }
    # an effect whose interval, holding every reading, reaches where it vanishes is not claimed
    either = holding_either(entries, others)
    claimed = [] if verdict["flag"] else [
        e for e in either if earned(problem.registry[e["effect"]], e["ci95"])
    ]  # fmt: skip
    extensions = search["registry_screen"]["survivors"] if search is not None else ()
    if verdict["flag"] and not few:  # what stays known beside the remainder
        beside = known_beside(problem, data, scales, settings, model, extensions, verdict)
        kept = [{**e, "ci95": beside[e["effect"]], "beside_unexplained": True}
                for e in entries if e["effect"] in beside]  # fmt: skip
        # what a term or another effect explains as well in its place is not known either
        others = swaps(problem, data, scales, settings, model) if kept else []
        claimed = [e for e in holding_either(kept, others)
                   if earned(problem.registry[e["effect"]], e["ci95"])]  # fmt: skip
        # what the observables that fit support, and a located effect's own size
        have = {e["effect"] for e in claimed}
        found = supported(problem, data, scales, settings, model, extensions, verdict)
        found.update(located_sizes(problem, data, settings))
        # an effect a term or another effect explains as well in its place stays unclaimed
        placed = {r["in_place_of"] for r in others if r.get("in_place_of")}
        claimed += [beside_entry(problem, name, got) for name, got in found.items()
                    if name not in have and name not in placed]  # fmt: skip
        either = [*claimed, *(e for e in holding_either(entries, others)
                              if e["effect"] not in {c["effect"] for c in claimed})]  # fmt: skip
    named = named_blocks(apart, settings.propose_share)
    discovered = discovery_report(problem, data, scales, settings, search, apart, named)
    left = remaining(verdict, named) if named else verdict
    for block in named:  # a named block's registry estimates: its own model's
        inside, have = set(block["problem"].registry), {c["effect"] for c in claimed}
        own = [e for e in effect_entries(block["problem"], block["search"]["final"])
               if e["effect"] not in have]  # fmt: skip
        either = [e for e in either if e["effect"] not in inside or e["effect"] in have] + own
        effects = (*(e for e in effects if e not in inside or e in have),
                   *(e["effect"] for e in own))  # fmt: skip
    # the trials compared where the constants moved (as found), else in the final model
    if moved:  # a constant whose shifts the final model holds is refitted, not left
        stable = {**early, "constants": [{**e, "refitted": key(e) in effects} if movable(problem, e)
                                         else e for e in early["constants"]]}  # fmt: skip
    elif early is not None and model is compared_in and verdict["flag"]:
        stable = early
    else:
        stable = stability(problem, data, scales, settings, model, fuller, verdict["flag"])
    cause = cause_sentence(
        problem,
        [e["effect"] for e in claimed],
        [e for e in effects if e not in {c["effect"] for c in claimed}],
        gain,
        left,
        discovered["named"],
        discovered["searched"],
        discovered.get("not_offered", ()),
        others,
        {e["effect"]: e["from_observables"] for e in claimed if "from_observables" in e},
        bool(extensions),
        verdict["flag"],
    )
    if stable["flag"]:  # a constant that differs between trials is left unexplained too
        if cause.startswith("none:"):
            cause = (
                f"The {problem.baseline_name} explains the data within each trial, but not "
                "with one value of each constant of the rig."
            )
        cause += " " + between_trials(stable)
    if unsized_text(stable):  # a trial that cannot size a constant says so
        cause += " " + unsized_text(stable)
    return {
        "group": problem.group,
        "source": source,
        "baseline": {"model": problem.baseline_name, "loss": gain["baseline_loss"]},
        "observables": {o: problem.units[o] for o in problem.measured},
        "observable_names": {o: observable_name(problem, o) for o in problem.measured},
        "observable_order": list(problem.measured),
        "noise_scales": {f"{o}_{problem.units[o]}": float(scales[o]) for o in problem.measured},
        "registry": {name: entry_spec(e) for name, e in problem.registry.items()},
        "candidates": [
            {
                "effects": list(ordered(problem, t["effects"])),
                "loss": float(t["cv"]["loss"].mean()),
                "loss_se": float(np.std(t["cv"]["loss"], ddof=1) / np.sqrt(data.units)),
                "score": t["score"],
            }
            for t in tried
        ],
        "forward_path": [list(ordered(problem, p["effects"])) for p in path],
        "selection": (
            "forward selection on AIC of full-data fits (too few units to hold any out)"
            if few
            else f"forward selection on held-out loss ({settings.folds} contiguous unit blocks "
            "per trial), then the fewest effects within one paired standard error of the best"
        )
        + "; an effect whose 95 % interval reaches the value where it vanishes (or a fit bound)"
        " is dropped and the rest refitted",
        "selected": list(effects),
        "dropped": model["dropped"],
        "intervals": f"{model['method']}; widened by √(1 + B²) = {model['widening']:.2f}, B "
        "the misfit of the mean residual curve per trial in its own standard errors (the bias "
        "a model-form error of that size leaves, added in quadrature)",
        "effects_found": claimed,
        "tentative": [e for e in either if e["effect"] not in {c["effect"] for c in claimed}],
        "discovery": discovered,
        "readings": others,
        "gain": gain,
        "unexplained": left,
        "stability": stable,
        "cause": cause,
    }


def unearned(problem: Problem, entries: list[dict], found: Sequence[Mapping]) -> set[str]:
    """The registry effects (report ``entries``, :func:`effect_entries`) whose intervals, holding
    the readings ``found`` (:func:`discovery.holding_either`), no longer earn them."""
    return {e["effect"] for e in holding_either(entries, list(found))
            if not earned(problem.registry[e["effect"]], e["ci95"])}  # fmt: skip


def effect_entries(problem: Problem, model: Mapping) -> list[dict]:
    """The registry effects of a settled model as the report lists them: description,
    observables, estimates, units and 95 % intervals."""
    return [
        registry_entry(problem, name, model["values"], model["intervals"])
        for name in model["effects"]
        if name in problem.registry
    ]  # the model's order


def registry_entry(problem: Problem, name: str, values: Mapping, intervals: Mapping) -> dict:
    """A registry effect as the report lists it: description, observables, its parameters'
    estimates (of ``values``), units and 95 % intervals (of ``intervals``)."""
    effect = problem.registry[name]
    return {
        "effect": name,
        "description": effect.description,
        "observables": list(effect.observables),
        "parameters": {p.name: values[p.name] for p in effect.parameters},
        "units": {p.name: p.unit for p in effect.parameters},
        "ci95": {p.name: intervals[p.name] for p in effect.parameters},
        **({"alternatives": list(effect.alternatives)} if effect.alternatives else {}),
    }


def beside_entry(problem: Problem, name: str, got: Mapping) -> dict:
    """A registry effect claimed beside unexplained structure from part of the evidence
    (:func:`beside.supported`, :func:`beside.located_sizes`), as the report lists it: the
    observables it rests on (none: sized by a check of the recordings before any fit)."""
    return {**registry_entry(problem, name, got["parameters"], got["ci95"]),
            "beside_unexplained": True,
            "from_observables": list(got["from_observables"])}  # fmt: skip


def entry_spec(effect) -> dict:
    """A registry effect or library term as the report lists it."""
    return {
        "description": effect.description,
        "observables": list(effect.observables),
        "requires": list(effect.requires),
        "parameters": [
            {"name": p.name, "unit": p.unit, "bounds": [p.low, p.high], "meaning": p.meaning}
            for p in effect.parameters
        ],
    }


def discovery_report(problem: Problem, data: Data, scales, settings: Settings, search,
                     found: Sequence[Mapping] = (),
                     named: Sequence[Mapping] = ()) -> dict:  # fmt: skip
    """The discovered-terms part of the report: whether the library was searched, the path,
    the named terms (with estimate, interval, gain and the terms that serve as well) and the
    terms proposed but not named (the combined model still leaves structure unexplained); the
    block searches (``found``, :func:`blocks.block_searches`) and the terms of those whose
    terms are named (``named``, :func:`blocks.named_blocks`), each with its block's
    observables."""
    out = {
        "library": {name: entry_spec(e) for name, e in problem.terms.items()},
        "searched": search is not None,
        "named": [],
        "proposed": [],
    }
    if search is None:
        return out
    out["root"] = search["root"]
    out["screened"] = search["screen"]["order"]
    out["forward_path"] = search["forward_path"]
    out["reselected_path"] = search.get("reselected_path", [])
    if search["final"] is not None:
        listed = kept_entries(problem, data, scales, settings, search)
        if search["named"]:
            out["named"] = listed
        else:  # structure remains: a term is offered only when it removes a large share of it
            offered = settings.propose_share * 100.0
            out["proposed"] = [e for e in listed if e["gain"]["gain_pct"] >= offered]
            out["not_offered"] = [{"term": e["term"], "description": e["description"],
                                   "gain_pct": e["gain"]["gain_pct"]}
                                  for e in listed if e["gain"]["gain_pct"] < offered]  # fmt: skip
        if search["verdict"]["flag"]:
            out["verdict_with_terms"] = {
                k: search["verdict"][k]
                for k in ("observable", "correlates_with", "statistic", "threshold")
            }
    for block in named:
        entries = kept_entries(block["problem"], data, scales, settings, block["search"])
        out["named"] += [found_on(problem, e, block["observables"], out["library"])
                         for e in entries]  # fmt: skip
    if found:
        terms = {e["term"] for e in out["named"]}
        out["proposed"] = [e for e in out["proposed"] if e["term"] not in terms]
        if "not_offered" in out:
            out["not_offered"] = [e for e in out["not_offered"] if e["term"] not in terms]
        out["blocks"] = [{"observables": list(b["observables"]), "root": b["search"]["root"],
                          "forward_path": b["search"]["forward_path"],
                          "named": list(b["search"]["named"])} for b in found]  # fmt: skip
    return out


def kept_entries(problem: Problem, data: Data, scales, settings: Settings, search) -> list:
    """The terms a search's final model keeps, each with estimate, interval, gain and the terms
    that serve as well (:func:`discovery.alternatives`)."""
    final, gains = search["final"], search["gains"]
    alike = alternatives(problem, data, scales, settings, final, gains,
                         search["screen"]["directions"])  # fmt: skip
    return [term_entry(problem, name, final["values"], final["intervals"], gains[name],
                       alike.get(name, []))
            for name in search["kept"]]  # fmt: skip


def rmse_by_observable(problem: Problem, held: Mapping[str, np.ndarray], scales) -> dict:
    """Held-out RMS error of every observable in its own unit (key carries the unit)."""
    return {
        f"{obs}_{problem.units[obs]}": float(np.sqrt(np.nanmean(r**2)) * scales[obs])
        for obs, r in held.items()
    }
