"""Which effects the data earn: blocked cross-validation, screening, forward selection and the
one-standard-error rule."""

from __future__ import annotations

from collections.abc import Mapping, Sequence

import numpy as np

from exobench.selection.fitting import fit, stacked
from exobench.selection.model import Data, Problem, Settings, parameters, residuals, unit_loss
from exobench.selection.workers import mapped


def block_folds(data: Data, count: int) -> np.ndarray:
    """Fold of every unit: ``count`` contiguous blocks of units within each trial."""
    fold = np.zeros(data.units, int)
    for trial in np.unique(data.trial):
        rows = np.flatnonzero(data.trial == trial)
        rows = rows[np.argsort(data.order[rows], kind="stable")]
        fold[rows] = np.arange(rows.size) * count // rows.size
    return fold


def _held_task(problem, data, scales, effects, start, train, test) -> tuple[dict, dict]:
    """Parameters fitted to the training units (from ``start``), held-out residuals of the test
    units."""
    values, _ = fit(problem, data.take(train), effects, scales, start)
    return values, residuals(problem, data.take(test), effects, values, scales)


def cross_validate(problem, data, candidates, scales, count: int) -> list[dict]:
    """Held-out loss of every unit and held-out residuals of each (effects, fold starts)
    candidate, parameters fitted per fold (from the start given for that fold, values fitted to
    its training units); every candidate's every fold is one task for the workers."""
    fold = block_folds(data, count)
    used = [k for k in range(count) if np.any(fold == k)]
    folds = [np.flatnonzero(fold == k) for k in used]
    calls = [
        (effects, starts[k] if starts else None, np.flatnonzero(fold != used[k]), folds[k])
        for effects, starts in candidates
        for k in range(len(folds))
    ]
    fitted = mapped(_held_task, calls, problem, data, scales)
    out = []
    for c in range(len(candidates)):
        loss = np.zeros(data.units)
        held: dict[str, np.ndarray] = {}
        own = fitted[c * len(folds) : (c + 1) * len(folds)]
        for test, (_, res) in zip(folds, own, strict=True):
            loss[test] = unit_loss(res)
            for obs, r in res.items():
                held.setdefault(obs, np.full((data.units, *r.shape[1:]), np.nan))[test] = r
        out.append({"loss": loss, "residuals": held, "fold_values": [v for v, _ in own]})
    return out


def paired_se(a: np.ndarray, b: np.ndarray) -> float:
    """Standard error of the mean of paired per-unit differences a − b."""
    d = a - b
    return float(np.std(d, ddof=1) / np.sqrt(d.size)) if d.size > 1 else float("inf")


def held_out(problem, data, candidates, scales, settings: Settings, parent=None) -> list[dict]:
    """Per-unit held-out loss and residuals of each candidate (blocked cross-validation; each
    fold's fit starts from the ``parent`` candidate's fit to the same fold)."""
    starts = parent["cv"].get("fold_values") if parent else None
    cvs = cross_validate(problem, data, [(e, starts) for e in candidates], scales, settings.folds)
    return [{"effects": e, "cv": cv, "score": float(cv["loss"].mean())}
            for e, cv in zip(candidates, cvs, strict=True)]  # fmt: skip


def _aic_task(problem, data, scales, effects, start) -> dict:
    """Full-data fit of a candidate (from ``start``) scored by AIC with the noise scales known:
    Σr² + 2p."""
    values, _ = fit(problem, data, effects, scales, start)
    res = residuals(problem, data, effects, values, scales)
    squares = sum(float(np.nansum(r**2)) for r in res.values())
    cv = {"loss": unit_loss(res), "residuals": res}
    return {"effects": effects, "cv": cv, "score": squares + 2 * len(values), "values": values}


def in_sample(problem, data, candidates, scales, settings: Settings, parent=None) -> list[dict]:
    """Each candidate's full-data fit (from the ``parent`` candidate's) scored by AIC."""
    start = parent.get("values") if parent else None
    return mapped(_aic_task, [(e, start) for e in candidates], problem, data, scales)


def _screen_task(problem, data, scales, effects, start) -> tuple[float, dict]:
    """Mean per-unit loss of a candidate's full-data fit (from ``start``), and the fit."""
    values, _ = fit(problem, data, effects, scales, start)
    return float(unit_loss(residuals(problem, data, effects, values, scales)).mean()), values


def probe_value(parameter) -> float:
    """Where a parameter is probed for its first-order change: its start value, or, where that
    is the value at which its effect vanishes, the smallest size a recording can see (else a
    thousandth of its fit range)."""
    start = parameter.initial()
    if start != parameter.neutral:
        return start
    step = float(parameter.detectable[0] - parameter.neutral)
    return parameter.neutral + (step if step else 1e-3 * (parameter.high - parameter.low))


def _probe_task(problem, data, scales, effects, start) -> np.ndarray:
    """A candidate's stacked residuals with its new parameters at :func:`probe_value` and the
    rest at ``start`` (one forward evaluation, no fit)."""
    values = {p.name: probe_value(p) for p in parameters(problem, effects)} | dict(start)
    return stacked(residuals(problem, data, effects, values, scales), fixed=True)


def linear_order(problem, data, current, options: Mapping[str, tuple[str, ...]], scales,
                 start: Mapping[str, float] | None) -> list[str]:  # fmt: skip
    """Options by the share of the current model's residual their first-order change explains
    (the squared projection of the residual on each option's change, one evaluation each)."""
    start = dict(start or {})
    base = _probe_task(problem, data, scales, tuple(current), start)
    calls = [((*current, *options[name]), start) for name in options]
    moved = mapped(_probe_task, calls, problem, data, scales)
    gains = []
    for change in (m - base for m in moved):
        size = float(change @ change)
        gains.append((float(change @ base) ** 2 / size) if size > 0 else 0.0)
    return [name for _, name in sorted(zip(gains, options, strict=True), key=lambda g: -g[0])]


def screened(problem, data, current, options: Mapping[str, tuple[str, ...]], scales, keep: int,
             start: Mapping[str, float] | None = None,
             linear: bool = False) -> dict[str, dict]:  # fmt: skip
    """The ``keep`` single additions (option -> the effects it adds) whose full-data fits (from
    ``start``, the current model's fit) lower the loss most, and the best addition of several
    effects at once (cheap screening before the held-out scoring; a bundle, which never fits
    worse than its parts, does not crowd single effects out), with their fits (every addition,
    in registry order, when there are no more than ``keep``); ``linear``: the options ranked
    first by their linearised change (:func:`linear_order`), and only the first ``keep`` singles
    and the first bundle fitted."""
    names = list(options)
    if linear and len(names) > keep:
        order = linear_order(problem, data, current, options, scales, start)
        names = ([n for n in order if len(options[n]) == 1][:keep]
                 + [n for n in order if len(options[n]) > 1][:1])  # fmt: skip
        keep = len(names)
    calls = [((*current, *options[name]), start) for name in names]
    fits = mapped(_screen_task, calls, problem, data, scales)
    if len(names) <= keep:
        return {name: values for name, (_, values) in zip(names, fits, strict=True)}
    order = np.argsort([f[0] for f in fits], kind="stable")
    singles = [i for i in order if len(options[names[i]]) == 1][:keep]
    bundles = [i for i in order if len(options[names[i]]) > 1][:1]
    return {names[i]: fits[i][1] for i in sorted(singles + bundles, key=list(order).index)}


def additions(problem: Problem, current: Sequence[str], pool: Sequence[str]) -> dict:
    """What each option adds to the current model: itself, with the effects it requires that
    the model lacks (an effect that only exists on top of another, such as a stiffening or a
    damping of the interface, enters together with it: alone, the other may fit so poorly that
    the search never takes it)."""
    out = {}
    for name in pool:
        needed = [r for r in problem.entries[name].requires if r not in current]
        if name not in current and all(r in pool for r in needed):
            out[name] = (*needed, name)
    return out


def forward_selection(problem: Problem, data: Data, scales, settings: Settings, score,
                      options: Sequence[str] | None = None, root: dict | None = None,
                      limit: int | None = None, linear: bool = False):  # fmt: skip
    """Candidates on the forward path: from the ``root`` model (scored; default the baseline),
    add the option (default: every registry effect; with what it requires, :func:`additions`)
    that lowers the score most, while any does and at most ``limit`` steps (default
    ``max_effects``); every fit starts from the current model's (``linear``: the options
    screened by their linearised change, :func:`screened`). Returns the path and every
    candidate tried."""
    path = [root] if root else score(problem, data, [()], scales, settings)
    tried = [path[0]]
    current: tuple[str, ...] = tuple(path[0]["effects"])
    pool = list(problem.registry) if options is None else list(options)
    for _ in range(settings.max_effects if limit is None else limit):
        options_now = additions(problem, current, pool)
        fits = screened(problem, data, current, options_now, scales, settings.screen,
                        path[-1].get("values"), linear)  # fmt: skip
        scored = score(problem, data, [(*current, *options_now[e]) for e in fits], scales,
                       settings, path[-1])  # fmt: skip
        trials = [{"values": v, **t} for v, t in zip(fits.values(), scored, strict=True)]
        tried.extend(trials)
        if not trials:
            break
        best = min(trials, key=lambda t: t["score"])
        if best["score"] >= path[-1]["score"]:
            break
        path.append(best)
        current = best["effects"]
    return path, tried


def one_se_rule(path: Sequence[dict]) -> dict:
    """The fewest effects whose held-out loss is within one paired standard error of the best."""
    best = min(path, key=lambda p: p["cv"]["loss"].mean())
    for entry in path:
        gap = entry["cv"]["loss"].mean() - best["cv"]["loss"].mean()
        if gap <= paired_se(entry["cv"]["loss"], best["cv"]["loss"]):
            return entry
    return best
