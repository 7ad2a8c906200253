"""Claims per observable: what the observables that fit support while another one misfits.

One observable's misfit (a controller that engages at other moments than its table, a motor and
cable that deliver the desired torque their own way) biases the joint fit, so the others misfit
beside it. The observable of the largest flagged structure is left out, and again, until the
settled model's registry effects, refitted on the observables left, leave nothing flagged on
them; those effects are claimed when their estimates hold whichever candidate term is added,
agree with the joint model's, and their intervals earn them. A count drop the session QC
located and sized on the encoder's own jump is claimed with that size whatever the fit says
(:func:`located_sizes`).
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import replace

import numpy as np

from exobench.selection.discovery import misfit_factor
from exobench.selection.fitting import fit
from exobench.selection.intervals import earned, settled, widened
from exobench.selection.model import Data, Problem, Settings
from exobench.selection.search import held_out
from exobench.selection.structure import verdict_of


def restricted(problem: Problem, observables) -> Problem:
    """The problem with only ``observables`` measured: fits and tests see nothing else (an
    observable sized by one left out is sized by its own spread)."""
    keep = [o for o in problem.measured if o in observables]
    return replace(problem, measured={o: problem.measured[o] for o in keep},
                   exact=tuple(o for o in problem.exact if o in keep),
                   sized_by={o: t for o, t in problem.sized_by.items()
                             if o in keep and t in keep})  # fmt: skip


def worst_misfit(verdict: Mapping) -> str | None:
    """The observable whose flagged residual tests exceed their thresholds most (statistic over
    threshold: noise-unit and resolution-unit tests alike)."""
    ratios: dict[str, float] = {}
    for t in (t for t in verdict["tests"] if t["flag"]):
        ratio = float(t["statistic"]) / max(float(t["threshold"]), 1e-300)
        ratios[t["observable"]] = max(ratios.get(t["observable"], 0.0), ratio)
    return max(ratios, key=ratios.get) if ratios else None


def supported(problem: Problem, data: Data, scales, settings: Settings, model: Mapping,
              extensions, verdict: Mapping) -> dict[str, dict]:  # fmt: skip
    """Effect → estimates, 95 % intervals and the observables they rest on, for the settled
    ``model``'s registry effects the observables that fit support: the observable of the largest
    flagged structure (:func:`worst_misfit`) left out in turn (a misfit biases the joint fit, so
    that the others misfit too) and the model of the effects that show in the rest refitted and
    settled on them alone (held-out selection and intervals as the engine's, :func:`settled`),
    until its own verdict on them flags nothing; kept when every estimate stays inside its
    interval with each candidate term of ``extensions`` added (refitted on the same
    observables) and inside the joint model's interval stretched by the misfit it leaves in the
    observables the effect shows in (:func:`misfit_factor`: the two fits agree), a located one
    whatever they give; only effects the intervals earn (none when no observable is left)."""
    kept, current = list(problem.measured), verdict
    while current["flag"]:
        kept.remove(worst_misfit(current))
        shown = [e for e in model["effects"] if e in problem.registry
                 and set(problem.registry[e].observables) & set(kept)]  # fmt: skip
        if not kept or not shown:
            return {}
        part = restricted(problem, kept)
        chosen = held_out(part, data, [tuple(shown)], scales, settings)[0]
        settled_part = settled(part, data, scales, settings, False, held_out, chosen)
        current = verdict_of(part, data, settled_part, scales, settings)
    if current is verdict:
        return {}
    effects, values = tuple(settled_part["effects"]), settled_part["values"]
    intervals = settled_part["intervals"]
    extra = [t for t in extensions if all(r in effects for r in problem.entries[t].requires)
             and set(problem.entries[t].observables) & set(kept)]  # fmt: skip
    refits = [fit(part, data, (*effects, t), scales, values)[0] for t in extra]
    out = {}
    for name in (e for e in effects if e in problem.registry):
        effect = problem.registry[name]
        names = [p.name for p in effect.parameters]
        holds = all(intervals[n][0] <= f[n] <= intervals[n][1] for f in refits for n in names)
        joint = widened(problem, (name,), model["values"], model["intervals"],
                        misfit_factor(verdict, effect.observables))  # fmt: skip
        holds &= all(joint[n][0] <= values[n] <= joint[n][1] for n in names)
        if (holds or name in problem.located) and earned(effect, intervals):
            out[name] = {"parameters": {n: values[n] for n in names},
                         "ci95": {n: intervals[n] for n in names},
                         "from_observables": list(kept)}  # fmt: skip
    return out


def located_sizes(problem: Problem, data: Data, settings: Settings) -> dict[str, dict]:
    """Effect → estimate and 95 % interval of each located effect the group sized before any fit
    (``data.constants['located']``: effect → parameter → the sizes found, one per location, and
    the resolution of one), from those sizes alone: their median, the interval their range ±
    ``located_steps`` resolution steps; none when the sizes spread wider than that about their
    median (drops of different sizes are not one size)."""
    out = {}
    for name, sizes in (data.constants.get("located") or {}).items():
        if name not in problem.located:
            continue
        parameters, ci = {}, {}
        for parameter, found in sizes.items():
            values = np.asarray(found["values"], float)
            half = settings.located_steps * float(found["resolution"])
            centre = float(np.median(values)) if values.size else np.nan
            if not values.size or np.max(np.abs(values - centre)) > half:
                break
            parameters[parameter] = centre
            ci[parameter] = [float(values.min() - half), float(values.max() + half)]
        else:
            if parameters and earned(problem.registry[name], ci):
                out[name] = {"parameters": parameters, "ci95": ci, "from_observables": []}
    return out
