"""Model discrepancy engine: where the rigid theory fails, which physical effect explains it.

The baseline is seed 000's rigid theory (eqs. 2.1–2.2): the exoskeleton angle equals the phantom
angle and M = k_θ·Δθ while the clutch is engaged. Candidate extensions add, in series, the
effects of :mod:`exoskeleton` (interface compliance and damping, frame compliance, frame
friction). Every model is driven by the measured phantom angle and predicts three observables
over the engaged window of each stride — knee moment, exoskeleton-angle change and spring-length
change — so that interface and frame compliance, which both soften the joint, are told apart by
where the deflection shows (between phantom and bars, or between bars and spring). Parameters
are fitted by least squares on training strides, models are scored on held-out stride blocks,
and the simplest model within one standard error of the best cross-validated score is chosen.
"""

from __future__ import annotations

import itertools
from collections.abc import Mapping, Sequence
from dataclasses import dataclass

import numpy as np
from scipy.optimize import least_squares

from exobench.phantom import exoskeleton
from exobench.phantom.rig import Rig

# Effect -> (parameter, lower bound, upper bound) of the mechanics it switches on.
EFFECTS = {
    "interface_compliance": ("k_interface_Nm_per_rad", 2.0, 1e5),
    "interface_damping": ("c_interface_Nms_per_rad", 1e-3, 50.0),
    "frame_compliance": ("k_frame_Nm_per_rad", 10.0, 1e6),
    "frame_friction": ("friction_Nm", 1e-3, 10.0),
}
REQUIRES = {"interface_damping": "interface_compliance"}
CHANNELS = ("moment", "exo", "spring")
DESCRIPTIONS = {
    "interface_compliance": "interface compliance (soft tissue and straps in series between "
    "limb and exoskeleton bars)",
    "interface_damping": "interface damping (viscous loss in the soft tissue and straps)",
    "frame_compliance": "frame compliance (chain and clutch in series between bars and spring)",
    "frame_friction": "frame friction (Coulomb loss in the chain and clutch)",
}


@dataclass(frozen=True)
class Observations:
    """Engaged-window signals of the analysed strides, rows = strides, all relative to engagement.

    ``phantom`` is the absolute phantom angle (the model input); the other channels are changes
    since the first window sample.
    """

    phantom_rad: np.ndarray
    moment_Nm: np.ndarray
    exo_change_rad: np.ndarray
    spring_change_m: np.ndarray
    spring_N_per_m: np.ndarray
    pretension_N: np.ndarray
    trial: np.ndarray
    stride: np.ndarray
    dt_s: float

    def take(self, rows) -> Observations:
        """The observations of a subset of strides."""
        return Observations(
            self.phantom_rad[rows],
            self.moment_Nm[rows],
            self.exo_change_rad[rows],
            self.spring_change_m[rows],
            self.spring_N_per_m[rows],
            self.pretension_N[rows],
            self.trial[rows],
            self.stride[rows],
            self.dt_s,
        )

    @property
    def count(self) -> int:
        return self.phantom_rad.shape[0]


def candidate_sets() -> list[tuple[str, ...]]:
    """Every combination of effects that is physically meaningful (damping needs compliance)."""
    names = list(EFFECTS)
    sets = []
    for size in range(len(names) + 1):
        for combo in itertools.combinations(names, size):
            if all(REQUIRES.get(e) in combo for e in combo if e in REQUIRES):
                sets.append(combo)
    return sets


def predict(obs: Observations, values: Mapping[str, float], rig: Rig) -> dict[str, np.ndarray]:
    """Moment, exoskeleton-angle change and spring-length change of a model (baseline if empty)."""
    mech = exoskeleton.Mechanics(
        joint_stiffness_Nm_per_rad=rig.joint_stiffness(obs.spring_N_per_m),
        spring_stiffness_N_per_m=obs.spring_N_per_m,
        travel_m_per_rad=rig.spring_travel_m_per_rad,
        pretension_N=float(np.median(obs.pretension_N)),
        tensioner_knee_stiffness_Nm_per_rad=rig.chain_ratio**2 * rig.tensioner_stiffness_Nm_per_rad,
        **values,
    )
    state = exoskeleton.simulate(obs.phantom_rad, np.ones_like(obs.phantom_rad), obs.dt_s, mech)
    exo = state["exo_knee_angle_rad"]
    return {
        "moment": state["knee_moment_Nm"],
        "exo": exo - exo[:, :1],
        "spring": state["spring_extension_m"] - state["spring_extension_m"][:, :1],
    }


def measured(obs: Observations) -> dict[str, np.ndarray]:
    """The observed counterparts of :func:`predict`'s channels."""
    return {"moment": obs.moment_Nm, "exo": obs.exo_change_rad, "spring": obs.spring_change_m}


def channel_scales(obs: Observations) -> dict[str, float]:
    """Normalising scale of each channel: its spread over all strides and samples."""
    return {name: float(np.std(values)) or 1.0 for name, values in measured(obs).items()}


def normalised_residuals(obs, values, rig, scales) -> np.ndarray:
    """Stacked residuals of all channels, each divided by its scale."""
    pred, meas = predict(obs, values, rig), measured(obs)
    return np.concatenate([((pred[c] - meas[c]) / scales[c]).ravel() for c in CHANNELS])


def initial_values(obs: Observations, effects: Sequence[str], rig: Rig) -> dict[str, float]:
    """Start values from the observables: compliances as deflection-per-moment slopes."""
    moment = obs.moment_Nm
    interface = obs.phantom_rad - obs.phantom_rad[:, :1] - obs.exo_change_rad
    frame = obs.exo_change_rad - obs.spring_change_m / rig.spring_travel_m_per_rad
    guesses = {
        "k_interface_Nm_per_rad": slope_through_origin(interface, moment),
        "c_interface_Nms_per_rad": 0.5,
        "k_frame_Nm_per_rad": slope_through_origin(frame, moment),
        "friction_Nm": 0.2,
    }
    values = {}
    for effect in effects:
        name, low, high = EFFECTS[effect]
        values[name] = float(np.clip(guesses[name], low * 1.01, high * 0.99))
    return values


def slope_through_origin(x: np.ndarray, y: np.ndarray) -> float:
    """Least-squares slope of y = k·x (inf when x carries no signal)."""
    denominator = float(np.sum(x * x))
    slope = float(np.sum(x * y)) / denominator if denominator > 0 else np.inf
    return slope if slope > 0 else np.inf


def fit(obs: Observations, effects: Sequence[str], rig: Rig, scales) -> dict[str, float]:
    """Least-squares parameters of a candidate (log space, bounded)."""
    if not effects:
        return {}
    names = [EFFECTS[e][0] for e in effects]
    start = initial_values(obs, effects, rig)
    low = np.log([EFFECTS[e][1] for e in effects])
    high = np.log([EFFECTS[e][2] for e in effects])

    def objective(log_values):
        return normalised_residuals(
            obs, dict(zip(names, np.exp(log_values), strict=True)), rig, scales
        )

    result = least_squares(
        objective,
        np.log([start[n] for n in names]),
        bounds=(low, high),
        diff_step=1e-3,
        x_scale=1.0,
        max_nfev=200,
    )
    return dict(zip(names, np.exp(result.x).tolist(), strict=True))


def scores(obs: Observations, values, rig, scales) -> dict[str, float]:
    """Held-out errors: normalised score, moment RMSE and per-stride peak-moment error."""
    pred, meas = predict(obs, values, rig), measured(obs)
    residual = normalised_residuals(obs, values, rig, scales)
    peak_error = np.abs(pred["moment"].max(1) - meas["moment"].max(1))
    return {
        "score": float(np.sqrt(np.mean(residual**2))),
        "rmse_Nm": float(np.sqrt(np.mean((pred["moment"] - meas["moment"]) ** 2))),
        "peak_moment_error_Nm": float(np.mean(peak_error)),
    }


def folds(obs: Observations, count: int) -> np.ndarray:
    """Fold of every stride: contiguous stride blocks within each trial, so every fold spans
    all springs."""
    fold = np.zeros(obs.count, int)
    for trial in np.unique(obs.trial):
        rows = np.flatnonzero(obs.trial == trial)
        order = rows[np.argsort(obs.stride[rows])]
        fold[order] = np.arange(order.size) * count // order.size
    return fold


def cross_validate(obs, effects, rig, scales, count: int) -> dict[str, float]:
    """Mean held-out scores over stride-block folds, with the standard error of the score."""
    fold = folds(obs, count)
    per_fold = []
    for k in range(count):
        values = fit(obs.take(fold != k), effects, rig, scales)
        per_fold.append(scores(obs.take(fold == k), values, rig, scales))
    score = np.array([f["score"] for f in per_fold])
    return {
        "cv_score": float(score.mean()),
        "cv_score_se": float(score.std(ddof=1) / np.sqrt(count)),
        "cv_rmse_Nm": float(np.mean([f["rmse_Nm"] for f in per_fold])),
        "cv_peak_moment_error_Nm": float(np.mean([f["peak_moment_error_Nm"] for f in per_fold])),
    }


def aic(obs, values, rig, scales) -> float:
    """Akaike information criterion of a full-data fit (Gaussian normalised residuals)."""
    residual = normalised_residuals(obs, values, rig, scales)
    n = residual.size
    return float(n * np.log(np.mean(residual**2)) + 2 * len(values))


def select(candidates: list[dict]) -> dict:
    """One-standard-error rule: the fewest effects whose CV score is within 1 SE of the best."""
    best = min(candidates, key=lambda c: c["cv_score"])
    limit = best["cv_score"] + best["cv_score_se"]
    eligible = [c for c in candidates if c["cv_score"] <= limit]
    return min(eligible, key=lambda c: (len(c["effects"]), c["cv_score"]))


def bootstrap(obs, effects, rig, scales, draws: int, rng) -> dict[str, list[float]]:
    """95 % percentile intervals of the parameters, refitting on strides drawn with replacement."""
    if not effects:
        return {}
    samples = []
    for _ in range(draws):
        rows = rng.integers(0, obs.count, obs.count)
        samples.append(fit(obs.take(rows), effects, rig, scales))
    return {
        name: np.percentile([s[name] for s in samples], [2.5, 97.5]).tolist() for name in samples[0]
    }


def cause_sentence(found: list[dict], gain: Mapping[str, float]) -> str:
    """One sentence naming the effects, or that the rigid theory explains the data."""
    if not found:
        return "none: the rigid theory explains the data"
    parts = [DESCRIPTIONS[f["effect"]] for f in found]
    named = parts[0] if len(parts) == 1 else ", ".join(parts[:-1]) + " and " + parts[-1]
    return (
        f"The rigid theory fails because of {named}; adding "
        f"{'it' if len(parts) == 1 else 'them'} cuts the held-out knee-moment error by "
        f"{gain['reduction_pct']:.0f} %."
    )


def analyse(obs: Observations, rig: Rig, settings: Mapping, source: str) -> dict:
    """The discrepancy report (contract of issue 6) for one set of observations."""
    scales = channel_scales(obs)
    count = int(settings["folds"])
    candidates = []
    for effects in candidate_sets():
        values = fit(obs, effects, rig, scales)
        entry = {"effects": list(effects), "parameters": values}
        entry.update(cross_validate(obs, effects, rig, scales, count))
        entry["aic"] = aic(obs, values, rig, scales)
        candidates.append(entry)
    baseline = candidates[0]
    chosen = select(candidates)
    rng = np.random.default_rng(int(settings["seed"]))
    intervals = bootstrap(obs, chosen["effects"], rig, scales, int(settings["bootstrap"]), rng)
    found = [
        {
            "effect": effect,
            "parameters": {EFFECTS[effect][0]: chosen["parameters"][EFFECTS[effect][0]]},
            "ci95": {EFFECTS[effect][0]: intervals[EFFECTS[effect][0]]},
        }
        for effect in chosen["effects"]
    ]
    gain = {
        "baseline_cv_rmse_Nm": baseline["cv_rmse_Nm"],
        "extended_cv_rmse_Nm": chosen["cv_rmse_Nm"],
        "reduction_pct": 100.0 * (1.0 - chosen["cv_rmse_Nm"] / baseline["cv_rmse_Nm"]),
    }
    return {
        "source": source,
        "baseline": {
            "model": "rigid",
            "cv_rmse_Nm": baseline["cv_rmse_Nm"],
            "cv_score": baseline["cv_score"],
        },
        "candidates": candidates,
        "selected": chosen["effects"],
        "selection": "fewest effects within one standard error of the best cross-validated "
        f"normalised error ({count} stride-block folds across all springs)",
        "channel_scales": scales,
        "effects_found": found,
        "cause": cause_sentence(found, gain),
        "gain": gain,
    }


def observations(
    parts: Sequence[tuple[str, float, object, object]], settings: Mapping, dt_s: float
) -> Observations:
    """Engaged-window observations from (trial, spring, kinetics, strides) of each trial.

    Included strides only, at most ``max_strides_per_trial`` evenly spread ones per trial,
    samples in ``window_pct`` taken every ``step``.
    """
    start, end = (float(v) for v in settings["window_pct"])
    step, limit = int(settings["step"]), int(settings["max_strides_per_trial"])
    blocks = {
        k: [] for k in ("phantom", "moment", "exo", "spring", "force", "k", "trial", "stride")
    }
    for trial, spring, kinetics, strides in parts:
        kept = strides.loc[strides["included"], "stride"].to_numpy()
        kept = kept[np.unique(np.linspace(0, kept.size - 1, min(limit, kept.size)).astype(int))]
        rows = kinetics[kinetics["stride"].isin(kept)]
        count = rows["stride"].nunique()
        window = (rows["gait_cycle_pct"] >= start) & (rows["gait_cycle_pct"] < end)
        grid = {
            c: rows.loc[window, c].to_numpy().reshape(count, -1)[:, ::step]
            for c in (
                "knee_moment_Nm",
                "phantom_knee_angle_rad",
                "exo_knee_angle_rad",
                "spring_length_m",
                "spring_force_N",
                "stride",
            )
        }
        blocks["phantom"].append(grid["phantom_knee_angle_rad"])
        blocks["moment"].append(grid["knee_moment_Nm"])
        blocks["exo"].append(grid["exo_knee_angle_rad"] - grid["exo_knee_angle_rad"][:, :1])
        blocks["spring"].append(grid["spring_length_m"] - grid["spring_length_m"][:, :1])
        blocks["force"].append(grid["spring_force_N"][:, 0])
        blocks["k"].append(np.full(count, float(spring)))
        blocks["trial"].append(np.full(count, trial, dtype=object))
        blocks["stride"].append(grid["stride"][:, 0].astype(int))
    join = {k: np.concatenate(v) for k, v in blocks.items()}
    return Observations(
        join["phantom"],
        join["moment"],
        join["exo"],
        join["spring"],
        join["k"],
        join["force"],
        join["trial"],
        join["stride"],
        dt_s * step,
    )


def prediction_table(obs: Observations, report: Mapping, rig: Rig):
    """Measured, baseline and extended moment per sample of every observed stride (for figures)."""
    import pandas as pd

    chosen = next(c for c in report["candidates"] if c["effects"] == report["selected"])
    baseline = predict(obs, {}, rig)["moment"]
    extended = predict(obs, chosen["parameters"], rig)["moment"]
    samples = obs.phantom_rad.shape[1]
    return pd.DataFrame(
        {
            "trial": np.repeat(obs.trial.astype(str), samples),
            "spring_stiffness_N_per_m": np.repeat(obs.spring_N_per_m, samples),
            "stride": np.repeat(obs.stride, samples),
            "t_s": np.tile(np.arange(samples) * obs.dt_s, obs.count),
            "phantom_knee_angle_rad": obs.phantom_rad.ravel(),
            "measured_moment_Nm": obs.moment_Nm.ravel(),
            "baseline_moment_Nm": baseline.ravel(),
            "extended_moment_Nm": extended.ravel(),
        }
    )
