"""A constant that moved between trials is refitted where it moved (selection.between).

A toy group observes one curve per unit, y = gain·x + zero, in six trials; a sensor re-zeroed
before some trials (or before every one) shifts its zero there. The data are generated here from a
printed seed, with the shifts hidden from the analysis; the truth is read only in the final
assertions.
"""

from __future__ import annotations

from dataclasses import replace

import numpy as np

from exobench import selection
from exobench.selection.model import Constant
from test_selection import X, toy_problem

SEED = 31
P = selection.Parameter
TRIALS, UNITS = 6, 14


def _gain(state, values, data):
    return {**state, "y": state["y"] * values["gain_1"]}


def _offset(state, values, data):
    """The sensor's zero, set (not added): a later setting replaces it (``Problem.per_unit``)."""
    return {**state, "offset_1": values["offset_1"]}


GAIN = P("gain_1", "1", 0.2, 5.0, "gain", start=1.0, neutral=1.0)
OFFSET = P("offset_1", "1", -3.0, 3.0, "offset", log=False, start=0.0, negligible=0.02)
REGISTRY = {
    "gain": selection.Effect("gain", "a gain error", (GAIN,), ("y",), _gain),
    "offset": selection.Effect("offset", "the sensor's zero", (OFFSET,), ("y",), _offset),
}
ZERO = Constant("zero_between", "sensor's zero", "offset", "offset_1", 0.02, False,
                alike=("drift_row",))  # fmt: skip


def curve(noise, per_unit: tuple[str, ...]) -> selection.Problem:
    """The toy problem: y = x per unit in the baseline, the sensor reading it + its zero; the
    zero's constant between trials."""
    return replace(toy_problem(noise), registry=REGISTRY, constants=(ZERO,), per_unit=per_unit,
                   baseline=lambda data: {"y": np.tile(X, (data.units, 1)), "offset_1": 0.0},
                   recorded=lambda state, data: {"y": state["y"] + state["offset_1"]})  # fmt: skip


def drawn(rng, moved: int, session: float = 0.0, sd: float = 0.05, apart: bool = False):
    """Data with a gain, the sensor's zero at ``session`` and, in ``moved`` trials drawn at
    random, shifted from it (``apart``: every trial's zero its own, 0.3 from the next)."""
    gain = rng.uniform(1.1, 1.3)
    trials = [f"t{k}" for k in range(TRIALS)]
    shifts = dict.fromkeys(trials, 0.0)
    for t in rng.choice(trials, moved, replace=False):
        shifts[str(t)] = float(rng.choice([-1.0, 1.0]) * rng.uniform(0.3, 0.6))
    if apart:
        shifts = dict(zip(trials, rng.permutation(0.3 * np.arange(TRIALS)), strict=True))
    trial = np.repeat(np.array(trials, dtype=object), UNITS)
    offset = session + np.array([shifts[t] for t in trial])[:, None]
    y = gain * np.tile(X, (trial.size, 1)) + offset + rng.normal(0.0, sd, (trial.size, X.size))
    data = selection.Data({"y": y}, trial, np.tile(np.arange(UNITS), TRIALS))
    noise = rng.normal(0.0, 1.0, (trial.size, 60))
    return data, {"y": sd}, noise, {"gain_1": gain, "session": session, "shifts": shifts}


SETTINGS = selection.Settings(folds=5, bootstrap=50, seed=SEED, null_draws=100, max_terms=0)


def test_a_constant_moved_in_some_trials_is_claimed_there_and_the_rest_kept():
    print(f"seed {SEED}")
    data, scales, noise, truth = drawn(np.random.default_rng([SEED, 1]), moved=2, session=0.5)
    report = selection.analyse(curve(noise, ("offset_1",)), data, scales, SETTINGS, "toy")
    found = {e["effect"]: e for e in report["effects_found"]}
    assert not report["unexplained"]["flag"]
    assert set(found) == {"zero_between.between", "gain"}
    entry = found["zero_between.between"]
    assert entry["alternatives"] == ["drift_row"]
    assert "Refitted in the trials it moved in" in report["cause"]
    assert "Left unexplained" not in report["cause"]
    moved = {t: s for t, s in truth["shifts"].items() if s}
    assert {name.split("@")[1] for name in entry["parameters"] if "@" in name} == set(moved)
    for trial, shift in moved.items():
        low, high = entry["ci95"][f"offset_1@{trial}"]
        assert low <= shift <= high
    for name, value in (("offset_1", truth["session"]), ("gain_1", truth["gain_1"])):
        low, high = (entry if name == "offset_1" else found["gain"])["ci95"][name]
        assert low <= value <= high


def test_when_every_trial_moved_one_keeps_the_session_s_value():
    data, scales, noise, truth = drawn(np.random.default_rng([SEED, 3]), moved=0, apart=True)
    report = selection.analyse(curve(noise, ("offset_1",)), data, scales, SETTINGS, "toy")
    entry = next(e for e in report["effects_found"] if e["effect"] == "zero_between.between")
    shifted = [n.split("@")[1] for n in entry["parameters"] if "@" in n]
    kept = (set(truth["shifts"]) - set(shifted)).pop()
    assert len(shifted) == TRIALS - 1
    # the kept trial's zero is the session's value, each shift its trial's zero less that: p
    # and the shifts stay apart (within five standard errors of one trial's mean zero)
    zeros = {t: truth["session"] + s for t, s in truth["shifts"].items()}
    within = 5.0 * scales["y"] / np.sqrt(UNITS * X.size)
    got = entry["parameters"]
    assert abs(got["offset_1"] - zeros[kept]) < within
    for trial in shifted:
        assert abs(got[f"offset_1@{trial}"] - (zeros[trial] - zeros[kept])) < 2.0 * within


def test_without_a_per_unit_parameter_the_move_stays_unexplained_between_trials():
    data, scales, noise, _ = drawn(np.random.default_rng([SEED, 1]), moved=2, session=0.5)
    report = selection.analyse(curve(noise, ()), data, scales, SETTINGS, "toy")
    assert report["unexplained"]["flag"] and report["stability"]["flag"]
    assert all(not e["effect"].endswith(".between") for e in report["effects_found"])


def test_a_session_whose_constant_held_gets_no_shift():
    data, scales, noise, _ = drawn(np.random.default_rng([SEED, 2]), moved=0, session=0.5)
    report = selection.analyse(curve(noise, ("offset_1",)), data, scales, SETTINGS, "toy")
    names = {e["effect"] for e in [*report["effects_found"], *report["tentative"]]}
    assert not any(n.endswith(".between") for n in names)
    assert not report["stability"]["flag"]
