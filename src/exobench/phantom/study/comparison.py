"""Reproduction table: every number seed 000 reports against the workflow's result, with its role,
its tolerance and, for a miss, the reason.

Roles by the project's one role rule (``exobench.roles``): with a lab's recordings every number
is ``measured``; with the twin a number is ``derived`` when it is a function of other rows alone
(the flexion difference of the two springs; the 7.9° exoskeleton–phantom difference, the
phantom's flexion less the exoskeleton's, its reproduced side the median of the per-stride
difference), a ``calibration target`` when the twin was fitted to it (``calibration/residuals.csv``)
or to a row derived from it (the fit through the flexion difference makes both flexions targets),
a ``setting`` when what the twin was given determines it (the strides analysed by the protocol,
the strides kept by the chosen trajectories, pretension and the 5 N rule, the spring's net work
by the twin's lossless spring), else a ``prediction`` (out of sample). A
number is reproduced when |reproduced − reported| ≤ rounding + z(1 − α/2)·√2·SE: its rounding
(half its last digit) and the sampling error of two medians, SE the bootstrap standard error of
the reproduced one (strides resampled within their spring; per-trial counts resampled over
trials), the study's taken as uncertain as ours (the same protocol and about as many strides: it
states no spread). A bound (the study's "did not exceed") is reproduced when the reproduced
value stays within it.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass

import numpy as np
import pandas as pd

from exobench import roles
from exobench.phantom.reference import rounding
from exobench.phantom.study.kept import SPRING, included

COLUMNS = [
    "metric",
    SPRING,
    "key",
    "reported",
    "reproduced",
    "unit",
    "abs_error",
    "rel_error",
    *roles.ROLE_COLUMNS,
    "rounding",
    "reproduced_se",
    "tolerance",
    "within_tolerance",
    "twin",
    "reason",
    "source",
]
DIFFERENCES = {"phantom_stance_flexion_median_difference_deg": "phantom_stance_flexion_deg"}
BOUNDS = {"work_spring_net_abs_max_J": "work_spring_net_J"}  # |median| of every spring within it
COUNTS = {"strides_analysed": "analysed", "strides_kept": "included"}
# What the twin was given that determines a number (its role: setting).
SETTINGS = {
    "strides_analysed": "the twin's protocol: its strides less the ramp strides",
    "strides_kept": "the chosen trajectory spread (phantom.twin.flexion_sd_deg), the straps' "
    "pretension (phantom.twin.pretension_N), the study's 5 N spring-force rule (§2.4) and the "
    "calibrated effects, none shown chosen without the study's 126 in view",
    "work_spring_net_abs_max_J": "the twin's lossless spring: its net work over a stride is "
    "zero by construction",
}
FIXED = {"strides_analysed"}  # counts the protocol fixes exactly (no sampling spread)
# Numbers that are functions of other reported numbers: (metric, spring) -> the rows' keys.
DERIVED = {
    ("phantom_stance_flexion_median_difference_deg", None): (
        "phantom_stance_flexion_deg@3400",
        "phantom_stance_flexion_deg@21700",
    ),
    ("exo_phantom_peak_angle_difference_deg", 21700.0): (
        "phantom_stance_flexion_deg@21700",
        "exo_stance_flexion_deg@21700",
    ),
}
# Derived rows whose reproduced side is measured directly (a median of per-stride values).
DIRECT = {"exo_phantom_peak_angle_difference_deg"}


@dataclass(frozen=True)
class Medians:
    """Per-spring medians of every metric over the included strides (``point``), each with its
    bootstrap draws (``draws``), and per spring the strides analysed and included (``counts``,
    point and draws over the springs). Built by :func:`medians`."""

    point: dict
    draws: dict
    counts: dict
    springs: tuple

    def value(self, metric: str, spring: float, drawn: bool = False):
        """One reported number's counterpart (or its draws): a spring's median, the softest
        minus the stiffest spring's, the largest |median| over every spring, a count."""
        source = self.draws if drawn else self.point
        if metric in COUNTS:
            return self.counts[(COUNTS[metric], drawn)]
        if metric in DIFFERENCES:
            column = DIFFERENCES[metric]
            return source[(column, self.springs[0])] - source[(column, self.springs[-1])]
        if metric in BOUNDS:
            stack = np.stack([np.abs(source[(BOUNDS[metric], s)]) for s in self.springs])
            return stack.max(axis=0)
        return source.get((metric, spring), np.nan)

    def se(self, metric: str, spring: float) -> float:
        """Bootstrap standard error of :meth:`value`."""
        drawn = np.asarray(self.value(metric, spring, drawn=True), float)
        return float(np.std(drawn, ddof=1)) if drawn.size > 1 else np.nan


def resampled(values: np.ndarray, draws: int, rng: np.random.Generator) -> np.ndarray:
    """Medians (NaN skipped) of ``draws`` row resamples of ``values`` (n, m): shape (draws, m)."""
    picks = rng.integers(0, values.shape[0], size=(draws, values.shape[0]))
    median = np.nanmedian if np.isnan(values).any() else np.median
    return median(values[picks], axis=1)


def medians(strides: pd.DataFrame, columns: Sequence[str], draws: int, seed: int) -> Medians:
    """:class:`Medians` of a per-stride table (``included`` strides; analysed = a finite peak
    moment), each spring resampled with its own generator ``[seed, i]`` (i its rank), so two
    tables of the same strides in the same order draw the same strides (paired draws)."""
    point, drawn, per = {}, {}, {"analysed": [], "included": []}
    springs = tuple(sorted(strides[SPRING].unique()))
    for index, spring in enumerate(springs):
        rows = strides[strides[SPRING] == spring]
        per["analysed"].append(int(rows["peak_moment_Nm"].notna().sum()))
        kept = included(rows)
        per["included"].append(len(kept))
        values = kept[list(columns)].to_numpy(float)
        samples = resampled(values, draws, np.random.default_rng([seed, index]))
        for j, column in enumerate(columns):
            point[(column, spring)] = float(np.nanmedian(values[:, j]))
            drawn[(column, spring)] = samples[:, j]
    counts = {}
    rng = np.random.default_rng([seed, len(springs)])
    for name, values in per.items():
        array = np.asarray(values, float)
        counts[(name, False)] = float(np.median(array))
        counts[(name, True)] = resampled(array[:, None], draws, rng)[:, 0]
    return Medians(point, drawn, counts, springs)


def key(metric: str, spring) -> str:
    """A reported number's key: 'metric@spring' (e.g. 'peak_moment_Nm@3400'), or the metric."""
    return metric if pd.isna(spring) else f"{metric}@{float(spring):g}"


def provenance(metric: str, spring, targets: set | None, keys=()) -> roles.Provenance:
    """Role facts of a number (targets None: a lab); a target on a derived row marks its rows."""
    if targets is None:
        return roles.Provenance(lab=True)
    spring = None if pd.isna(spring) else float(spring)
    named = DERIVED.get((metric, spring), ())
    own = key(metric, spring)
    through = [d for d, rows in DERIVED.items() if own in rows and d in targets]
    matched = (
        ["phantom_calibrate's fit (calibration/residuals.csv)"]
        if (metric, spring) in targets
        else []
    )
    matched += [
        f"phantom_calibrate's fit through {d[0]} (calibration/residuals.csv)" for d in through
    ]
    return roles.Provenance(
        derived_from=named if named and set(named) <= set(keys) else (),
        matched_by=tuple(matched),
        determined_by=(SETTINGS[metric],) if metric in SETTINGS else (),
        rests_on=("the twin's calibrated effects",),
    )


def calibration_targets(residuals: pd.DataFrame) -> set:
    """The (metric, spring) the twin was fitted to (spring None for a number about all)."""
    springs = residuals[SPRING]
    return {
        (m, None if pd.isna(s) else float(s))
        for m, s in zip(residuals["metric"], springs, strict=True)
    }


def tolerance(metric: str, text, se: float, z: float) -> float:
    """rounding + z·√2·SE (a bound: its rounding)."""
    fixed = metric in BOUNDS or metric in FIXED
    spread = 0.0 if fixed or not np.isfinite(se) else se
    return rounding(text) + z * np.sqrt(2.0) * spread


def within(metric: str, reported: float, value: float, allowed: float) -> bool:
    """Whether a value reproduces a reported number: within the tolerance, or inside a bound."""
    if metric in BOUNDS:
        return bool(value <= abs(reported) + allowed)
    return bool(abs(value - reported) <= allowed)


def compare(
    reported: pd.DataFrame,
    chain: Medians,
    alpha: float,
    targets: set | None = None,
    twin: Medians | None = None,
    method: pd.DataFrame | None = None,
) -> pd.DataFrame:
    """One row per reported number (``reported`` read with its text kept): reported, reproduced,
    errors, role, rounding, SE, tolerance, whether reproduced, the twin's own prediction and the
    reason for a miss."""
    from statistics import NormalDist

    z = float(NormalDist().inv_cdf(1 - alpha / 2))
    keys = [key(m, s) for m, s in zip(reported["metric"], reported[SPRING], strict=True)]
    rows = []
    for entry in reported.to_dict("records"):
        metric, spring, text = entry["metric"], entry["spring_stiffness_N_per_m"], entry["value"]
        value = float(text)
        got = float(chain.value(metric, spring))
        se = chain.se(metric, spring)
        allowed = tolerance(metric, text, se, z)
        predicted = np.nan
        if twin is not None and (metric not in BOUNDS or twin.springs == chain.springs):
            predicted = float(twin.value(metric, spring))
        row = {
            "metric": metric,
            SPRING: spring,
            "key": key(metric, spring),
            "reported": value,
            "reproduced": got,
            "unit": entry["unit"],
            "abs_error": abs(got - value),
            "rel_error": abs(got - value) / abs(value),
            **_role(provenance(metric, spring, targets, keys), metric),
            "rounding": rounding(text),
            "reproduced_se": se,
            "tolerance": allowed,
            "within_tolerance": within(metric, value, got, allowed),
            "twin": predicted,
            "source": entry["source"],
        }
        twin_allowed = np.nan
        if twin is not None and np.isfinite(predicted):
            twin_allowed = tolerance(metric, text, twin.se(metric, spring), z)
        row["reason"] = "" if row["within_tolerance"] else reason(row, twin_allowed, method)
        rows.append(row)
    table = pd.DataFrame(rows, columns=COLUMNS)
    roles.check(table, "key", "paper_comparison.csv")
    return table


def _role(facts: roles.Provenance, metric: str) -> dict:
    """The role columns, saying where a derived row's reproduced side is measured directly."""
    columns = roles.columns(facts)
    if columns["role"] == "derived" and metric in DIRECT:
        columns["role_basis"] += "; its reproduced side, the median of the per-stride difference"
    return columns


def _with_unit(value: float, unit: str) -> str:
    """A value to 3 significant digits with its unit."""
    return f"{value:.3g}" + ("" if unit in ("1", "") else f" {unit}")


def reason(row: Mapping, twin_allowed: float, method: pd.DataFrame | None) -> str:
    """Why a number misses: the calibration leaves it, the twin's model mispredicts it, the chain
    departs from the twin's prediction, or nothing predicts it (left unexplained)."""
    got, twin, unit = row["reproduced"], row["twin"], row["unit"]
    if row["role"] == "setting":
        return f"set by {SETTINGS[row['metric']]}; the run gives {_with_unit(got, unit)}"
    source = "a lab's recordings" if row["role"] == "measured" else "the twin's recordings"
    if not np.isfinite(twin):
        return (
            f"left unexplained: {source} give {_with_unit(got, unit)}; the twin's "
            "calibration simulates the reported springs only, so nothing predicts this "
            "number"
        )
    twin_misses = not within(row["metric"], row["reported"], twin, twin_allowed)
    if twin_misses and row["role"] == "calibration target":
        text = (
            f"the calibration leaves it: the twin's best fit to every target gives "
            f"{_with_unit(twin, unit)} (calibration/residuals.csv)"
        )
    elif twin_misses:
        text = f"the twin's model predicts {_with_unit(twin, unit)}: the twin mispredicts it"
    else:
        text = (
            f"the twin predicts {_with_unit(twin, unit)}, within the tolerance, but "
            f"{source} give {_with_unit(got, unit)}"
        )
    check = _method_row(method, row)
    if check is not None and bool(check["beyond"]):
        side = {
            "chain": "the chain is wrong",
            "twin": "the twin is wrong",
            "both": "both are wrong",
        }.get(check["side"], "left unexplained")
        text += (
            f"; the chain's measurement ({_with_unit(got, unit)}) departs from the "
            f"prediction beyond their uncertainty and, against the twin's true value "
            f"({_with_unit(check['truth'], unit)}), {side} (method_check.csv)"
        )
    elif twin_misses and row["role"] != "measured":
        agreed = ", as predicted (method_check.csv)" if check is not None else ""
        text += f"; the chain measures {_with_unit(got, unit)} on its recordings{agreed}"
    return text


def _method_row(method: pd.DataFrame | None, row: Mapping):
    """The method check's row of the same number (None without one)."""
    if method is None or method.empty:
        return None
    same = method["metric"] == row["metric"]
    spring = row[SPRING]
    same &= method[SPRING].isna() if pd.isna(spring) else method[SPRING] == spring
    found = method[same]
    return None if found.empty else found.iloc[0]


def rate(table: pd.DataFrame, kinds: Sequence[str]) -> tuple[int, int]:
    """Numbers of the given roles reproduced, and their count."""
    rows = table[table["role"].isin(kinds)]
    return int(rows["within_tolerance"].sum()), len(rows)
