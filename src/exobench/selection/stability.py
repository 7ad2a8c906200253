"""Parameter stability between trials: a constant of the rig must hold from one trial to the next.

Straps are re-fastened, sensors re-zeroed, cables re-tensioned between trials; the model fits one
value for the session. The constants a group's assumption table says must hold between trials
(its ``between`` rows, :class:`Constant`) are refitted with one value per trial, jointly, every
other parameter of the model shared and refitted with them (:func:`heterogeneous`; an offset
the model lacks starts from its neutral value; a compliance the model lacks has nothing to vary
and is not tested). Where structure is left or a constant differs, the trials are compared in
the best by AIC of the settled model and fuller ones (:func:`compared`). Each trial's
estimates have the cluster-sandwich covariance over its units given the shared parameters (the
limit of the engine's one-step bootstrap over units), widened by √(1 + B²) for the misfit B of
the mean residual curve the fit leaves (:func:`systematic_ratio`, as the engine widens its
intervals: a model-form error, not a changed constant, is what per-trial values cannot remove).
A shared parameter that moves one trial's units alone (a count drop located before that trial)
counts as that trial's own in its errors; a constant that another parameter can stand in for
there, or whose interval holds its whole search range, is not sized by that trial, which is left
out of its comparison and named (``unsized``).

Whether the trials agree is Welch's test of equal means with unequal variances (Welch 1951):
Cochran's Q = Σ w_i(x_i − x̄)² (w_i = 1/se_i², x̄ their weighted mean) with the small-sample
correction for each se_i resting on n_i − 1 degrees of freedom, F = Q/(k − 1)/(1 + 2(k − 2)Λ/
(k² − 1)) on k − 1 and (k² − 1)/(3Λ) degrees of freedom, Λ = Σ(1 − w_i/W)²/(n_i − 1). The
p values of the constants a report tests are adjusted by Holm's method. A flagged constant names
the trials that depart: the one furthest from the others' weighted mean (in its own and their
standard errors), set apart in turn while the rest still disagree at α/m by more than the row's
floor (a quarter of the smallest spread a recording can see, docs/assumptions.md: a smaller
departure is not a finding); each departure is given as its difference from the others with a
95 % interval (Welch–Satterthwaite degrees of freedom).
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence

import numpy as np
from scipy.optimize import least_squares
from scipy.special import fdtrc, stdtrit  # F's tail and Student's t quantile (scipy.stats' own)

from exobench.selection.fitting import scaled_bounds, stacked, to_scaled, to_values
from exobench.selection.intervals import forward_differences, systematic_ratio
from exobench.selection.model import (
    Constant,
    Data,
    Problem,
    Settings,
    observable_weight,
    ordered,
    parameters,
    residuals,
    trial_labels,
)


def welch(x: np.ndarray, se: np.ndarray, units: np.ndarray) -> dict:
    """Welch's test that trial means agree: Q = Σw(x − x̄)², F = Q/(k − 1)/(1 + 2(k − 2)Λ/(k² − 1))
    on (k − 1, (k² − 1)/(3Λ)) degrees of freedom, Λ = Σ(1 − w/W)²/(n − 1), w = 1/se²."""
    w = 1.0 / se**2
    total = float(w.sum())
    mean = float(np.sum(w * x) / total)
    q = float(np.sum(w * (x - mean) ** 2))
    k = x.size
    lam = float(np.sum((1.0 - w / total) ** 2 / (units - 1.0)))
    statistic = q / (k - 1.0) / (1.0 + 2.0 * (k - 2.0) * lam / (k**2 - 1.0))
    df = (k - 1.0, (k**2 - 1.0) / (3.0 * lam) if lam > 0 else np.inf)
    return {"q": q, "statistic": statistic, "df": df, "p": float(fdtrc(*df, statistic)),
            "mean": mean}  # fmt: skip


def departure(x: np.ndarray, se: np.ndarray, units: np.ndarray, i: int,
              rest: np.ndarray) -> dict:  # fmt: skip
    """Trial i against the weighted mean x̄ of the ``rest`` (an index array): d = x_i − x̄, its
    standard error √(se_i² + 1/W) and Welch–Satterthwaite degrees of freedom
    (se_i² + 1/W)²/(se_i⁴/(n_i − 1) + 1/(W²·Σ(n − 1)))."""
    w = 1.0 / se[rest] ** 2
    mean = float(np.sum(w * x[rest]) / w.sum())
    pooled = 1.0 / float(w.sum())
    error = float(np.sqrt(se[i] ** 2 + pooled))
    df = (se[i] ** 2 + pooled) ** 2 / (
        se[i] ** 4 / (units[i] - 1.0) + pooled**2 / float(np.sum(units[rest] - 1.0))
    )
    return {"others": mean, "difference": float(x[i] - mean), "se": error, "df": float(df),
            "z": float((x[i] - mean) / error)}  # fmt: skip


def departing(x: np.ndarray, se: np.ndarray, units: np.ndarray, level: float,
              floor: float) -> list[int]:  # fmt: skip
    """The trials that depart: while the trials left disagree (Welch's p below ``level``), the
    one furthest from the others' weighted mean (|z| of :func:`departure`) is set apart if it
    departs by more than ``floor``; two trials left that still disagree by more both depart."""
    left = list(range(x.size))
    out: list[int] = []
    while len(left) >= 2 and welch(x[left], se[left], units[left])["p"] < level:
        if len(left) == 2:
            return out + left if abs(x[left[0]] - x[left[1]]) > floor else out
        apart = [departure(x, se, units, i, np.array([j for j in left if j != i])) for i in left]
        far = int(np.argmax([abs(d["z"]) for d in apart]))
        if abs(apart[far]["difference"]) <= floor:
            break
        out.append(left.pop(far))
    return out


def holm(p: Sequence[float]) -> list[float]:
    """Holm's step-down adjustment: p_(j) → max over i ≤ j of min(1, (m − i + 1)·p_(i))."""
    order = np.argsort(p)
    adjusted = np.empty(len(p))
    running = 0.0
    for rank, i in enumerate(order):
        running = max(running, min(1.0, (len(p) - rank) * p[i]))
        adjusted[i] = running
    return adjusted.tolist()


def _natural(parameter, x: float) -> float:
    """A value on a parameter's fit scale in its own unit: e^x for a log-scale one."""
    return float(np.exp(x) if parameter.log else x)


def untested(problem: Problem, model: Mapping, constant: Constant) -> str:
    """Why a constant cannot be tested with this engine and model ('' if it can)."""
    if constant.effect not in problem.entries:
        return f"no effect or term of this engine sizes it ({constant.effect})"
    if constant.needs_effect and constant.effect not in model["effects"]:
        return f"the model holds no {constant.effect.replace('_', ' ')}: nothing to vary"
    return ""


class Heterogeneous:
    """The model with each testable constant one value per trial (of the trials in ``groups``,
    trial -> its unit rows) and every other parameter shared: its parameters on the fit scale
    (the shared ones, then each trial's constants) and its residuals, each trial's units
    evaluated with that trial's values."""

    def __init__(self, problem: Problem, data: Data, scales, effects: Sequence[str],
                 varying: Sequence[str], groups: Mapping[str, np.ndarray]) -> None:  # fmt: skip
        self.problem, self.scales = problem, scales
        self.names = tuple(ordered(problem, effects))
        every = parameters(problem, self.names)
        self.constants = [next(p for p in every if p.name == name) for name in varying]
        self.shared = [p for p in every if p.name not in varying]
        self.parts = [data.take(rows) for rows in groups.values()]
        self.data = data.take(np.concatenate(list(groups.values())))

    def split(self, x: np.ndarray) -> list[dict[str, float]]:
        """Each trial's parameter values from the scaled vector x."""
        s, m = len(self.shared), len(self.constants)
        common = to_values(self.shared, x[:s])
        return [common | to_values(self.constants, x[s + i * m : s + (i + 1) * m])
                for i in range(len(self.parts))]  # fmt: skip

    def residuals(self, x: np.ndarray, only: int | None = None, base=None) -> dict:
        """Residuals of every unit (trials in order); ``only``: that trial's re-evaluated, the
        others' taken from ``base``."""
        values = self.split(x)
        per = [residuals(self.problem, part, self.names, values[i], self.scales)
               if only is None or i == only else None
               for i, part in enumerate(self.parts)]  # fmt: skip
        if only is not None:
            rows = np.cumsum([0] + [p.units for p in self.parts])
            return {o: np.concatenate([base[o][rows[i]:rows[i + 1]] if r is None else r[o]
                                       for i, r in enumerate(per)]) for o in base}  # fmt: skip
        return {o: np.concatenate([r[o] for r in per]) for o in per[0]}

    def jacobian(self, x: np.ndarray, base: Mapping) -> dict:
        """∂r/∂x per unit and sample (:func:`forward_differences`), a trial's constant
        re-evaluating its trial alone."""
        s, m = len(self.shared), len(self.constants)

        def moved(j, shifted):
            return self.residuals(shifted, None if j < s else (j - s) // m, base)

        return forward_differences(x, self.bounds()[1], base, moved, self.data.units)

    def start(self, values: Mapping[str, float]) -> np.ndarray:
        """The scaled vector with every parameter at ``values``."""
        return np.concatenate(
            [
                to_scaled(self.shared, values),
                np.tile(to_scaled(self.constants, values), len(self.parts)),
            ]
        )

    def bounds(self) -> tuple[np.ndarray, np.ndarray]:
        """Fit bounds of the scaled vector."""
        (low, high), (clow, chigh) = scaled_bounds(self.shared), scaled_bounds(self.constants)
        k = len(self.parts)
        return np.concatenate([low, np.tile(clow, k)]), np.concatenate([high, np.tile(chigh, k)])


def vanishing(parameter) -> float:
    """Where a parameter's effect vanishes, inside its fit bounds (a stiffness: its upper)."""
    if np.isinf(parameter.neutral):
        return float(parameter.high)
    return float(np.clip(parameter.neutral, parameter.low, parameter.high))


def _inverse(curvature: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The inverse of a curvature matrix A = JᵀJ through its scale-free form R = D⁻¹AD⁻¹
    (D² = diag A), A⁻¹ = D⁻¹R⁻¹D⁻¹, and which parameters the data leave unsized: those another
    parameter can stand in for, whose variance inflation [R⁻¹]ⱼⱼ = 1/(1 − R²ⱼ) exceeds 1/√ε
    (J comes from forward differences, good to a relative √ε: a larger inflation cannot be told
    from an infinite one), or that move nothing. R's eigenvalues are floored at ε·max."""
    scale = np.sqrt(np.clip(np.diag(curvature), 0.0, None))
    moved = scale > 0.0
    scale = np.where(moved, scale, 1.0)
    values, vectors = np.linalg.eigh(curvature / np.outer(scale, scale))
    floored = np.maximum(values, np.finfo(float).eps * values.max(initial=1.0))
    scaled = (vectors / floored) @ vectors.T
    unsized = ~moved | (np.diag(scaled) > 1.0 / np.sqrt(np.finfo(float).eps))
    return scaled / np.outer(scale, scale), unsized


def heterogeneous(problem: Problem, data: Data, scales, model: Mapping,
                  testable: Sequence[Constant], trials: np.ndarray, min_units: int,
                  warm: Mapping | None = None) -> dict:  # fmt: skip
    """The model refitted to all the trials of at least ``min_units`` units with each testable
    constant one value per trial, every other parameter shared (least squares from the model's
    estimates, :func:`vanishing` where it has none, or from a smaller model's fit, ``warm``).
    Returns per trial its constants' estimates
    x on the fit scale and their standard errors given the shared parameters (whose error is
    common to the trials and cancels where they are compared), from the cluster sandwich over
    the trial's n units, A⁻¹·n/(n − 1)·Σ_u(g_u − ḡ)(g_u − ḡ)ᵀ·A⁻¹ (A = Σ_o w_o Σ JᵀJ and g_u =
    Σ_o w_o Σ Jᵀr over a unit's samples, in the trial's constants; w_o =
    :func:`observable_weight`) (``fits``); the misfit B the fit leaves (:func:`systematic_ratio`,
    as the engine widens its intervals); its AIC with the noise scales known, Σr² + 2p, over the
    observables that carry noise; and its values, shared and per trial (a warm start)."""
    groups = {str(t): np.flatnonzero(trials == t) for t in dict.fromkeys(trials)}
    groups = {t: rows for t, rows in groups.items() if rows.size >= min_units}
    if not groups:
        return {"fits": {}, "misfit": 0.0, "aic": np.inf, "shared": {}, "trials": {}}
    effects = {*model["effects"], *(c.effect for c in testable)}
    fit_ = Heterogeneous(problem, data, scales, effects, [c.parameter for c in testable], groups)
    # a parameter the model has no estimate of starts where its effect vanishes
    start = {p.name: vanishing(p) for p in [*fit_.shared, *fit_.constants]} | dict(model["values"])
    start |= (warm or {}).get("shared", {})
    low, high = fit_.bounds()
    x0 = fit_.start(start)
    s, m = len(fit_.shared), len(fit_.constants)
    for i, trial in enumerate(groups):  # each trial's constants where a smaller model left them
        own = {**start, **(warm or {}).get("trials", {}).get(trial, {})}
        x0[s + i * m : s + (i + 1) * m] = to_scaled(fit_.constants, own)
    x0 = np.clip(x0, low + 1e-9 * (high - low), high - 1e-9 * (high - low))

    def objective(x):
        return stacked(fit_.residuals(x))

    def jac(x):
        base = fit_.residuals(x)
        slopes = fit_.jacobian(x, base)
        parts = []
        for o, r in base.items():
            counted = np.isfinite(r).reshape(fit_.data.units, -1)
            weight = np.sqrt(observable_weight(counted.sum()))
            parts.append(slopes[o][counted] * weight)
        return np.concatenate(parts)

    x = least_squares(objective, x0, jac=jac, bounds=(low, high), x_scale="jac", ftol=1e-6,
                      xtol=1e-6, max_nfev=100).x  # fmt: skip
    base = fit_.residuals(x)
    slopes = fit_.jacobian(x, base)
    size = x.size
    curvature, contributions = np.zeros((size, size)), np.zeros((fit_.data.units, size))
    for o, r in base.items():
        flat = r.reshape(fit_.data.units, -1)
        counted = np.isfinite(flat)
        weight = observable_weight(counted.sum())
        curvature += weight * np.einsum("umi,umj->ij", slopes[o], slopes[o])
        contributions += weight * np.einsum("umi,um->ui", slopes[o], np.where(counted, flat, 0.0))
    units = np.array([rows.size for rows in groups.values()], float)
    clow, chigh = scaled_bounds(fit_.constants)
    starts = np.concatenate([[0], np.cumsum(units)]).astype(int)
    # the units each shared parameter moves: one a single trial's units alone move (a count drop
    # the QC located in that trial) is that trial's own, its error not common to the trials
    moves = sum(np.nansum(np.abs(slopes[o][..., :s]), axis=1) for o in base) > 0.0
    fits = {}
    for i, trial in enumerate(groups):
        block = slice(s + i * m, s + (i + 1) * m)
        inside = np.zeros(fit_.data.units, bool)
        inside[starts[i] : starts[i + 1]] = True
        local = np.flatnonzero(moves[inside].any(axis=0) & ~moves[~inside].any(axis=0))
        index = np.concatenate([local, np.arange(s + i * m, s + (i + 1) * m)])
        own = contributions[inside][:, index]
        centred = own - own.mean(axis=0)
        spread = units[i] / (units[i] - 1.0) * centred.T @ centred
        inverse, unsized = _inverse(curvature[np.ix_(index, index)])
        se = np.sqrt(np.clip(np.diag(inverse @ spread @ inverse), 0.0, None))
        se = np.where(unsized, np.inf, se)[local.size :]
        fits[trial] = {"x": x[block], "se": se, "units": int(units[i]),
                       "local": [fit_.shared[j].name for j in local],
                       "at_bound": np.minimum(x[block] - clow, chigh - x[block])
                       <= 1e-6 * (chigh - clow)}  # fmt: skip
    noisy = {o: r for o, r in base.items() if o not in problem.exact}
    squares = sum(float(np.nansum(r**2)) for r in noisy.values())
    values = fit_.split(x)
    shared = {p.name: values[0][p.name] for p in fit_.shared}
    per_trial = {t: {p.name: v[p.name] for p in fit_.constants}
                 for t, v in zip(groups, values, strict=True)}  # fmt: skip
    return {"fits": fits, "misfit": systematic_ratio(fit_.data, noisy),
            "aic": squares + 2.0 * x.size, "shared": shared, "trials": per_trial}  # fmt: skip


def compared(problem: Problem, data: Data, scales, settings: Settings,
             models: Sequence[Mapping]) -> tuple[Mapping, dict, dict, float]:  # fmt: skip
    """Of the candidate ``models`` (each holding the one before), the one whose
    :func:`heterogeneous` fit scores the lowest AIC, with its reasons per constant, per-trial
    fits and misfit B; each candidate's fit starts where the one before left its parameters."""
    trials = trial_labels(problem, data)
    best, warm = None, None
    for model in models:
        reasons = {c.row: untested(problem, model, c) for c in problem.constants}
        testable = [c for c in problem.constants if not reasons[c.row]]
        result = {"fits": {}, "misfit": 0.0, "aic": np.inf}
        if testable:
            result = heterogeneous(problem, data, scales, model, testable, trials,
                                   settings.stability_min_units, warm)  # fmt: skip
            warm = result
        if best is None or result["aic"] < best[4]:
            best = (model, reasons, result["fits"], result["misfit"], result["aic"])
    return best[:4]


def stability(problem: Problem, data: Data, scales, settings: Settings, model: Mapping,
              fuller: Sequence[Mapping] = (), left: bool = False) -> dict:  # fmt: skip
    """Parameter stability of every constant of the problem for a settled ``model`` (module
    docstring): per trial its estimate and 95 % interval, Welch's test, Holm-adjusted p, the
    trials that depart with their differences, and whether it is flagged. Where structure is
    ``left`` or a constant differs, the trials are compared again in the best of the model and
    the ``fuller`` candidates, each holding the one before (:func:`compared`): a constant
    changed in one trial spreads the held-out errors, and the selection may then settle on too
    few effects."""
    result = compared_constants(problem, data, scales, settings, [model])
    if not (left or result["flag"]) or not fuller:
        return result
    models = [model]
    for more in fuller:
        effects = tuple(dict.fromkeys([*models[-1]["effects"], *more["effects"]]))
        if set(effects) != set(models[-1]["effects"]):
            models.append({"effects": effects, "values": {**more["values"], **model["values"]}})
    return compared_constants(problem, data, scales, settings, models)


def compared_constants(problem: Problem, data: Data, scales, settings: Settings,
                       models: Sequence[Mapping]) -> dict:  # fmt: skip
    """The parameter stability in the best of the candidate ``models`` (:func:`compared`)."""
    model, reasons, fits, misfit = compared(problem, data, scales, settings, models)
    testable = [c for c in problem.constants if not reasons[c.row]]
    widening = float(np.hypot(1.0, misfit))
    tested, out = [], []
    for constant in problem.constants:
        reason = reasons[constant.row]
        parameter = (None if reason.startswith("no effect") else next(
            p for p in problem.entries[constant.effect].parameters
            if p.name == constant.parameter))  # fmt: skip
        entry = {"assumption": constant.row, "name": constant.name, "effect": constant.effect,
                 "parameter": constant.parameter, "unit": parameter.unit if parameter else "",
                 "relative": bool(parameter and parameter.log), "size_floor": constant.floor,
                 "flag": False, "trials": [], "departing": []}  # fmt: skip
        out.append(entry)
        if reason:
            entry.update(tested=False, reason=reason, decision=f"not tested: {reason}")
            continue
        k = testable.index(constant)
        (low,), (high,) = scaled_bounds([parameter])
        usable, entry["unsized"] = [], []
        for trial, f in fits.items():
            x, se, bound = float(f["x"][k]), float(f["se"][k]) * widening, bool(f["at_bound"][k])
            half = float(stdtrit(f["units"] - 1, 0.975) * se)
            # a trial whose interval holds the whole search range does not size the constant
            sized = bool(np.isfinite(half) and (x - half > low or x + half < high))
            entry["trials"].append({
                "trial": trial, "units": f["units"], "estimate": _natural(parameter, x),
                "ci95": [_natural(parameter, x - half), _natural(parameter, x + half)]
                if sized else [None, None],
                "at_bound": bound, "sized": sized,
            })  # fmt: skip
            if not sized:
                entry["unsized"].append({"trial": trial, "with": f["local"]})
            elif se > 0 and not bound:
                usable.append((trial, x, se, f["units"]))
        if len(usable) < 2:
            reason = f"fewer than two trials of at least {settings.stability_min_units} units"
            entry.update(tested=False, reason=reason, decision=f"not tested: {reason}")
            continue
        arrays = [np.array([u[i] for u in usable], float) for i in (1, 2, 3)]
        entry.update(tested=True, reason="", used=[u[0] for u in usable], **welch(*arrays))
        entry["pooled"] = _natural(parameter, entry.pop("mean"))
        tested.append((entry, arrays, parameter))
    count = len(tested)
    for (entry, arrays, parameter), adjusted in zip(tested, holm([e["p"] for e, _, _ in tested]),
                                                    strict=True):  # fmt: skip
        entry["p_adjusted"] = adjusted
        if adjusted >= settings.stability_alpha:
            entry["decision"] = f"holds: trials agree (Holm-adjusted p {adjusted:.3g})"
            continue
        x, se, units = arrays
        apart = departing(x, se, units, settings.stability_alpha / count, entry["size_floor"])
        rest = np.array([i for i in range(x.size) if i not in apart] or range(x.size))
        for i in apart:
            d = departure(x, se, units, i, np.array([j for j in rest if j != i]))
            half = float(stdtrit(d["df"], 0.975) * d["se"])
            entry["departing"].append({
                "trial": entry["used"][i],
                "difference": d["difference"],
                "difference_ci95": [d["difference"] - half, d["difference"] + half],
                "others": _natural(parameter, d["others"]),
            })  # fmt: skip
        entry["size"] = max((abs(d["difference"]) for d in entry["departing"]), default=0.0)
        entry["flag"] = bool(entry["departing"]) and entry["size"] > entry["size_floor"]
        entry["decision"] = (
            f"violated: trials disagree (Holm-adjusted p {adjusted:.3g})" if entry["flag"] else
            f"holds: trials disagree (Holm-adjusted p {adjusted:.3g}) by less than the floor "
            f"{entry['size_floor']:.3g}"
        )  # fmt: skip
    return {
        "method": "the model refitted with each constant one value per trial, every other "
        "parameter shared; cluster-sandwich standard errors over units, widened by "
        f"√(1 + B²) = {widening:.2f}, B the misfit the refits leave; Welch's test of equal "
        "means (Cochran's Q with its small-sample correction) per constant; Holm's adjustment "
        f"over the {count} constants tested",
        "alpha": settings.stability_alpha,
        "model": list(ordered(problem, model["effects"])),
        "widening": widening,
        "flag": any(e["flag"] for e in out),
        "constants": out,
    }
