"""Parameter stability between trials: its test holds its level, and a rig constant changed in
one trial is named with that trial, in the shared engine and in both groups.

The groups' tests record every trial with the twin on its own (its own settings and noise): one
constant of the assumption table's ``between`` rows, the trial and the size are drawn at random
(the seed is printed; ``EXOBENCH_STABILITY_SEED=<n>`` reruns one), the engine analyses the
recordings as a lab's, told nothing, and the truth is read only in the final assertions.
"""

from __future__ import annotations

import numpy as np
import pytest

import seeds
from exobench import selection
from exobench.selection import checks, stability
from exobench.selection.model import Constant
from exobench.selection.summary import left_unexplained


def random_seed(name: str) -> int:
    """The seed of a drawn case (:func:`seeds.drawn`: fixed, or fresh under --explore)."""
    return seeds.drawn(name)


def test_welchs_test_holds_its_level_for_trials_of_unequal_size_and_spread():
    rng = np.random.default_rng(8)
    p = []
    for _ in range(1500):
        k = int(rng.integers(3, 7))
        units = rng.integers(5, 13, k)
        sd = np.repeat(rng.uniform(0.5, 3.0, k), units)
        values = rng.normal(0.0, sd)
        starts = np.concatenate([[0], np.cumsum(units)[:-1]])
        means = np.add.reduceat(values, starts) / units
        spread = np.add.reduceat((values - np.repeat(means, units)) ** 2, starts) / (units - 1)
        p.append(stability.welch(means, np.sqrt(spread / units), units.astype(float))["p"])
    p = np.array(p)
    for level in (0.01, 0.05, 0.2):  # within four binomial standard errors of 1500 draws
        assert abs(np.mean(p < level) - level) < 4 * np.sqrt(level * (1 - level) / p.size)


def test_holm_adjusts_step_down_and_keeps_the_order():
    assert stability.holm([0.01, 0.04, 0.03, 0.5]) == pytest.approx([0.04, 0.09, 0.09, 0.5])


def offsets_problem(constants, more=()) -> selection.Problem:
    """A toy rig: each unit records an offset plus noise over 20 samples (``more``: further
    registry effects)."""
    offset = selection.Effect(
        "offset", "an offset",
        (selection.Parameter("offset_N", "N", -50.0, 50.0, "offset", log=False, start=0.0),),
        ("y",), lambda state, values, data: {**state, "y": state["y"] + values["offset_N"]},
    )  # fmt: skip
    return selection.Problem(
        group="toy", registry={"offset": offset, **{e.name: e for e in more}},
        baseline=lambda data: {"y": np.zeros_like(data.arrays["y_N"])},
        measured={"y": "y_N"}, units={"y": "N"}, baseline_name="toy", constants=constants,
    )  # fmt: skip


def offsets_data(rng, shifts) -> selection.Data:
    """Four trials of eight units; trial i's offset 2 N + shifts[i]; noise 1 N per sample."""
    trial = np.repeat(np.arange(4), 8)
    y = 2.0 + np.asarray(shifts)[trial][:, None] + rng.normal(0.0, 1.0, (trial.size, 20))
    return selection.Data({"y_N": y}, trial.astype(str), np.arange(trial.size))


ZERO = Constant("zero_between", "offset", "offset", "offset_N", 0.05, False)


def toy_report(data, constants=(ZERO,), effects=("offset",), more=()) -> dict:
    problem = offsets_problem(constants, more)
    values, _ = selection.fit(problem, data, effects, {"y": 1.0})
    model = {"effects": effects, "values": values}
    return stability.stability(problem, data, {"y": 1.0}, selection.Settings(), model)


def test_a_shifted_trial_is_named_and_agreeing_trials_are_not():
    # rates over many drawn cases: each test holds its 1 % level, so a single case would fail
    # now and then (over 400 cases: 1.5 % also named an agreeing trial, 0.5 % flagged calm data)
    rng = np.random.default_rng(random_seed("toy offsets"))
    missed = extra = alarms = 0
    cases = 150
    for _ in range(cases):
        changed = int(rng.integers(4))
        size = float(rng.choice([-1.0, 1.0]) * rng.uniform(0.5, 2.0))  # ≥ 2 standard errors × 10
        shifts = np.zeros(4)
        shifts[changed] = size
        found = toy_report(offsets_data(rng, shifts))["constants"][0]
        calm = toy_report(offsets_data(rng, np.zeros(4)))["constants"][0]
        assert calm["tested"]
        alarms += calm["flag"]
        named = {d["trial"] for d in found["departing"]}
        missed += not (found["flag"] and str(changed) in named)
        extra += bool(named - {str(changed)})
    # thresholds a few times the rates a sound test gives (each exceeded by chance < 1e-4)
    assert missed <= 0.03 * cases and extra <= 0.07 * cases and alarms <= 0.04 * cases


def test_a_departing_trials_interval_holds_its_size_95_times_in_100():
    # the departure's 95 % interval (Welch–Satterthwaite) over many shifted toy trials
    rng = np.random.default_rng(12)
    covered = []
    for _ in range(150):
        shifts = np.zeros(4)
        changed = int(rng.integers(4))
        shifts[changed] = size = float(rng.uniform(1.0, 2.0))
        departing = toy_report(offsets_data(rng, shifts))["constants"][0]["departing"]
        (low, high), *_ = [d["difference_ci95"] for d in departing if d["trial"] == str(changed)]
        covered.append(low <= size <= high)
    assert abs(np.mean(covered) - 0.95) < 4 * np.sqrt(0.95 * 0.05 / len(covered))


def test_a_constant_the_engine_cannot_size_or_has_nothing_to_vary_says_why():
    data = offsets_data(np.random.default_rng(1), np.zeros(4))
    missing = Constant("cable_between", "cable", "cable.offset", "cable.offset_deg", 0.1, False)
    needs = Constant("straps_between", "offset", "offset", "offset_N", 0.05, True)
    result = toy_report(data, (missing, needs), effects=())
    reasons = [c["decision"] for c in result["constants"]]
    assert not result["flag"] and all(r.startswith("not tested") for r in reasons)
    assert "cable.offset" in reasons[0] and "nothing to vary" in reasons[1]


def test_a_trial_whose_own_parameter_takes_the_same_change_is_said_not_to_size_the_constant():
    # a shared parameter that moves one trial's units alone (as a count drop the QC located
    # before a trial does) takes whatever that trial's constant would: its error is that
    # trial's own, so the trial does not size the constant and is not named, whatever the fit
    # leaves there; the verdict says which trial and why
    step = selection.Effect(
        "step", "a step in trial 2",
        (selection.Parameter("step_N", "N", -50.0, 50.0, "step", log=False, start=0.0),),
        ("y",), lambda state, values, data: {
            **state, "y": state["y"] + values["step_N"] * (data.trial == "2")[:, None]},
    )  # fmt: skip
    data = offsets_data(np.random.default_rng(4), [0.0, 0.0, 1.5, 0.0])
    result = toy_report(data, effects=("offset", "step"), more=(step,))
    (entry,) = result["constants"]
    assert entry["unsized"] == [{"trial": "2", "with": ["step_N"]}]
    assert entry["tested"] and "2" not in entry["used"] and not result["flag"]
    report = {"unexplained": {"flag": False, "tests": []}, "stability": result}
    assert "Trial 2 does not size the offset (offset_N" in left_unexplained(report)
    assert "step_N" in left_unexplained(report)


def test_the_verdict_and_the_checks_name_a_constant_that_differs():
    data = offsets_data(np.random.default_rng(2), [0.0, 0.0, 1.5, 0.0])
    result = toy_report(data)
    report = {"unexplained": {"flag": False, "tests": []}, "stability": result}
    text = left_unexplained(report)
    assert "offset_N" in text and "trial 2 departs" in text and not text.startswith("Nothing")
    (row,) = checks.between_rows(result)
    assert row["assumption"] == "zero_between" and row["decision"] == "violated"
    assert row["measured"] > row["expected"]


# The engine as the groups' tests run it: few folds, draws and screened candidates, no term
# search (what is tested here is the parameter stability of the model the registry settles on).
FAST_ENGINE = {"folds": 3, "bootstrap": 20, "null_draws": 100, "screen": 2, "max_terms": 0}
# The phantom's rig in its tests: the soft tissue every real rig has (one registry effect: its
# forward selection stops after two steps).
PHANTOM_RIG = {"interface_compliance": {"k_interface_Nm_per_rad": 65.0}}


def visible_spread(table_relaxations, row: str) -> tuple[float, float]:
    """The spread between trials a recording can see (docs/assumptions.md's visible sizes)."""
    return table_relaxations[f"{row}.between"][1].visible


def flagged(report) -> list[tuple[str, list[str]]]:
    """The constants the report finds different between trials, with the trials it names."""
    return [(e["assumption"], [d["trial"] for d in e["departing"]])
            for e in report["stability"]["constants"] if e["flag"]]  # fmt: skip


@pytest.fixture(scope="module")
def phantom_case():
    """What the phantom's tests share: the config with the fast engine, the mean cycle, the
    swing fraction, and the analysis of the twin's recordings with effects per trial."""
    from exobench.phantom.model import discrepancy
    from exobench.phantom.validation import stability as records
    from phantom_helpers import mean_cycle, swing_fraction, workflow_config

    base = workflow_config()
    base["discrepancy"] = {**base["discrepancy"], **FAST_ENGINE, "max_effects": 2}
    cycle, swing = mean_cycle(), swing_fraction()

    def analysed(seed: int, changed: dict) -> tuple[dict, list[str]]:
        data, scales = records.observations(base, 8, seed, cycle, swing, changed, PHANTOM_RIG)
        settings = {**base["phantom"]["discrepancy"], "engine": base["discrepancy"],
                    "seed": seed}  # fmt: skip
        return discrepancy.analyse(data, scales, settings, "test"), sorted(set(data.trial))

    return analysed


def test_the_phantoms_verdict_names_a_constant_changed_in_one_trial_and_the_trial(phantom_case):
    from exobench.phantom.model import assumptions
    from exobench.phantom.validation import stability as records

    seed = random_seed("phantom, a constant changed in one trial")
    rng = np.random.default_rng(seed)
    constant = str(rng.choice(sorted(records.CHANGES)))
    trial = int(rng.integers(3))
    low, high = visible_spread(assumptions.relaxations(), constant)
    size = float(rng.choice([-1.0, 1.0]) * rng.uniform(low, high))
    report, trials = phantom_case(seed, {trial: records.changed_rig(constant, size, PHANTOM_RIG)})
    print(report["cause"])
    (entry,) = [e for e in report["stability"]["constants"] if e["assumption"] == constant]
    assert flagged(report) == [(constant, [trials[trial]])]
    assert entry["parameter"] in report["cause"]
    assert f"trial {trials[trial]} departs" in report["cause"]
    assert f"trial {trials[trial]} departs" in left_unexplained(report)


def test_the_phantoms_trials_agree_when_nothing_changes_between_them(phantom_case):
    report, _ = phantom_case(3, {})
    assert all(e["tested"] for e in report["stability"]["constants"])
    assert flagged(report) == [] and "between trials" not in report["cause"]


@pytest.fixture(scope="module")
def emulator_case():
    """What the emulator's tests share: the session's rig on the validation protocol (two
    speeds, two springs) of 10 s, the fast engine, and the analysis of the twin's recordings
    with a constant changed per condition."""
    from emulator_helpers import DEFAULT
    from exobench.emulator.model import discrepancy
    from exobench.emulator.validation import stability as records

    cfg = records.session_config(DEFAULT["emulator"])
    cfg["protocol"]["duration_s"] = 10.0
    engine = {**DEFAULT["discrepancy"], **FAST_ENGINE}

    def analysed(seed: int, changed: dict) -> tuple[dict, list[str]]:
        data, scales = records.observations(cfg, seed, engine["folds"], changed)
        report = discrepancy.analyse(data, scales, engine, seed, "test")
        return report, list(dict.fromkeys(discrepancy.session_trials(data)))

    return analysed


def test_the_emulators_verdict_names_a_constant_changed_in_one_trial_and_the_trial(emulator_case):
    from exobench.emulator.model import assumptions
    from exobench.emulator.validation import stability as records

    seed = random_seed("emulator, a constant changed in one condition")
    rng = np.random.default_rng(seed)
    # the constants the engine sizes per condition at this protocol: the cuffs' compliance is
    # not (on the twin with nothing changed its estimate per condition runs about 20 % low at
    # 2 N·m/rad and 10 % low at 3.5, and its interval spans ±25–40 % at 6–11 steps;
    # docs/engine.md, "Parameter stability between trials")
    constant = str(rng.choice(sorted(set(records.CHANGES) - {"straps_between"})))
    trial = int(rng.integers(4))
    low, high = visible_spread(assumptions.relaxations(), constant)
    size = float(rng.choice([-1.0, 1.0]) * rng.uniform(low, high))
    report, trials = emulator_case(seed, {trial: (constant, size)})
    print(report["cause"])
    (entry,) = [e for e in report["stability"]["constants"] if e["assumption"] == constant]
    unsized = {u["trial"]: u["with"] for u in entry["unsized"]}
    if unsized.get(trials[trial]):
        # a motion-capture zero moved by about 2° or more reads to the QC as a count drop before
        # the trial (the encoder against motion capture shifts the same way); with that drop and
        # the cable's zero free in the trial, its zero is not sized there: the verdict says so,
        # naming the parameter, the trial and what it cannot be told from, and names nothing
        assert flagged(report) == []
        said = f"Trial {trials[trial]} does not size the {entry['name']} ({entry['parameter']}"
        assert said in report["cause"] and said in left_unexplained(report)
        return
    assert flagged(report) == [(constant, [trials[trial]])]
    assert entry["parameter"] in report["cause"]
    assert f"trial {trials[trial]} departs" in report["cause"]


def test_the_emulators_trials_agree_when_nothing_changes_between_them(emulator_case):
    report, _ = emulator_case(3, {})
    assert flagged(report) == [] and "between trials" not in report["cause"]


@pytest.mark.parametrize("group", ["phantom", "emulator"])
def test_every_row_between_trials_is_a_constant_the_stability_sizes_in_its_own_unit(group):
    # the table's rows of kind "between" are what the stability tests (their check), each by
    # the parameter of the relaxation it varies: a spread in the parameter's unit, or a share
    # of a log-scale parameter; a term the library does not hold yet is said untested
    import importlib

    assumptions = importlib.import_module(f"exobench.{group}.model.assumptions")
    discrepancy = importlib.import_module(f"exobench.{group}.model.discrepancy")
    problem = discrepancy.problem()
    rows = {row.key for row in assumptions.TABLE if row.kind == "between"}
    assert rows and {c.row for c in problem.constants} == rows
    for constant in problem.constants:
        (row,) = [r for r in assumptions.TABLE if r.key == constant.row]
        assert row.check == "stability" and all(r.checked for r in row.relaxations)
        spread = row.relaxations[0]
        if constant.effect not in problem.entries:
            assert constant.effect in assumptions.relaxations()  # a term yet to be built
            continue
        (parameter,) = [p for p in problem.entries[constant.effect].parameters
                        if p.name == constant.parameter]  # fmt: skip
        assert spread.unit == ("1" if parameter.log else parameter.unit), constant
