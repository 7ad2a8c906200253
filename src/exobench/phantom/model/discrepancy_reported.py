"""Model discrepancy against the medians W.S.B. et al. report (no recordings, only numbers).

Units are the reported springs; observables are the stance metrics each spring reports. With
k_θ from eq. (2.2), the series predictions are: exoskeleton stiffness (1/k_θ + 1/k_frame)⁻¹,
phantom stiffness (1/k_exo + 1/k_interface)⁻¹, peak moment = phantom stiffness × phantom stance
flexion, exoskeleton stance flexion = peak moment / exoskeleton stiffness. The rigid theory has
both compliances at zero and a phantom that follows its programme: the same stance flexion
for every spring. Drive compliance lets the hexapod's ankle yield to the load: the knee then
loses M·(D / (l₁·l₂·sin θ))² / k_drive of flexion (virtual work of the two-link leg with the
ankle on the vertical through the hip; D the hip–ankle distance), θ the knee's flexion at the
stance peak (its flexion at the clutch's engagement plus the stance flexion).

Each number's stated uncertainty comes from the study: its rounding (half its last digit). The
study states no spread for these medians (its standard deviations are drawn in its figures only)
and, without one, its n (126 strides) gives no sampling error. The fits weigh the metrics'
relative (log) errors alike, over one scale σ̂ estimated from the residuals of the largest
candidate model, σ̂² = RSS/(n − p) (as Mallows' C_p does when no noise is known), and the phantom
flexion over its rounding.

Ten numbers and three candidate parameters: the engine selects by AIC (two springs cannot be
split into folds), so the errors it reports are each number's held-out error instead: the number
predicted by the model fitted to the other numbers. A held-out error is beyond the number's
stated uncertainty when it exceeds its rounding plus what the other numbers' roundings move the
prediction (each moved by its rounding, the moves added: the most rounding can do); such a miss
is left unexplained, and the effects are then fitted but not claimed. An effect is a candidate
only when every parameter rests on more than one number (leaving any one number out leaves it
determined) and not only on a difference the study reports as not significant. A quantity no
candidate model predicts (the phantom flexion, without the drive's compliance) is an input,
not a number in the table.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence

import numpy as np
import pandas as pd

from exobench import selection, studies
from exobench.phantom.chain.metrics import STANCE_METRICS
from exobench.phantom.model import effects
from exobench.phantom.reference import rounding
from exobench.phantom.rig import Rig
from exobench.selection.report import cause_sentence, rmse_change

FLEXION = "phantom_stance_flexion_deg"
UNITS = {**{m: "log" for m in STANCE_METRICS}, FLEXION: "deg"}
NATIVE_UNITS = {
    "peak_moment_Nm": "N·m",
    "phantom_stiffness_Nm_per_rad": "N·m/rad",
    "exo_stiffness_Nm_per_rad": "N·m/rad",
    "exo_stance_flexion_deg": "deg",
    FLEXION: "deg",
}
NAMES = {
    "peak_moment_Nm": "peak knee moment",
    "phantom_stiffness_Nm_per_rad": "phantom stiffness",
    "exo_stiffness_Nm_per_rad": "exoskeleton stiffness",
    "exo_stance_flexion_deg": "exoskeleton stance flexion",
    FLEXION: "phantom stance flexion",
}
# Differences across springs the study itself reports as not statistically significant (§3.1:
# the phantom's stance flexion), with where it says so.
NOT_SIGNIFICANT = {FLEXION: "§3.1"}
# A Jacobian column smaller than this share of its full-data size is zero: the parameter is
# undetermined by the numbers left.
UNDETERMINED = 1e-8


def medians(reported: pd.DataFrame, column: str = "value") -> pd.DataFrame:
    """Reported medians per spring (rows) for the phantom flexion and the predicted metrics
    (``column`` 'rounding': the rounding of each instead)."""
    rows = reported.dropna(subset=["spring_stiffness_N_per_m"]).copy()
    rows["rounding"] = rows["value"].map(rounding)
    rows["value"] = pd.to_numeric(rows["value"])
    table = rows.pivot(index="spring_stiffness_N_per_m", columns="metric", values=column)
    return table[[FLEXION, *STANCE_METRICS]].dropna()


def engagement_deg(cycle: pd.DataFrame, clutch_on_pct: float) -> float:
    """The knee's flexion when the clutch engages, from the reference mean cycle (columns
    gait_cycle_pct, knee_flexion_deg)."""
    pct = cycle["gait_cycle_pct"].to_numpy(float)
    return float(np.interp(clutch_on_pct, pct, cycle["knee_flexion_deg"].to_numpy(float)))


def drive_compliance_rad_per_Nm(flexion_rad, k_drive_N_per_m: float, rig: Rig):
    """Knee-equivalent compliance of a vertical ankle drive: (D / (l₁·l₂·sin θ))² / k_drive."""
    l1, l2 = rig.thigh_length_m, rig.shank_length_m
    d = np.sqrt(l1**2 + l2**2 + 2 * l1 * l2 * np.cos(flexion_rad))
    return (d / (l1 * l2 * np.sin(flexion_rad))) ** 2 / k_drive_N_per_m


def _counted(data: selection.Data) -> np.ndarray:
    """The springs whose phantom flexion counts (all but a held-out one)."""
    return data.arrays.get(f"mask_{FLEXION}", np.ones(data.units, bool))


def _series(state: dict, data: selection.Data) -> dict:
    """Series-stiffness predictions of the stance metrics for the state's compliances; the
    programme (the flexion without load) is the mean over the counted springs."""
    k_theta = data.arrays["k_theta_Nm_per_rad"]
    exo = 1.0 / (1.0 / k_theta + 1.0 / state["k_frame_Nm_per_rad"])
    phantom = 1.0 / (1.0 / exo + 1.0 / state["k_interface_Nm_per_rad"])
    flexion = np.deg2rad(data.arrays[FLEXION])
    moment = phantom * flexion
    counted = _counted(data)
    loss = np.zeros_like(flexion)
    if np.isfinite(state["k_drive_N_per_m"]):
        peak = data.constants["engagement_rad"] + flexion
        loss = drive_compliance_rad_per_Nm(peak, state["k_drive_N_per_m"], data.constants["rig"])
        loss = loss * moment
    programme = np.mean((flexion + loss)[counted])  # the same programme for every spring
    return {
        **state,
        "peak_moment_Nm": np.log(moment),
        "phantom_stiffness_Nm_per_rad": np.log(phantom),
        "exo_stiffness_Nm_per_rad": np.log(exo),
        "exo_stance_flexion_deg": np.log(np.rad2deg(moment / exo)),
        FLEXION: np.rad2deg(programme - loss),
    }


def baseline(data: selection.Data) -> dict:
    """Rigid theory: rigid interface and frame, a phantom that follows its programme."""
    rigid = {"k_interface_Nm_per_rad": np.inf, "k_frame_Nm_per_rad": np.inf,
             "k_drive_N_per_m": np.inf}  # fmt: skip
    return _series(rigid, data)


def _compliance(name: str):
    def transform(state, values, data):
        return _series({**state, name: values[name]}, data)

    return transform


P = selection.Parameter
REGISTRY = {
    "interface_compliance": selection.Effect(
        "interface_compliance",
        effects.REGISTRY["interface_compliance"].description,
        effects.REGISTRY["interface_compliance"].parameters,
        ("peak_moment_Nm", "phantom_stiffness_Nm_per_rad", "exo_stance_flexion_deg"),
        _compliance("k_interface_Nm_per_rad"),
    ),
    "frame_compliance": selection.Effect(
        "frame_compliance",
        effects.REGISTRY["frame_compliance"].description,
        effects.REGISTRY["frame_compliance"].parameters,
        tuple(STANCE_METRICS),
        _compliance("k_frame_Nm_per_rad"),
    ),
    "drive_compliance": selection.Effect(
        "drive_compliance",
        "a compliant ankle drive (the phantom does not follow its programme under load)",
        (
            P(
                "k_drive_N_per_m",
                "N/m",
                1e3,
                1e9,
                "vertical stiffness of hexapod, fixture and foot",
                start=3e5,
            ),
        ),
        (FLEXION,),
        _compliance("k_drive_N_per_m"),
    ),
}


def observed(registry: Mapping[str, selection.Effect]) -> list[str]:
    """The observables the engine compares: the stance metrics, and the phantom flexion when a
    candidate moves it (else only the programme, fitted to it, would)."""
    moved = {o for e in registry.values() for o in e.observables}
    return [o for o in UNITS if o in STANCE_METRICS or o in moved]


def problem(candidates: Sequence[str] | None = None) -> selection.Problem:
    """The reported-medians problem for the shared engine (``candidates``: the registry
    effects it may select, all by default)."""
    registry = {n: e for n, e in REGISTRY.items() if candidates is None or n in candidates}
    return selection.Problem(
        group="phantom_reported",
        registry=registry,
        baseline=baseline,
        measured={m: f"measured_{m}" for m in observed(registry)},
        units=UNITS,
        baseline_name=f"rigid theory ({studies.PHANTOM.key} eqs. 2.1–2.2)",
        names=NAMES,
    )


def observations(
    reported: pd.DataFrame, rig: Rig, engagement_deg: float
) -> tuple[selection.Data, dict]:
    """Springs as units, the reported medians as measurements, and their scales (the metrics'
    log errors over 1 until :func:`fit_scale` sizes them, the flexion over its rounding);
    ``engagement_deg`` the knee's flexion when the clutch engages."""
    table = medians(reported)
    springs = table.index.to_numpy(float)
    arrays = {
        FLEXION: table[FLEXION].to_numpy(float),
        "k_theta_Nm_per_rad": rig.joint_stiffness(springs),
        **{f"measured_{m}": np.log(table[m].to_numpy(float)) for m in STANCE_METRICS},
        f"measured_{FLEXION}": table[FLEXION].to_numpy(float),
    }
    roundings = medians(reported, "rounding")
    scales = {**dict.fromkeys(STANCE_METRICS, 1.0), FLEXION: float(roundings[FLEXION].max())}
    constants = {"rig": rig, "engagement_rad": float(np.deg2rad(engagement_deg))}
    data = selection.Data(arrays, np.zeros(springs.size, int), springs, constants)
    return data, scales


def without(data: selection.Data, observable: str, unit: int) -> selection.Data:
    """The data with one reported number left out (its observable's mask false there)."""
    masks = {f"mask_{o}": data.arrays.get(f"mask_{o}", np.ones(data.units, bool)).copy()
             for o in UNITS}  # fmt: skip
    masks[f"mask_{observable}"][unit] = False
    return selection.Data({**data.arrays, **masks}, data.trial, data.order, data.constants)


def _moved(engine: selection.Problem, data, effect: str, scales) -> dict[str, np.ndarray]:
    """How much every counted number's scaled residual moves per unit change of each of an
    effect's (scaled) parameters at its start value: parameter -> (observables, units)."""
    values = {p.name: p.initial() for p in engine.registry[effect].parameters}
    base = selection.residuals(engine, data, [effect], values, scales)
    out = {}
    for p in engine.registry[effect].parameters:
        step = 1e-3
        moved = dict(values, **{p.name: values[p.name] * np.exp(step) if p.log
                                else values[p.name] + step})  # fmt: skip
        res = selection.residuals(engine, data, [effect], moved, scales)
        out[p.name] = np.array([np.nan_to_num((res[o] - base[o]) / step) for o in UNITS])
    return out


def support(data: selection.Data, scales: Mapping) -> dict[str, dict]:
    """What each registry effect's parameters rest on: the reported numbers they move, whether
    leaving one number out leaves them undetermined (that number, or None), and whether every
    number they move is one whose difference across springs the study reports as not
    significant; effect -> parameter -> {"numbers", "single", "not_significant"}."""
    engine = problem()
    springs = data.order
    out = {}
    for effect in REGISTRY:
        full = _moved(engine, data, effect, scales)
        entry = {}
        for name, moves in full.items():
            size = np.abs(moves).max()
            moving = np.argwhere(np.abs(moves) > UNDETERMINED * size)
            numbers = [(list(UNITS)[k], float(springs[i])) for k, i in moving]
            single = None
            for o, spring in numbers:
                left = without(data, o, int(np.flatnonzero(springs == spring)[0]))
                if np.abs(_moved(engine, left, effect, scales)[name]).max() <= UNDETERMINED * size:
                    single = (o, spring)
                    break
            observables = sorted({o for o, _ in numbers})
            entry[name] = {
                "numbers": [{"metric": o, "spring_stiffness_N_per_m": s} for o, s in numbers],
                "single": None if single is None else {
                    "metric": single[0], "spring_stiffness_N_per_m": single[1]},
                "not_significant": bool(observables)
                and all(o in NOT_SIGNIFICANT for o in observables),
            }  # fmt: skip
        out[effect] = entry
    return out


def refusal(data: selection.Data, entry: Mapping) -> str | None:
    """Why an effect is not a candidate, in words (None when every parameter has support)."""
    reasons = []
    for name, s in entry.items():
        moved = sorted({n["metric"] for n in s["numbers"]})
        subject = "it" if len(entry) == 1 else name
        if s["single"] is not None:
            reasons.append(f"{subject} rests on a single number: {_single(data, s['numbers'])}")
        if s["not_significant"]:
            where = ", ".join(sorted({NOT_SIGNIFICANT[m] for m in moved}))
            words = " and ".join(NAMES[m] for m in moved)
            reasons.append(
                f"{studies.PHANTOM.key} report the differences of the {words} across springs as "
                f"not statistically significant ({where})"
            )
    return "; ".join(reasons) if reasons else None


def _single(data: selection.Data, numbers: Sequence[Mapping]) -> str:
    """The one number a parameter rests on, in words: a difference between two springs' values
    of one metric, or the number itself."""
    metrics = {n["metric"] for n in numbers}
    if len(numbers) == 2 and len(metrics) == 1:
        (metric,) = metrics
        values = _native(metric, data.arrays[f"measured_{metric}"])
        springs = [n["spring_stiffness_N_per_m"] for n in numbers]
        rows = [int(np.flatnonzero(data.order == s)[0]) for s in springs]
        difference = abs(values[rows[0]] - values[rows[1]])
        return (
            f"the difference of the {NAMES[metric]} between the {springs[0] / 1e3:g} and "
            f"{springs[1] / 1e3:g} kN/m springs ({difference:.2g} {NATIVE_UNITS[metric]}; "
            "leaving either value out leaves it undetermined)"
        )
    return "the " + ", ".join(
        f"{NAMES[n['metric']]} at {n['spring_stiffness_N_per_m'] / 1e3:g} kN/m" for n in numbers
    )


def held_out(data, scales, effects: Sequence[str], start: Mapping[str, float] | None,
             observables: Sequence[str]) -> dict[str, np.ndarray]:  # fmt: skip
    """Each reported number predicted by the model fitted to the other numbers: observable ->
    predictions per spring (the observable's unit, log for the metrics)."""
    engine = problem()
    out = {o: np.full(data.units, np.nan) for o in observables}
    for o in observables:
        for i in range(data.units):
            left = without(data, o, i)
            values, _ = selection.fit(engine, left, effects, scales, start)
            out[o][i] = selection.predict(engine, left, effects, values)[o][i]
    return out


def _native(observable: str, values: np.ndarray) -> np.ndarray:
    return np.exp(values) if UNITS[observable] == "log" else values


def fit_scale(data: selection.Data, scales: Mapping, candidates: Sequence[str]) -> float:
    """σ̂ of the metrics' log errors: √(RSS/(n − p)) of the largest candidate model fitted with
    them weighed alike (the study states no spread; Mallows' C_p sizes the noise so)."""
    engine = problem(candidates)
    values, _ = selection.fit(engine, data, candidates, scales, None)
    res = selection.residuals(engine, data, candidates, values, scales)
    metrics = [np.ravel(res[o]) * scales[o] for o in res if o in STANCE_METRICS]
    flat = np.concatenate(metrics)
    flat = flat[np.isfinite(flat)]
    return float(np.sqrt(np.sum(flat**2) / max(flat.size - len(values), 1)))


def _shifted(data: selection.Data, observable: str, unit: int, step: float) -> selection.Data:
    """The data with one reported number moved by ``step`` (a flexion also as the input the
    predictions take)."""
    arrays = dict(data.arrays)
    keys = [f"measured_{observable}"] + ([FLEXION] if observable == FLEXION else [])
    for key in keys:
        arrays[key] = arrays[key].copy()
        arrays[key][unit] += step
    return selection.Data(arrays, data.trial, data.order, data.constants)


def stated_uncertainty(data, scales, effects: Sequence[str], start, roundings: pd.DataFrame,
                       held: Mapping[str, np.ndarray]) -> dict[str, np.ndarray]:  # fmt: skip
    """Each held-out number's stated uncertainty in its own unit: its rounding plus the change
    of its held-out prediction when each other number moves by its rounding, summed (the most
    the roundings can do). ``held``: observable -> held-out predictions of the model."""
    engine = problem()
    inputs = [(q, j) for q in (*STANCE_METRICS, FLEXION) for j in range(data.units)]
    out = {}
    for o, predictions in held.items():
        bound = roundings[o].to_numpy(float).copy()
        for i in range(data.units):
            base = float(_native(o, predictions[i : i + 1])[0])
            for q, j in inputs:
                if (q, j) == (o, i):
                    continue
                value = float(_native(q, data.arrays[f"measured_{q}"][j : j + 1])[0])
                r = float(roundings[q].iloc[j])
                step = np.log1p(r / value) if UNITS[q] == "log" else r
                left = without(_shifted(data, q, j, step), o, i)
                fitted, _ = selection.fit(engine, left, effects, scales, start)
                moved = selection.predict(engine, left, effects, fitted)[o][i : i + 1]
                bound[i] += abs(float(_native(o, moved)[0]) - base)
        out[o] = bound
    return out


def number_rows(data, held: Mapping[str, Mapping[str, np.ndarray]], roundings,
                bounds: Mapping[str, np.ndarray]) -> list[dict]:  # fmt: skip
    """One row per reported number a model predicts: its value, rounding, stated uncertainty
    of its held-out error (``bounds``) and each model's held-out prediction and error in the
    number's own unit. ``held``: model -> observable -> predictions."""
    rows = []
    for o in bounds:
        measured = _native(o, data.arrays[f"measured_{o}"])
        for i, spring in enumerate(data.order):
            row = {
                "metric": o,
                "name": NAMES[o],
                "spring_stiffness_N_per_m": float(spring),
                "unit": NATIVE_UNITS[o],
                "reported": float(measured[i]),
                "rounding": float(roundings.loc[spring, o]),
                "stated_uncertainty": float(bounds[o][i]),
            }
            for model, predictions in held.items():
                value = float(_native(o, predictions[o])[i])
                row[model] = value
                row[f"{model}_error"] = value - row["reported"]
            row["beyond"] = abs(row["extended_error"]) > row["stated_uncertainty"]
            rows.append(row)
    return rows


def as_written(row: Mapping) -> str:
    """A reported number with the digits the study gives ('8.0', '355.6')."""
    digits = max(0, round(-np.log10(2 * row["rounding"])))
    return f"{row['reported']:.{digits}f}"


def misses(rows: Sequence[Mapping]) -> dict:
    """The engine's ``unexplained`` keys from the held-out misses: one test per number, its
    held-out error over its stated uncertainty against 1, flagged beyond it."""
    tests = []
    for n in rows:
        ratio = abs(n["extended_error"]) / n["stated_uncertainty"]
        where = f"{n['spring_stiffness_N_per_m'] / 1e3:g} kN/m"
        told = (f"{n['extended']:.4g} against {as_written(n)} ± {n['stated_uncertainty']:.2g} "
                f"{n['unit']} at {where}, {ratio:.3g} × the stated uncertainty")  # fmt: skip
        plain = f"**flagged**: {told}" if n["beyond"] else f"within its stated uncertainty: {told}"
        tests.append({"observable": n["metric"], "spring_stiffness_N_per_m": n[
            "spring_stiffness_N_per_m"], "correlates_with": "stated uncertainty",
                      "statistic": ratio, "threshold": 1.0, "flag": bool(n["beyond"]),
                      "decision": plain.replace("**", ""), "plain": plain})  # fmt: skip
    flagged = [t for t in tests if t["flag"]]
    worst = max(flagged or tests, key=lambda t: t["statistic"], default=None)
    flag = bool(flagged)
    return {"flag": flag, "observable": worst["observable"] if flag else None,
            "correlates_with": "stated uncertainty" if flag else None,
            "statistic": worst["statistic"] if worst else None, "threshold": 1.0,
            "tests": tests}  # fmt: skip


def held_out_gain(data, scales, held: Mapping[str, Mapping[str, np.ndarray]],
                  observables: Sequence[str]) -> dict:  # fmt: skip
    """The engine's ``gain`` keys from the held-out predictions of the engine's observables: RMS
    error per observable (its unit) and the mean squared scaled error, of the rigid theory and
    the selected model."""
    out = {"held_out": True, "held_out_by": "leaving one reported number out"}
    losses = {}
    for key in ("baseline", "extended"):
        errors = {o: held[key][o] - data.arrays[f"measured_{o}"] for o in observables}
        out[f"{key}_rmse"] = {f"{o}_{UNITS[o]}": float(np.sqrt(np.mean(e**2)))
                              for o, e in errors.items()}  # fmt: skip
        losses[key] = float(np.mean([np.mean((e / scales[o]) ** 2) for o, e in errors.items()]))
        out[f"{key}_loss"] = losses[key]
    out["reduction_pct"] = 100.0 * (1.0 - losses["extended"] / losses["baseline"])
    return out


def analyse(reported: pd.DataFrame, rig: Rig, settings: Mapping, source: str,
            engagement_deg: float) -> dict:  # fmt: skip
    """Discrepancy report for the reported medians (shared engine and schema), its errors held
    out one number at a time, with the effects whose parameters the numbers cannot carry left
    out of the candidates (``not_claimed``)."""
    data, scales = observations(reported, rig, engagement_deg)
    roundings = medians(reported, "rounding")
    backing = support(data, scales)
    refused = {e: why for e in REGISTRY if (why := refusal(data, backing[e])) is not None}
    candidates = [e for e in REGISTRY if e not in refused]
    sigma = fit_scale(data, scales, candidates)
    scales = {**scales, **dict.fromkeys(STANCE_METRICS, sigma)}
    engine = selection.Settings.from_config(settings["engine"], settings["seed"])
    report = selection.analyse(problem(candidates), data, scales, engine, source)
    values = {k: v for e in report["effects_found"] + report["tentative"]
              for k, v in e["parameters"].items()}  # fmt: skip
    chosen = report["selected"]
    observables = report["observable_order"]
    held = {
        "baseline": held_out(data, scales, [], None, observables),
        "extended": held_out(data, scales, chosen, values, observables),
    }
    report["gain"] = held_out_gain(data, scales, held, observables)
    bounds = stated_uncertainty(data, scales, chosen, values, roundings, held["extended"])
    report["numbers"] = number_rows(data, held, roundings, bounds)
    report["unexplained"] = misses(report["numbers"])
    if report["unexplained"]["flag"]:  # the engine's rule: not claimed while misses stand
        report["tentative"] = [*report["effects_found"], *report["tentative"]]
        report["effects_found"] = []
    report["cause"] = cause(problem(candidates), report)
    report["fit_scale_log"] = sigma
    report["uncertainty"] = (
        "each reported number's stated uncertainty is its rounding (half its last digit): the "
        "study states no spread for these medians, and without one its n gives no sampling "
        "error; a held-out error is beyond it when it exceeds the rounding plus what the other "
        "numbers' roundings move the prediction. The fits weigh the metrics' relative errors "
        f"alike, over σ̂ = {sigma:.3g} log units estimated from the largest candidate model's "
        "residuals (Mallows' C_p), and the phantom flexion over its rounding"
    )
    report["support"] = backing
    report["not_claimed"] = [
        not_claimed(data, scales, name, why, chosen, values) for name, why in refused.items()
    ]
    predicted = selection.predict(problem(), data, chosen, values)
    report["predictions"] = [
        {"spring_stiffness_N_per_m": float(spring),
         **{m: float(_native(m, predicted[m])[i]) for m in UNITS}}
        for i, spring in enumerate(data.order)
    ]  # fmt: skip
    return report


def cause(engine: selection.Problem, report: Mapping) -> str:
    """The engine's cause sentence, told with the held-out errors; while numbers are missed
    beyond their stated uncertainty, those misses instead of a residual test."""
    found = [e["effect"] for e in report["effects_found"]]
    tentative = [e["effect"] for e in report["tentative"]]
    verdict = report["unexplained"]
    if not verdict["flag"]:
        return cause_sentence(engine, found, tentative, report["gain"], verdict)
    missed = [n for n in report["numbers"] if n["beyond"]]
    worst = max(missed, key=lambda n: abs(n["extended_error"]) / n["stated_uncertainty"])
    change = rmse_change(engine, report["gain"])
    subject = f"The {engine.baseline_name} misses the data"
    if tentative:
        named = " and ".join(engine.registry[e].description for e in tentative)
        verbs = ("improve", "are") if len(tentative) > 1 else ("improves", "is")
        subject += f"; {named} {verbs[0]} the fit ({change}) but {verbs[1]} not claimed"
    ratio = abs(worst["extended_error"]) / worst["stated_uncertainty"]
    return (
        f"{subject}: {len(missed)} of {len(report['numbers'])} reported numbers, each held "
        f"out, are missed by more than their stated uncertainty, the {worst['name']} at "
        f"{worst['spring_stiffness_N_per_m'] / 1e3:g} kN/m most ({worst['extended']:.4g} "
        f"against {as_written(worst)} ± {worst['stated_uncertainty']:.2g} {worst['unit']}, "
        f"{ratio:.3g} times). Left unexplained: those misses; no registry effect accounts for "
        "them."
    )


def not_claimed(data, scales, effect: str, reason: str, chosen, values) -> dict:
    """A refused effect, the reason, and what its parameters come to when fitted anyway beside
    the selected model (an estimate only: the numbers cannot carry it)."""
    engine = problem()
    model = [*chosen, effect]
    fitted, _ = selection.fit(engine, data, model, scales, values)
    parameters = REGISTRY[effect].parameters
    return {
        "effect": effect,
        "description": REGISTRY[effect].description,
        "reason": reason,
        "fitted_anyway": {p.name: fitted[p.name] for p in parameters},
        "units": {p.name: p.unit for p in parameters},
        "bounds": {p.name: [p.low, p.high] for p in parameters},
    }
