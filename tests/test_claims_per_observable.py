"""Claims per observable (issue 54, item 1): one observable's misfit silences no claim the others
support, and a located effect is claimed with the size its check found.

A toy group observes two curves per unit, y(x) and z(x), both scaled by one gain; the data carry
the gain and, in z only, a bump no registry effect or term makes. Data are generated here from a
printed seed; the truth is read only in the final assertions.
"""

from __future__ import annotations

import numpy as np
import pytest

from exobench import selection
from exobench.selection import beside

SEED = 23
X = np.linspace(0.0, 1.0, 40)
P = selection.Parameter


def _gain(state, values, data):
    return {o: state[o] * values["gain_1"] for o in state}


REGISTRY = {
    "gain": selection.Effect(
        "gain",
        "a gain error",
        (P("gain_1", "1", 0.2, 5.0, "gain", start=1.0, neutral=1.0),),
        ("y", "z"),
        _gain,
    ),
}


def two_curves(noise: dict) -> selection.Problem:
    """The toy problem: y and z, each x per unit at a gain of 1 in the baseline."""
    return selection.Problem(
        group="toy",
        registry=REGISTRY,
        baseline=lambda data: {o: np.tile(X, (data.units, 1)) for o in ("y", "z")},
        measured={"y": "y", "z": "z"},
        units={"y": "1", "z": "1"},
        names={"y": "curve y", "z": "curve z"},
        baseline_name="unit gain",
        features=lambda data: {o: {"x": np.tile(X, (data.units, 1))} for o in ("y", "z")},
        noise=lambda data: noise,
    )


def drawn(rng, units: int = 60, sd: float = 0.05):
    """Data with a gain on both curves and a bump on z alone; the truth beside them."""
    gain = rng.uniform(1.1, 1.3)
    bump = rng.uniform(0.3, 0.6) * np.sin(2.0 * np.pi * 2.0 * X)
    y = np.tile(X, (units, 1)) * gain + rng.normal(0.0, sd, (units, X.size))
    z = np.tile(X, (units, 1)) * gain + bump + rng.normal(0.0, sd, (units, X.size))
    trial = np.repeat(np.arange(3), units // 3)
    data = selection.Data({"y": y, "z": z}, trial, np.arange(units))
    noise = {o: rng.normal(0.0, 1.0, (units, 80)) for o in ("y", "z")}
    return data, {"y": sd, "z": sd}, noise, {"gain_1": gain}


def test_a_misfit_of_one_observable_leaves_the_others_claims():
    print(f"seed {SEED}")
    data, scales, noise, truth = drawn(np.random.default_rng([SEED, 1]))
    settings = selection.Settings(folds=5, bootstrap=50, seed=SEED, null_draws=100)
    report = selection.analyse(two_curves(noise), data, scales, settings, "toy")
    flagged = {t["observable"] for t in report["unexplained"]["tests"] if t["flag"]}
    found = {e["effect"]: e for e in report["effects_found"]}
    assert "z" in flagged  # the joint fit's bias may show in y too
    assert set(found) == {"gain"}
    assert found["gain"]["from_observables"] == ["y"]
    assert "estimated from the curve y alone" in report["cause"]
    low, high = found["gain"]["ci95"]["gain_1"]
    assert low <= truth["gain_1"] <= high


def test_nothing_is_claimed_from_the_fitting_observables_when_they_misfit_too():
    rng = np.random.default_rng([SEED, 2])
    data, scales, noise, _ = drawn(rng)
    # the bump on y as well: no observable fits, nothing rests on part of the evidence
    bent = {**data.arrays, "y": data.arrays["y"] + 0.5 * np.sin(2.0 * np.pi * 2.0 * X)}
    data = selection.Data(bent, data.trial, data.order)
    settings = selection.Settings(folds=5, bootstrap=50, seed=SEED, null_draws=100)
    report = selection.analyse(two_curves(noise), data, scales, settings, "toy")
    assert all("from_observables" not in e for e in report["effects_found"])


def _located_problem() -> selection.Problem:
    drop = P("drop_1", "deg", -30.0, 30.0, "counts lost", log=False, start=0.0)
    effect = selection.Effect("drop", "a count drop", (drop,), ("y",), lambda s, v, d: s)
    return selection.Problem(group="toy", registry={"drop": effect}, baseline=lambda d: {},
                             measured={"y": "y"}, units={"y": "deg"}, baseline_name="toy",
                             located=("drop",))  # fmt: skip


def _with_located(sizes, resolution) -> selection.Data:
    located = {"drop": {"drop_1": {"values": sizes, "resolution": resolution}}}
    return selection.Data({"y": np.zeros((2, 3))}, np.zeros(2), np.arange(2),
                          {"located": located})  # fmt: skip


STEPS = selection.Settings(located_steps=2.0)


@pytest.mark.parametrize("sizes", [[4.536], [4.536, 4.464, 4.536]])
def test_a_located_drop_is_sized_by_its_check_within_its_steps(sizes):
    got = beside.located_sizes(_located_problem(), _with_located(sizes, 0.072), STEPS)
    low, high = got["drop"]["ci95"]["drop_1"]
    assert got["drop"]["parameters"]["drop_1"] == pytest.approx(np.median(sizes))
    assert low == pytest.approx(min(sizes) - 0.144) and high == pytest.approx(max(sizes) + 0.144)
    assert got["drop"]["from_observables"] == []


@pytest.mark.parametrize("sizes", [[0.05], [], [2.016, 4.536]], ids=["within steps of 0", "none",
                                                                      "two sizes"])  # fmt: skip
def test_a_located_size_is_not_claimed_near_nothing_or_for_drops_of_different_sizes(sizes):
    assert beside.located_sizes(_located_problem(), _with_located(sizes, 0.072), STEPS) == {}


def test_the_restricted_problem_measures_and_tests_only_the_fitting_observables():
    problem = replace_exact(two_curves({}))
    part = beside.restricted(problem, ["y"])
    assert dict(part.measured) == {"y": "y"}
    assert part.exact == ()
    assert beside.restricted(problem, ["z"]).exact == ("z",)


def replace_exact(problem: selection.Problem) -> selection.Problem:
    """The toy problem with z an exact observable."""
    from dataclasses import replace

    return replace(problem, exact=("z",))


def test_a_misfit_implicates_the_violated_rows_on_its_signal_that_nothing_holds():
    from exobench.selection import checks
    from exobench.selection.assumptions import Assumption, Relaxation

    def row(key, observables, registry=None):
        relax = Relaxation("delay", "d_s", "s", "late by d", (0.1, 0.2), registry=registry)
        return Assumption(key, "timing", key, f"{key} on time", observables, (relax,), "check")

    rows = [row("clutch", ("impulse",)), row("drop", ("impulse", "angle"), registry="drop_effect"),
            row("sensor", ("angle",))]  # fmt: skip
    table = checks.frame([
        checks.stated("clutch", "table", "late steps", 1.0, 0.0, 0.05, "1", 40, "violated", ""),
        checks.stated("drop", "drops", "drops located", 2.0, 0.0, 0.0, "1", 2, "violated", ""),
        checks.stated("sensor", "zero", "zero", 0.01, 0.0, 0.05, "deg", 40, "holds", ""),
    ])  # fmt: skip
    report = {"effects_found": [{"effect": "drop_effect"}], "discovery": {"named": []},
              "unexplained": {"tests": [{"observable": "impulse", "flag": True},
                                        {"observable": "angle", "flag": False}]},
              "observable_order": ["impulse", "angle"],
              "observable_names": {"impulse": "impulse", "angle": "angle"}}  # fmt: skip
    (sentence,) = checks.implicated(table, report, rows)
    # the clutch's row is violated on the misfit's signal; the drop's is held by a claim; the
    # sensor's holds and shows on a signal that fits
    assert "implicates the assumption row clutch (table: late steps 1 against 0 ± 0.05)" in sentence
    assert "drop" not in sentence and "sensor" not in sentence


def test_an_observable_sized_by_one_left_out_is_sized_by_its_own_spread():
    from dataclasses import replace

    problem = replace(two_curves({}), sized_by={"y": "z"})
    assert beside.restricted(problem, ["y"]).sized_by == {}
    assert beside.restricted(problem, ["y", "z"]).sized_by == {"y": "z"}
    data, scales, noise, truth = drawn(np.random.default_rng([SEED, 1]))
    settings = selection.Settings(folds=5, bootstrap=50, seed=SEED, null_draws=100)
    report = selection.analyse(replace(two_curves(noise), sized_by={"y": "z"}), data, scales,
                               settings, "toy")  # fmt: skip
    low, high = {e["effect"]: e for e in report["effects_found"]}["gain"]["ci95"]["gain_1"]
    assert low <= truth["gain_1"] <= high
