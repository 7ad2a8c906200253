"""95 % intervals of a selected model's parameters: one-step block bootstrap (or Wald), the
expansion for few units, the model-form widening, the resolution floor, and whether an effect is
earned."""

from __future__ import annotations

from collections.abc import Mapping, Sequence

import numpy as np
from scipy.special import ndtri, stdtrit

from exobench.selection.fitting import fit, scaled_bounds, stacked, to_scaled, to_values
from exobench.selection.model import (
    Data,
    Effect,
    Parameter,
    Settings,
    observable_weight,
    ordered,
    parameters,
    residuals,
)


def jacobians(problem, data, effects, values, scales) -> tuple[dict, dict]:
    """Residuals r at ``values`` and their forward-difference Jacobian ∂r/∂x in the fit's scaled
    parameters x (:func:`forward_differences`)."""
    params = parameters(problem, effects)
    x = to_scaled(params, values)
    _, high = scaled_bounds(params)
    base = residuals(problem, data, effects, values, scales)

    def moved(_, shifted):
        return residuals(problem, data, effects, to_values(params, shifted), scales)

    return base, forward_differences(x, high, base, moved, data.units)


def forward_differences(x: np.ndarray, high: np.ndarray, base: Mapping, evaluate,
                        units: int) -> dict:  # fmt: skip
    """∂r/∂x of residuals ``base`` at x by forward differences, steps √ε·max(1, |x|) (backward
    at the upper bound); ``evaluate(j, moved)`` gives the residuals with x moved in its j-th
    entry. (units, samples, parameters) per observable, 0 where a sample is not counted or its
    derivative is not finite."""
    steps = np.sqrt(np.finfo(float).eps) * np.maximum(1.0, np.abs(x))
    steps = np.where(x + steps > high, -steps, steps)
    columns = []
    for j, h in enumerate(steps):
        moved = x.copy()
        moved[j] += h
        res = evaluate(j, moved)
        columns.append({obs: (res[obs] - r) / h for obs, r in base.items()})
    jac = {}
    for obs in base:
        stacked = np.stack([c[obs].reshape(units, -1) for c in columns], axis=-1)
        jac[obs] = np.where(np.isfinite(stacked), stacked, 0.0)
    return jac


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
    low, high = scaled_bounds(params)
    x = to_scaled(params, values)
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
    full = stacked(residuals(problem, data, effects, values, scales))
    intervals = wald_intervals(problem, effects, values, jacobian, full)
    return values, intervals, "Wald, from the least-squares Jacobian (too few units to resample)"


def expansion(data: Data) -> float:
    """Expanded-percentile factor √(n/(n−1))·t(0.975, n−1)/z(0.975): a percentile bootstrap over
    few units per trial gives intervals too narrow (Hesterberg's expanded percentile, here as a
    stretch about the estimate). n is the size of the trial an average unit is in, Σn²/Σn (a
    short segment after a count drop does not inflate every interval)."""
    sizes = np.unique(data.trial, return_counts=True)[1].astype(float)
    n = max(float(np.sum(sizes**2) / np.sum(sizes)), 3.0)
    return float(np.sqrt(n / (n - 1.0)) * stdtrit(n - 1.0, 0.975) / ndtri(0.975))


def earned(effect: Effect, intervals: Mapping[str, list[float]]) -> bool:
    """Whether the data earn an effect: the interval of every parameter that sizes it (not a
    ``shape`` one; of any one where the effect has ``any_size``, the others inside their fit
    bounds) lies beyond the size below which the effect is negligible (its ``negligible``
    value, else the value where it vanishes) and inside the fit bounds."""
    sizing = [p for p in effect.parameters if not p.shape]
    if effect.any_size:
        return all(inside(p, intervals[p.name]) for p in sizing) and any(
            sized(p, intervals[p.name]) for p in sizing
        )
    return all(sized(p, intervals[p.name]) for p in sizing)


def inside(p: Parameter, interval: Sequence[float]) -> bool:
    """Whether an interval lies inside the parameter's fit bounds, low > p.low and high < p.high
    (one at a bound: the fit could not place it)."""
    return bool(interval[0] > p.low and interval[1] < p.high)


def sized(p: Parameter, interval: Sequence[float]) -> bool:
    """Whether one parameter's interval lies beyond its negligible size (or its neutral value)
    on one side, and :func:`inside` its fit bounds."""
    low, high = interval
    floor = p.neutral if p.negligible is None else p.negligible
    weakest = float(np.min(p.strength([low, high])))
    crosses = np.sign(low - p.neutral) != np.sign(high - p.neutral)
    return not (crosses or weakest <= float(p.strength(floor))) and inside(p, interval)


def widened(problem, effects, values, intervals, ratio: float) -> dict:
    """Intervals stretched about the estimate by a factor (on the parameter's fit scale)."""
    out = {}
    for p in parameters(problem, effects):
        centre = to_scaled([p], values)[0]
        low, high = (to_scaled([p], {p.name: end})[0] for end in intervals[p.name])
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
    x = to_scaled(params, values)
    z = ndtri(0.975)
    return {
        p.name: [
            float(np.exp(x[i] + sign * z * se[i]) if p.log else x[i] + sign * z * se[i])
            for sign in (-1.0, 1.0)
        ]
        for i, p in enumerate(params)
    }


def settled(problem, data, scales, settings: Settings, few: bool, score, chosen: dict) -> dict:
    """The chosen model with only what the data earn: estimates and 95 % intervals (bootstrap or
    Wald, widened by √(1 + B²) for the model-form error B, at least ± half a resolution); an
    effect or term whose interval reaches where it vanishes (or a fit bound) is dropped, with
    what requires it, and the rest refitted and rescored, until all are earned."""
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
        weak = [e for e in effects if not earned(problem.entries[e], intervals)]
        weak += [e for e in effects if any(r in weak for r in problem.entries[e].requires)]
        if not weak:
            break
        for e in dict.fromkeys(weak):
            names = [p.name for p in problem.entries[e].parameters]
            dropped.append({"effect": e, "ci95": {n: intervals[n] for n in names}})
        effects = tuple(e for e in effects if e not in weak)
        chosen = score(problem, data, [effects], scales, settings, chosen)[0]
        start = values  # the larger model's estimate
    return {"effects": effects, "values": values, "intervals": intervals, "method": method,
            "widening": widening, "dropped": dropped, "chosen": chosen}  # fmt: skip
