"""What is left unexplained: structure tests of held-out residuals against the data's own
noise-only windows."""

from __future__ import annotations

from collections.abc import Mapping

import numpy as np
from scipy.special import ndtri, stdtrit

from exobench.selection.model import Data, Problem, Settings, residuals


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


def verdict_of(problem: Problem, data: Data, model: Mapping, scales, settings: Settings) -> dict:
    """:func:`unexplained` for a settled model: its held-out residuals, and its full-data
    residuals for the drift test (held-out folds are contiguous blocks of each trial, so each
    fold's own fitting error would be a step along the trial)."""
    fitted = residuals(problem, data, model["effects"], model["values"], scales)
    return unexplained(problem, data, model["chosen"]["cv"]["residuals"], scales, settings, fitted)


def unexplained(problem: Problem, data: Data, held: Mapping[str, np.ndarray], scales,
                settings: Settings, fitted: Mapping | None = None) -> dict:  # fmt: skip
    """Structure left in the held-out residuals, against the data's own noise as the null.

    Per observable: RMS (the goodness-of-fit floor, ``fit_floor`` × the noise's RMS), the
    share carried by each feature (phase, angle, velocity, force …) and the autocorrelation,
    each against the (1 − α/m) level of the same statistic on noise-only windows of the same
    shape (m = number of tests, a normal fit to the null draws); where the problem gives each
    unit's time in its trial (``trend``), a slow drift of every observable over the trial
    (:func:`drift` of the ``fitted`` full-data residuals where given, a t test at the same
    level). A test counts only when the
    structure it finds is also large: its RMS at least ``min_share`` of the observable's spread
    (structure below that is smaller than any finding this project reports); a drift, when the
    change it makes over the trial exceeds ``fit_floor`` noise scales (a sensor drifting by a
    few newtons is a finding however large the observable's spread over the springs).
    """
    if problem.noise is None:
        rows = [
            {"observable": obs, "correlates_with": "overall",
             "statistic": float(np.sqrt(np.nanmean(r**2))), "threshold": settings.fit_floor}
            for obs, r in held.items()
        ]  # fmt: skip
        return verdict_from_tests(rows)
    features = problem.features(data)
    noise = problem.noise(data)
    spread = {obs: measured_spread(problem, data, problem.sized_by.get(obs, obs)) / scales[obs]
              for obs in held}  # fmt: skip
    rng = np.random.default_rng([settings.seed, 11])
    tests = []
    for obs in problem.exact:  # no noise null: the fit floor, and min_share of the spread
        rms = float(np.sqrt(np.nanmean(held[obs] ** 2)))
        tests.append((obs, "overall", rms, None, rms, settings.min_share * spread[obs]))
    for obs, res in held.items():
        if obs not in noise:
            continue
        feats = features.get(obs, {})
        if res.ndim > 1:  # the samples that count (masked ones are NaN in every unit)
            cols = np.isfinite(res).any(axis=0)
            res = res[:, cols]
            feats = {k: v[:, cols] for k, v in feats.items()}
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
    drifts = []
    if problem.trend is not None:
        when = problem.trend(data)
        for obs, res in (fitted or held).items():
            value, df, size = drift(res, when, data.trial)
            drifts.append((obs, value, df, size, settings.fit_floor))
    count = max(len(tests) + len(drifts), 1)
    z = ndtri(1.0 - settings.alpha / count)
    rows = []
    for obs, value, df, size, floor in drifts:  # two-sided t test of the slope
        limit = float(stdtrit(df, 1.0 - settings.alpha / (2 * count))) if df > 0 else np.inf
        rows.append({"observable": obs, "correlates_with": "trial time", "statistic": value,
                     "threshold": limit, "size": float(size), "size_floor": float(floor),
                     "flag": bool(value > limit and size > floor)})  # fmt: skip
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
    for row in rows:
        row["decision"] = decision(row)
    return verdict_from_tests(rows)


def decision(row: Mapping) -> str:
    """Why a structure test flags or not: its statistic against the noise threshold, and the
    structure's size against the floor (``min_share`` of the observable's spread)."""
    above = row["statistic"] > row["threshold"]
    versus = f"{row['statistic']:.3g} {'above' if above else 'within'} {row['threshold']:.3g}"
    if not above:
        return f"not flagged: statistic {versus}, the noise allows it"
    if "size_floor" not in row or row["size"] > row["size_floor"]:
        return f"flagged: statistic {versus}"
    floor = "min_share of the observable's spread"
    if row["correlates_with"] == "trial time":
        floor = "fit_floor noise scales of change over the trial"
    return (
        f"not flagged: statistic {versus}, but the structure it finds ({row['size']:.3g} noise "
        f"units) is below the size floor ({row['size_floor']:.3g}: {floor})"
    )


def drift(res: np.ndarray, when: np.ndarray, trial: np.ndarray) -> tuple[float, int, float]:
    """A slow drift over each trial: the pooled within-trial slope of the units' mean residual
    against their time in the trial, as |t| over the stride-to-stride scatter about it (so
    whatever varies from unit to unit without a trend is its null), its degrees of freedom, and
    the change it makes over the mean trial span (in noise units)."""
    means = np.nanmean(res.reshape(res.shape[0], -1), axis=1)
    keep = np.isfinite(means) & np.isfinite(when)
    means, when = means[keep], when[keep]
    names, index = np.unique(trial[keep], return_inverse=True)
    counts = np.bincount(index, minlength=names.size).astype(float)
    centred_t = when - (np.bincount(index, when, names.size) / counts)[index]
    centred_m = means - (np.bincount(index, means, names.size) / counts)[index]
    sxx = float(np.sum(centred_t**2))
    df = int(means.size - names.size - 1)
    if sxx <= 0.0 or df <= 0:
        return 0.0, max(df, 0), 0.0
    slope = float(np.sum(centred_t * centred_m)) / sxx
    scatter = float(np.sum((centred_m - slope * centred_t) ** 2)) / df
    value = abs(slope) / np.sqrt(max(scatter, 1e-300) / sxx)
    first = np.full(names.size, np.inf)
    last = np.full(names.size, -np.inf)
    np.minimum.at(first, index, when)
    np.maximum.at(last, index, when)
    span = float(np.mean(last - first))
    return float(value), df, float(abs(slope) * span)


def measured_spread(problem: Problem, data: Data, obs: str) -> float:
    """Standard deviation of a measured observable over the samples that count."""
    values = data.arrays[problem.measured[obs]]
    mask = data.arrays.get(f"mask_{obs}")
    return float(np.std(values[mask] if mask is not None else values))


def verdict_from_tests(rows: list[dict]) -> dict:
    """The flag and the flagged test furthest beyond its threshold (else the closest one)."""
    for row in rows:
        row.setdefault("flag", row["statistic"] > row["threshold"])
        row.setdefault("decision", decision(row))
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
