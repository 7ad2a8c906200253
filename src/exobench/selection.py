"""One model-selection engine for every rule group: which physical effects the data earn.

A group supplies a :class:`Problem`: its effect registry (each :class:`Effect` a forward
transformation of the baseline prediction), the baseline, the measured observables and the
noise-only samples of its own data. The engine does the rest, the same way everywhere:
- least-squares fits of a candidate's parameters (log or linear scale, bounded);
- blocked cross-validation: contiguous blocks of units (strides, steps) within every trial,
  every parameter fitted on the training blocks only;
- forward selection (tractable as the registry grows: at most n·(n+1)/2 candidates) and the
  one-standard-error rule on the paired held-out losses;
- block bootstrap over units, each resample refitted by one Gauss–Newton step from the full-data
  fit, for 95 % percentile intervals (Wald intervals from the Jacobian when there are too few
  units to resample);
- an "unexplained structure" verdict on the held-out residuals of the selected model;
- one report with the same keys for every group.
"""

from __future__ import annotations

import gc
import multiprocessing
from collections.abc import Callable, Mapping, Sequence
from contextlib import contextmanager
from dataclasses import dataclass, field

import numpy as np
from scipy.optimize import least_squares
from scipy.stats import norm
from scipy.stats import t as student


@dataclass(frozen=True)
class Parameter:
    """A fitted constant: name with unit suffix, unit, bounds, physical meaning, fit scale;
    ``resolution`` the finest step in which the data can show it (a 95 % interval is never
    narrower than ± half of it); ``shape`` for a parameter at whose neutral value the effect
    does not vanish (a settling time: a cuff without lag is still compliant), which therefore
    does not decide whether the data earn the effect."""

    name: str
    unit: str
    low: float
    high: float
    meaning: str
    log: bool = True
    start: float | None = None
    neutral: float = 0.0
    detectable: tuple[float, float] = (0.0, 0.0)
    negligible: float | None = None
    resolution: float = 0.0
    shape: bool = False

    def strength(self, value):
        """Size of the effect at a value: distance from the neutral value (its inverse for a
        stiffness, whose neutral value is infinite)."""
        value = np.asarray(value, float)
        return 1.0 / value if np.isinf(self.neutral) else np.abs(value - self.neutral)

    def value_at(self, strength: float, sign: float = 1.0) -> float:
        """The parameter value of an effect of a given size (and sign, where it has one)."""
        if np.isinf(self.neutral):
            return 1.0 / strength
        return float(self.neutral + sign * strength)

    def initial(self) -> float:
        """Start value: the given one, else the geometric (log) or arithmetic middle."""
        if self.start is not None:
            return self.start
        return float(np.sqrt(self.low * self.high)) if self.log else 0.5 * (self.low + self.high)


@dataclass(frozen=True)
class Effect:
    """One registry entry: a physical effect and its forward transformation of a prediction.

    ``transform(state, values, data)`` returns the state (a dict of arrays) with the effect
    applied; ``values`` holds every parameter of the candidate. ``observables`` says where it
    shows; ``requires`` names effects it only makes sense on top of.
    """

    name: str
    description: str
    parameters: tuple[Parameter, ...]
    observables: tuple[str, ...]
    transform: Callable[[dict, Mapping[str, float], Data], dict]
    requires: tuple[str, ...] = ()


@dataclass(frozen=True)
class Data:
    """Observations of one group: every array's first axis is a unit (stride or step)."""

    arrays: Mapping[str, np.ndarray]
    trial: np.ndarray
    order: np.ndarray
    constants: Mapping[str, object] = field(default_factory=dict)

    @property
    def units(self) -> int:
        return int(self.trial.size)

    def take(self, rows: np.ndarray) -> Data:
        """The observations of a subset of units (in the given order; rows may repeat)."""
        return Data(
            {k: v[rows] for k, v in self.arrays.items()},
            self.trial[rows],
            self.order[rows],
            self.constants,
        )


@dataclass(frozen=True)
class Problem:
    """What a rule group supplies to the engine.

    - ``registry``: effects in the order their transformations apply;
    - ``baseline(data)``: the state of the baseline model (must hold every observable);
    - ``measured``: observable -> name of its measured array in ``data.arrays``; an array named
      ``mask_<observable>`` (bool), where present, selects the samples that count;
    - ``scales``: observable -> noise scale (its unit) that normalises residuals;
    - ``features(data)``: name -> array like the observables, for the residual-structure tests;
    - ``noise(data)``: observable -> (noise-only residuals, their features), the null;
    - ``units``: observable -> unit string; ``baseline_name``: the baseline in words;
    - ``recorded(state, data)``: the observables as the recording and its processing make them
      of the predicted state (e.g. the analysis chain's filter), after every transformation;
    - ``relative``: observables measured as changes since the first counted sample (their
      noise-only windows are referenced the same way);
    - ``exact``: observables the recording determines without noise (a controller's own
      output), their scale the recording's resolution: no noise-only null, their held-out RMS
      is tested against the goodness-of-fit floor, and they do not enter the model-form ratio B.
    """

    group: str
    registry: Mapping[str, Effect]
    baseline: Callable[[Data], dict]
    measured: Mapping[str, str]
    units: Mapping[str, str]
    baseline_name: str
    features: Callable[[Data], dict] | None = None
    noise: Callable[[Data], dict] | None = None
    recorded: Callable[[dict, Data], dict] | None = None
    relative: tuple[str, ...] = ()
    exact: tuple[str, ...] = ()


@dataclass(frozen=True)
class Settings:
    """Engine settings: folds, bootstrap draws, seed, the most effects a model may add, the
    goodness-of-fit floor (held-out RMS residual in noise units) and the structure test's
    false-alarm level; ``workers`` processes share independent fits (same results for any
    number)."""

    folds: int = 5
    bootstrap: int = 200
    seed: int = 0
    max_effects: int = 4
    screen: int = 3
    fit_floor: float = 3.0
    min_share: float = 0.02
    alpha: float = 0.01
    null_draws: int = 400
    min_units_cv: int = 10
    workers: int = 1

    @classmethod
    def from_config(cls, block: Mapping, seed: int) -> Settings:
        """Settings from a config block (keys as the fields), with the workflow seed."""
        known = {k: block[k] for k in cls.__dataclass_fields__ if k in block and k != "seed"}
        return cls(seed=int(seed), **known)


def parameters(problem: Problem, effects: Sequence[str]) -> list[Parameter]:
    """Every parameter of a candidate, in registry order."""
    return [p for name in ordered(problem, effects) for p in problem.registry[name].parameters]


def ordered(problem: Problem, effects: Sequence[str]) -> list[str]:
    """The effects of a candidate in the registry's order of transformation."""
    return [name for name in problem.registry if name in effects]


def predict(problem: Problem, data: Data, effects: Sequence[str], values) -> dict:
    """Observables of a candidate: the baseline state transformed by each effect in turn."""
    state = problem.baseline(data)
    for name in ordered(problem, effects):
        state = problem.registry[name].transform(state, values, data)
    if problem.recorded:
        return problem.recorded(state, data)
    return {o: state[o] for o in problem.measured}


def residuals(problem: Problem, data: Data, effects, values, scales) -> dict[str, np.ndarray]:
    """Prediction − measurement of every observable in noise units, NaN where masked out."""
    pred = predict(problem, data, effects, values)
    out = {}
    for obs, name in problem.measured.items():
        r = (pred[obs] - data.arrays[name]) / scales[obs]
        mask = data.arrays.get(f"mask_{obs}")
        out[obs] = np.where(mask, r, np.nan) if mask is not None else r
    return out


def unit_loss(res: Mapping[str, np.ndarray]) -> np.ndarray:
    """Per-unit loss: mean over observables of each one's mean squared normalised residual."""
    per = []
    for r in res.values():
        flat = r.reshape(r.shape[0], -1)
        per.append(np.nanmean(flat**2, axis=1) if flat.shape[1] else np.zeros(flat.shape[0]))
    return np.nanmean(np.vstack(per), axis=0)


def observable_weight(counted):
    """Weight 1/n of an observable's squared residuals, n its counted samples (at least 1): every
    observable counts equally in the least-squares loss."""
    return 1.0 / np.maximum(counted, 1.0)


def _stack(res: Mapping[str, np.ndarray]) -> np.ndarray:
    """Residual vector of the least-squares fit: each observable's residuals times √(its
    :func:`observable_weight`)."""
    parts = []
    for r in res.values():
        flat = r[np.isfinite(r)]
        parts.append(flat * np.sqrt(observable_weight(flat.size)))
    return np.concatenate(parts)


def _to_values(params: Sequence[Parameter], x: np.ndarray) -> dict[str, float]:
    return {p.name: float(np.exp(v) if p.log else v) for p, v in zip(params, x, strict=True)}


def _to_x(params: Sequence[Parameter], values: Mapping[str, float]) -> np.ndarray:
    x = [np.log(values[p.name]) if p.log else values[p.name] for p in params]
    return np.array(x, float)


def _bounds(params: Sequence[Parameter]) -> tuple[np.ndarray, np.ndarray]:
    """Lower and upper fit bounds of the scaled parameters."""
    low = np.array([np.log(p.low) if p.log else p.low for p in params])
    high = np.array([np.log(p.high) if p.log else p.high for p in params])
    return low, high


def fit(problem, data, effects, scales, start: Mapping[str, float] | None = None):
    """Least-squares parameters of a candidate and the fit's Jacobian (scaled parameters)."""
    params = parameters(problem, effects)
    if not params:
        return {}, np.zeros((0, 0))
    low, high = _bounds(params)
    guess = {p.name: p.initial() for p in params}
    if start:
        guess.update({k: v for k, v in start.items() if k in guess})
    x0 = np.clip(_to_x(params, guess), low + 1e-9 * (high - low), high - 1e-9 * (high - low))

    def objective(x):
        return _stack(residuals(problem, data, effects, _to_values(params, x), scales))

    result = least_squares(
        objective, x0, bounds=(low, high), x_scale="jac", ftol=1e-6, xtol=1e-6, max_nfev=100
    )
    return _to_values(params, result.x), result.jac


# The analysis whose worker processes are running: ((problem, data, scales), pool). Workers are
# forked once per analysis with it in memory, so a task carries only its arguments (effects,
# start values, unit indices) and its result, and each worker pays its first-task copy-on-write
# faults (about 0.3 s) once rather than at every parallel step.
_ANALYSIS: list[tuple] = []


@contextmanager
def worker_pool(problem, data, scales, workers: int):
    """Worker processes for one analysis (``workers`` ≤ 1: none, tasks run in this process);
    one analysis at a time (not nested: a nested pool would unfreeze the collector early)."""
    if workers <= 1:
        yield
        return
    _ANALYSIS.append(((problem, data, scales), None))
    gc.freeze()  # the workers' garbage collections skip the inherited heap
    try:
        with multiprocessing.get_context("fork").Pool(workers) as pool:
            _ANALYSIS[-1] = (_ANALYSIS[-1][0], pool)
            yield
    finally:
        gc.unfreeze()
        _ANALYSIS.pop()


def _in_worker(task: Callable, args: tuple):
    return task(*_ANALYSIS[-1][0], *args)


def mapped(task: Callable, calls: Sequence[tuple], problem, data, scales) -> list:
    """[task(problem, data, scales, *args) for args in calls], shared among the analysis's
    worker processes when it has them (the same results either way)."""
    if _ANALYSIS and len(calls) > 1:
        (p, d, s), pool = _ANALYSIS[-1]
        if pool is not None and p is problem and d is data and s is scales:
            return pool.starmap(_in_worker, [(task, args) for args in calls], chunksize=1)
    return [task(problem, data, scales, *args) for args in calls]


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


def screened(problem, data, current, options, scales, keep: int,
             start: Mapping[str, float] | None = None) -> dict[str, dict]:  # fmt: skip
    """The ``keep`` additions whose full-data fits (from ``start``, the current model's fit)
    lower the loss most (cheap screening before the held-out scoring), with those fits (every
    addition, in registry order, when there are no more than ``keep``)."""
    calls = [((*current, option), start) for option in options]
    fits = mapped(_screen_task, calls, problem, data, scales)
    if len(options) <= keep:
        return {option: values for option, (_, values) in zip(options, fits, strict=True)}
    best = np.argsort([f[0] for f in fits], kind="stable")[:keep]
    return {options[i]: fits[i][1] for i in best}


def forward_selection(problem: Problem, data: Data, scales, settings: Settings, score):
    """Candidates on the forward path: from the baseline, add the effect that lowers the score
    most, while any does; every fit starts from the current model's. Returns the path and every
    candidate tried."""
    path = score(problem, data, [()], scales, settings)
    tried = [path[0]]
    current: tuple[str, ...] = ()
    while len(current) < settings.max_effects:
        options = [
            e
            for e, entry in problem.registry.items()
            if e not in current and all(r in current for r in entry.requires)
        ]
        fits = screened(
            problem, data, current, options, scales, settings.screen, path[-1].get("values")
        )
        scored = score(problem, data, [(*current, e) for e in fits], scales, settings, path[-1])
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


def jacobians(problem, data, effects, values, scales) -> tuple[dict, dict]:
    """Residuals r at ``values`` and their forward-difference Jacobian ∂r/∂x in the fit's scaled
    parameters x, (units, samples, parameters): zero where a sample is not counted or its
    derivative is not finite."""
    params = parameters(problem, effects)
    x = _to_x(params, values)
    _, high = _bounds(params)
    base = residuals(problem, data, effects, values, scales)
    steps = np.sqrt(np.finfo(float).eps) * np.maximum(1.0, np.abs(x))
    steps = np.where(x + steps > high, -steps, steps)
    columns = []
    for j, h in enumerate(steps):
        moved = x.copy()
        moved[j] += h
        res = residuals(problem, data, effects, _to_values(params, moved), scales)
        columns.append({obs: (res[obs] - r) / h for obs, r in base.items()})
    jac = {}
    for obs in base:
        stacked = np.stack([c[obs].reshape(data.units, -1) for c in columns], axis=-1)
        jac[obs] = np.where(np.isfinite(stacked), stacked, 0.0)
    return base, jac


def resample_counts(data: Data, draws: int, rng: np.random.Generator) -> np.ndarray:
    """How often each unit is drawn in each of ``draws`` resamples (draws, units): every trial's
    units drawn with replacement, as many as it has."""
    counts = np.zeros((draws, data.units))
    for trial in np.unique(data.trial):
        rows = np.flatnonzero(data.trial == trial)
        picked = rows[rng.integers(0, rows.size, (draws, rows.size))]
        np.add.at(counts, (np.arange(draws)[:, None], picked), 1.0)
    return counts


def _held_steps(normal: np.ndarray, gradient: np.ndarray, held: np.ndarray) -> np.ndarray:
    """Gauss–Newton steps A⁺g of a batch of normal equations (draws, p, p) with the parameters
    ``held`` (draws, p) kept where they are: their rows and columns removed from A."""
    free = ~held
    reduced = normal * (free[:, :, None] & free[:, None, :]) + held[:, :, None] * np.eye(
        held.shape[1]
    )
    return np.einsum("bij,bj->bi", np.linalg.pinv(reduced, rcond=1e-12), gradient * free)


def bootstrap_intervals(problem, data, effects, values, scales, settings: Settings):
    """95 % percentile intervals of the one-step bootstrap (Andrews 2002, k = 1): units resampled
    with replacement within each trial; a resample's parameters are one Gauss–Newton step of its
    own least-squares problem from the full-data fit, x* = x̂ − (Σₒ wₒJₒᵀCJₒ)⁺ Σₒ wₒJₒᵀCrₒ (C its
    unit counts, wₒ = :func:`observable_weight` of its counted samples); a parameter at a fit
    bound is held there in the resamples whose step would take it beyond (as a bounded refit
    holds it); all resamples at once from per-unit products."""
    params = parameters(problem, effects)
    if not params:
        return {}
    counts = resample_counts(data, settings.bootstrap, np.random.default_rng([settings.seed, 7]))
    base, jac = jacobians(problem, data, effects, values, scales)
    size = len(params)
    normal = np.zeros((settings.bootstrap, size, size))
    gradient = np.zeros((settings.bootstrap, size))
    for obs, r in base.items():
        flat = r.reshape(data.units, -1)
        weight = observable_weight(counts @ np.isfinite(flat).sum(axis=1))
        gram = np.einsum("umi,umj->uij", jac[obs], jac[obs]).reshape(data.units, -1)
        normal += (counts @ gram).reshape(-1, size, size) * weight[:, None, None]
        cross = np.einsum("umi,um->ui", jac[obs], np.where(np.isfinite(flat), flat, 0.0))
        gradient += (counts @ cross) * weight[:, None]
    low, high = _bounds(params)
    x = _to_x(params, values)
    at_bound = np.minimum(x - low, high - x) <= 1e-6 * (high - low)
    steps = _held_steps(normal, gradient, np.zeros(gradient.shape, bool))
    outward = at_bound & ((x - steps < low) | (x - steps > high))
    steps = _held_steps(normal, gradient, outward)
    draws = np.clip(x - steps, low, high)
    log = np.array([p.log for p in params])
    draws[:, log] = np.exp(draws[:, log])
    ends = np.percentile(draws, [2.5, 97.5], axis=0)
    return {p.name: ends[:, i].tolist() for i, p in enumerate(params)}


def estimate(problem, data, effects, scales, settings: Settings, few: bool, start=None):
    """Full-data parameters of a model (fit from ``start``) and their 95 % intervals (bootstrap,
    or Wald)."""
    values, jacobian = fit(problem, data, effects, scales, start)
    if not few and settings.bootstrap > 0:
        intervals = bootstrap_intervals(problem, data, effects, values, scales, settings)
        factor = expansion(data)
        return (
            values,
            widened(problem, effects, values, intervals, factor),
            f"block bootstrap over units within trials, {settings.bootstrap} one-step refits, "
            f"percentile intervals expanded by {factor:.3f} for the units per trial",
        )
    full = _stack(residuals(problem, data, effects, values, scales))
    intervals = wald_intervals(problem, effects, values, jacobian, full)
    return values, intervals, "Wald, from the least-squares Jacobian (too few units to resample)"


def expansion(data: Data) -> float:
    """Expanded-percentile factor √(n/(n−1))·t(0.975, n−1)/z(0.975): a percentile bootstrap over
    few units per trial gives intervals too narrow (Hesterberg's expanded percentile, here as a
    stretch about the estimate). n is the size of the trial an average unit is in, Σn²/Σn (a
    short segment after a count drop does not inflate every interval)."""
    sizes = np.unique(data.trial, return_counts=True)[1].astype(float)
    n = max(float(np.sum(sizes**2) / np.sum(sizes)), 3.0)
    return float(np.sqrt(n / (n - 1.0)) * student.ppf(0.975, n - 1.0) / norm.ppf(0.975))


def earned(effect: Effect, intervals: Mapping[str, list[float]]) -> bool:
    """Whether the data earn an effect: the interval of every parameter that sizes it (not a
    ``shape`` one) lies beyond the size below which the effect is negligible (its ``negligible``
    value, else the value where it vanishes) and inside the fit bounds."""
    for p in (q for q in effect.parameters if not q.shape):
        low, high = intervals[p.name]
        floor = p.neutral if p.negligible is None else p.negligible
        weakest = float(np.min(p.strength([low, high])))
        crosses = np.sign(low - p.neutral) != np.sign(high - p.neutral)
        if crosses or weakest <= float(p.strength(floor)) or low <= p.low or high >= p.high:
            return False
    return True


def widened(problem, effects, values, intervals, ratio: float) -> dict:
    """Intervals stretched about the estimate by a factor (on the parameter's fit scale)."""
    out = {}
    for p in parameters(problem, effects):
        centre = _to_x([p], values)[0]
        low, high = (_to_x([p], {p.name: end})[0] for end in intervals[p.name])
        stretched = (centre - ratio * (centre - low), centre + ratio * (high - centre))
        out[p.name] = [float(np.exp(e) if p.log else e) for e in stretched]
    return out


def resolved(problem, effects, values, intervals) -> dict:
    """Intervals at least ± half the parameter's resolution wide (a log-scale parameter's
    interval then stops at its fit bound, never at or below zero)."""
    out = {}
    for p in parameters(problem, effects):
        half, (low, high) = 0.5 * p.resolution, intervals[p.name]
        floor = min(low, values[p.name] - half)
        out[p.name] = [min(low, p.low) if p.log and floor <= 0.0 else floor,
                       max(high, values[p.name] + half)]  # fmt: skip
    return out


def systematic_ratio(data: Data, res: Mapping[str, np.ndarray]) -> float:
    """Model-form error against the statistical one: per trial and observable, the mean residual
    curve over its n units, r̄(t), against its own noise s²(t)/n (the units' spread at t);
    B² = mean of r̄²/(s²/n) − (n − 1)/(n − 3) (the expected value of that Student ratio for an
    exact model), averaged over trials. Returns √B² of the observable that misfits most: the
    systematic misfit in standard errors of the mean (0 with fewer than 4 units per trial)."""
    worst = 0.0
    for r in res.values():
        flat = r.reshape(r.shape[0], -1)
        excess = []
        for trial in np.unique(data.trial):
            rows = flat[data.trial == trial]
            n = rows.shape[0]
            if n < 4:
                continue
            rows = rows[:, np.isfinite(rows).all(axis=0)]
            noise = np.maximum(rows.var(axis=0, ddof=1) / n, 1e-300)
            excess.append(np.mean(rows.mean(axis=0) ** 2 / noise) - (n - 1) / (n - 3))
        worst = max(worst, float(np.mean(excess)) if excess else 0.0)
    return float(np.sqrt(worst))


def wald_intervals(problem, effects, values, jacobian, dof_residuals: np.ndarray):
    """95 % intervals from the fit's Jacobian (scaled parameters), for too few units to resample."""
    params = parameters(problem, effects)
    if not params:
        return {}
    dof = max(dof_residuals.size - len(params), 1)
    variance = float(np.sum(dof_residuals**2)) / dof
    cov = np.linalg.pinv(jacobian.T @ jacobian) * variance
    se = np.sqrt(np.clip(np.diag(cov), 0.0, None))
    x = _to_x(params, values)
    z = norm.ppf(0.975)
    return {
        p.name: [
            float(np.exp(x[i] + sign * z * se[i]) if p.log else x[i] + sign * z * se[i])
            for sign in (-1.0, 1.0)
        ]
        for i, p in enumerate(params)
    }


def statistics(stack: np.ndarray, features: Mapping[str, np.ndarray], lag: int) -> dict:
    """Structure statistics of residual sets ``stack`` (sets, units, samples), NaN = not counted:
    RMS; per feature, the share of the mean square carried by the means over ten
    feature-quantile bins; and the mean lag-``lag`` autocorrelation within units."""
    sets = stack.shape[0]
    keep = np.isfinite(stack[0])
    flat = np.where(np.isfinite(stack), stack, 0.0).reshape(sets, -1)
    square = np.sum(flat**2, axis=1)
    out = {"overall": np.sqrt(square / max(keep.sum(), 1))}
    for name, feature in features.items():
        x = feature[keep]
        edges = np.quantile(x, np.linspace(0.0, 1.0, 11)[1:-1]) if x.size else np.zeros(9)
        which = np.where(keep, np.searchsorted(edges, np.where(keep, feature, 0.0)), 10).ravel()
        onehot = np.zeros((which.size, 11))
        onehot[np.arange(which.size), which] = 1.0
        sums, counts = flat @ onehot[:, :10], np.maximum(onehot[:, :10].sum(axis=0), 1.0)
        out[name] = np.sum(sums**2 / counts, axis=1) / np.maximum(square, 1e-300)
    if stack.ndim == 3 and stack.shape[2] > lag:
        values = np.where(np.isfinite(stack), stack, 0.0)
        a, b = values[:, :, :-lag], values[:, :, lag:]
        norm_ab = np.sqrt(np.sum(a * a, axis=(1, 2)) * np.sum(b * b, axis=(1, 2)))
        out["autocorrelation"] = np.sum(a * b, axis=(1, 2)) / np.maximum(norm_ab, 1e-300)
    return out


def _noise_draw(noise: np.ndarray, shape: tuple[int, ...], rng) -> np.ndarray:
    """Noise-only residual windows of a given (units, samples) shape, units and starts random."""
    units = rng.integers(0, noise.shape[0], shape[0])
    if len(shape) < 2:
        return noise[units]
    width = shape[1]
    starts = rng.integers(0, noise.shape[1] - width + 1, shape[0])
    return noise[units[:, None], starts[:, None] + np.arange(width)[None, :]]


def unexplained(problem: Problem, data: Data, held: Mapping[str, np.ndarray], scales,
                settings: Settings) -> dict:  # fmt: skip
    """Structure left in the held-out residuals, against the data's own noise as the null.

    Per observable: RMS (the goodness-of-fit floor, ``fit_floor`` × the noise's RMS), the
    share carried by each feature (phase, angle, velocity, force …) and the autocorrelation,
    each against the (1 − α/m) level of the same statistic on noise-only windows of the same
    shape (m = number of tests, a normal fit to the null draws). A test counts only when the
    structure it finds is also large: its RMS at least ``min_share`` of the observable's spread
    (structure below that is smaller than any finding this project reports).
    """
    if problem.noise is None:
        rows = [
            {"observable": obs, "correlates_with": "overall",
             "statistic": float(np.sqrt(np.nanmean(r**2))), "threshold": settings.fit_floor}
            for obs, r in held.items()
        ]  # fmt: skip
        return _verdict(rows)
    features = problem.features(data)
    noise = problem.noise(data)
    spread = {obs: measured_spread(problem, data, obs) / scales[obs] for obs in held}
    rng = np.random.default_rng([settings.seed, 11])
    tests = []
    for obs in problem.exact:  # no noise null: the fit floor, and min_share of the spread
        rms = float(np.sqrt(np.nanmean(held[obs] ** 2)))
        tests.append((obs, "overall", rms, None, rms, settings.min_share * spread[obs]))
    for obs, res in held.items():
        if obs not in noise:
            continue
        if res.ndim > 1:  # the samples that count (masked ones are NaN in every unit)
            cols = np.isfinite(res).any(axis=0)
            res = res[:, cols]
            feats = {k: v[:, cols] for k, v in features.items() if v.shape[1] == cols.size}
        else:
            feats = {k: v for k, v in features.items() if v.shape == res.shape}
        lag = max(res.shape[1] // 4, 1) if res.ndim > 1 else 1
        observed = {k: float(v[0]) for k, v in statistics(res[None], feats, lag).items()}
        draws = np.stack([_noise_draw(noise[obs], res.shape, rng)
                          for _ in range(settings.null_draws)])  # fmt: skip
        if obs in problem.relative:
            draws = draws - draws[:, :, :1]
        draws = np.where(np.isfinite(res)[None], draws, np.nan)
        null = statistics(draws, feats, lag)
        floor = settings.min_share * spread[obs]
        for name, value in observed.items():
            share = 1.0 if name == "overall" else max(value, 0.0)
            size = observed["overall"] * np.sqrt(share)
            tests.append((obs, name, value, null[name], size, floor))
    z = norm.ppf(1.0 - settings.alpha / max(len(tests), 1))
    rows = []
    for obs, name, value, null, size, floor in tests:
        if null is None:  # an exact observable: the fit floor, in resolution units
            limit = settings.fit_floor
        else:
            limit = float(null.mean() + z * null.std(ddof=1))
            if name == "overall":
                limit = max(limit, settings.fit_floor * float(null.mean()))
        rows.append({"observable": obs, "correlates_with": name, "statistic": value,
                     "threshold": limit, "size": float(size), "size_floor": float(floor),
                     "flag": bool(value > limit and size > floor)})  # fmt: skip
    return _verdict(rows)


def measured_spread(problem: Problem, data: Data, obs: str) -> float:
    """Standard deviation of a measured observable over the samples that count."""
    values = data.arrays[problem.measured[obs]]
    mask = data.arrays.get(f"mask_{obs}")
    return float(np.std(values[mask] if mask is not None else values))


def _verdict(rows: list[dict]) -> dict:
    """The flag and the flagged test furthest beyond its threshold (else the closest one)."""
    for row in rows:
        row.setdefault("flag", row["statistic"] > row["threshold"])
    flagged = [r for r in rows if r["flag"]] or rows
    worst = max(flagged, key=lambda r: r["statistic"] / r["threshold"]) if rows else None
    flag = bool(worst and worst["flag"])
    return {
        "flag": flag,
        "observable": worst["observable"] if flag else None,
        "correlates_with": worst["correlates_with"] if flag else None,
        "statistic": worst["statistic"] if worst else None,
        "threshold": worst["threshold"] if worst else None,
        "tests": rows,
    }


def rmse_by_observable(problem: Problem, held: Mapping[str, np.ndarray], scales) -> dict:
    """Held-out RMS error of every observable in its own unit (key carries the unit)."""
    return {
        f"{obs}_{problem.units[obs]}": float(np.sqrt(np.nanmean(r**2)) * scales[obs])
        for obs, r in held.items()
    }


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


def _joined(parts: Sequence[str]) -> str:
    return parts[0] if len(parts) == 1 else ", ".join(parts[:-1]) + " and " + parts[-1]


def cause_sentence(problem: Problem, found: Sequence[str], tentative: Sequence[str],
                   gain: Mapping, verdict: Mapping) -> str:  # fmt: skip
    """What the baseline gets wrong and why, and what is left unexplained."""
    if found:
        named = _joined([problem.registry[e].description for e in found])
        text = (
            f"The {problem.baseline_name} misses the data because of {named}; the extended "
            f"model cuts the {'held-out ' if gain['held_out'] else ''}error by "
            f"{gain['reduction_pct']:.0f} %."
        )
    elif not verdict["flag"]:
        return f"none: the {problem.baseline_name} explains the data"
    elif tentative:
        named = _joined([problem.registry[e].description for e in tentative])
        text = (
            f"The {problem.baseline_name} misses the data; {named} improve the fit but are not "
            "claimed while structure remains that none of them explains."
        )
    else:
        text = (
            f"No effect in the registry explains the data better than the {problem.baseline_name}."
        )
    if verdict["flag"]:
        what = verdict["correlates_with"]
        patterns = {"overall": "is larger than the noise allows",
                    "autocorrelation": "is correlated in time"}  # fmt: skip
        pattern = patterns.get(what, f"follows {what}")
        text += (
            f" Left unexplained: the held-out residual of {verdict['observable']} {pattern} "
            f"(statistic {verdict['statistic']:.3g} against a noise threshold of "
            f"{verdict['threshold']:.3g}); no registry effect accounts for it."
        )
    return text


def analyse(problem: Problem, data: Data, scales: Mapping[str, float], settings: Settings,
            source: str) -> dict:  # fmt: skip
    """The discrepancy report: candidates, selection, effects with 95 % intervals, gain,
    unexplained structure and the cause, with the same keys for every group."""
    with worker_pool(problem, data, scales, settings.workers):
        return _report(problem, data, scales, settings, source)


def _report(problem: Problem, data: Data, scales, settings: Settings, source: str) -> dict:
    """:func:`analyse` with its worker processes running."""
    few = data.units < settings.min_units_cv
    score = in_sample if few else held_out
    path, tried = forward_selection(problem, data, scales, settings, score)
    chosen = min(path, key=lambda p: p["score"]) if few else one_se_rule(path)
    effects = tuple(ordered(problem, chosen["effects"]))
    dropped: list[dict] = []
    start = chosen.get("values")
    while True:
        values, intervals, method = estimate(problem, data, effects, scales, settings, few, start)
        res = residuals(problem, data, effects, values, scales)
        noisy = {o: r for o, r in res.items() if o not in problem.exact}
        widening = float(np.hypot(1.0, systematic_ratio(data, noisy)))
        intervals = widened(problem, effects, values, intervals, widening)
        intervals = resolved(problem, effects, values, intervals)
        weak = [e for e in effects if not earned(problem.registry[e], intervals)]
        weak += [e for e in effects if any(r in weak for r in problem.registry[e].requires)]
        if not weak:
            break
        for e in dict.fromkeys(weak):
            names = [p.name for p in problem.registry[e].parameters]
            dropped.append({"effect": e, "ci95": {n: intervals[n] for n in names}})
        effects = tuple(e for e in effects if e not in weak)
        chosen = score(problem, data, [effects], scales, settings, chosen)[0]
        start = values  # the larger model's estimate
    verdict = unexplained(problem, data, chosen["cv"]["residuals"], scales, settings)
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
    entries = [
        {
            "effect": name,
            "description": problem.registry[name].description,
            "observables": list(problem.registry[name].observables),
            "parameters": {p.name: values[p.name] for p in problem.registry[name].parameters},
            "units": {p.name: p.unit for p in problem.registry[name].parameters},
            "ci95": {p.name: intervals[p.name] for p in problem.registry[name].parameters},
        }
        for name in effects
    ]
    claimed = [] if verdict["flag"] else entries
    return {
        "group": problem.group,
        "source": source,
        "baseline": {"model": problem.baseline_name, "loss": gain["baseline_loss"]},
        "observables": {o: problem.units[o] for o in problem.measured},
        "noise_scales": {f"{o}_{problem.units[o]}": float(scales[o]) for o in problem.measured},
        "registry": {
            name: {
                "description": e.description,
                "observables": list(e.observables),
                "requires": list(e.requires),
                "parameters": [
                    {
                        "name": p.name,
                        "unit": p.unit,
                        "bounds": [p.low, p.high],
                        "meaning": p.meaning,
                    }
                    for p in e.parameters
                ],
            }
            for name, e in problem.registry.items()
        },
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
        "dropped": dropped,
        "intervals": f"{method}; widened by √(1 + B²) = {widening:.2f}, B "
        "the misfit of the mean residual curve per trial in its own standard errors (the bias "
        "a model-form error of that size leaves, added in quadrature)",
        "effects_found": claimed,
        "tentative": [] if claimed else entries,
        "gain": gain,
        "unexplained": verdict,
        "cause": cause_sentence(
            problem,
            [e["effect"] for e in claimed],
            [] if claimed else list(effects),
            gain,
            verdict,
        ),
    }
