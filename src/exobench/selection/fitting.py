"""Least-squares fits of a candidate's parameters (bounded, on log or linear scales)."""

from __future__ import annotations

from collections.abc import Mapping, Sequence

import numpy as np
from scipy.optimize import least_squares

from exobench.selection.model import Parameter, observable_weight, parameters, residuals


def stacked(res: Mapping[str, np.ndarray], fixed: bool = False) -> np.ndarray:
    """Residual vector of the least-squares fit: each observable's counted residuals times
    √(its :func:`observable_weight`) (``fixed``: every sample kept, the uncounted as 0, so
    that vectors of different candidates line up)."""
    parts = []
    for r in res.values():
        counted = np.isfinite(r)
        flat = np.where(counted, r, 0.0).ravel() if fixed else r[counted]
        parts.append(flat * np.sqrt(observable_weight(counted.sum())))
    return np.concatenate(parts)


def to_values(params: Sequence[Parameter], x: np.ndarray) -> dict[str, float]:
    return {p.name: float(np.exp(v) if p.log else v) for p, v in zip(params, x, strict=True)}


def to_scaled(params: Sequence[Parameter], values: Mapping[str, float]) -> np.ndarray:
    x = [np.log(values[p.name]) if p.log else values[p.name] for p in params]
    return np.array(x, float)


def scaled_bounds(params: Sequence[Parameter]) -> tuple[np.ndarray, np.ndarray]:
    """Lower and upper fit bounds of the scaled parameters."""
    low = np.array([np.log(p.low) if p.log else p.low for p in params])
    high = np.array([np.log(p.high) if p.log else p.high for p in params])
    return low, high


def fit(problem, data, effects, scales, start: Mapping[str, float] | None = None):
    """Least-squares parameters of a candidate and the fit's Jacobian (scaled parameters)."""
    params = parameters(problem, effects)
    if not params:
        return {}, np.zeros((0, 0))
    low, high = scaled_bounds(params)
    guess = {p.name: p.initial() for p in params}
    if start:
        guess.update({k: v for k, v in start.items() if k in guess})
    x0 = np.clip(to_scaled(params, guess), low + 1e-9 * (high - low), high - 1e-9 * (high - low))

    def objective(x):
        return stacked(residuals(problem, data, effects, to_values(params, x), scales))

    result = least_squares(
        objective, x0, bounds=(low, high), x_scale="jac", ftol=1e-6, xtol=1e-6, max_nfev=100
    )
    return to_values(params, result.x), result.jac


# The analysis whose worker processes are running: ((problem, data, scales), pool). Workers are
# forked once per analysis with it in memory, so a task carries only its arguments (effects,
