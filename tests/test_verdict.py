"""The verdict in words: the cause sentence's grammar over every registry effect of every group,
and the summary's numbers against the report they come from."""

from __future__ import annotations

import re

import numpy as np
import pandas as pd
import pytest

from exobench import document
from exobench.emulator.model import discrepancy as emulator_discrepancy
from exobench.phantom.model import discrepancy, discrepancy_reported
from exobench.phantom.report import verdict_context
from exobench.selection import report, structure, summary, verdict

PROBLEMS = {
    "phantom": discrepancy.problem(),
    "phantom_reported": discrepancy_reported.problem(),
    "emulator": emulator_discrepancy.problem(),
}
CASES = [(group, name) for group, problem in PROBLEMS.items() for name in problem.registry]


def _gain(problem, held_out=True) -> dict:
    keys = [f"{o}_{problem.units[o]}" for o in problem.measured]
    return {
        "held_out": held_out,
        "reduction_pct": 93.0,
        "baseline_rmse": dict.fromkeys(keys, 2.5),
        "extended_rmse": dict.fromkeys(keys, 0.125),
    }


def _flagged(problem) -> dict:
    obs = next(iter(problem.measured))
    return {
        "flag": True,
        "observable": obs,
        "correlates_with": "phase",
        "statistic": 0.4,
        "threshold": 0.1,
    }


def _well_formed(text: str) -> None:
    """One or more sentences: capital start, full stop at the end, balanced brackets, no empty
    list items or doubled separators."""
    assert text[0].isupper() and text.endswith("."), text
    assert text.count("(") == text.count(")") and text.count("[") == text.count("]"), text
    for bad in ("  ", " ,", ",,", ";;", "; ;", " .", "..", "()", "and and", "of of", "the the"):
        assert bad not in text, (bad, text)
    for sentence in re.split(r"(?<=\.) (?=[A-Z])", text):
        assert sentence[0].isupper(), (sentence, text)


@pytest.mark.parametrize("group", PROBLEMS)
def test_the_baseline_name_is_one_noun_phrase(group):
    """Every sentence opens 'The <baseline name> misses the data': a name with a clause of its
    own (a comma outside brackets) garbles it."""
    name = PROBLEMS[group].baseline_name
    outside = re.sub(r"\([^)]*\)", "", name)
    assert "," not in outside and not name[0].isupper() and not name.endswith("."), name


@pytest.mark.parametrize(("group", "effect"), CASES)
def test_cause_sentences_are_well_formed_for_every_effect(group, effect):
    problem = PROBLEMS[group]
    description = problem.registry[effect].description
    gain = _gain(problem)
    calm = {"flag": False}
    found = report.cause_sentence(problem, [effect], [], gain, calm)
    tentative = report.cause_sentence(problem, [], [effect], gain, _flagged(problem))
    others = [e for e in problem.registry if e != effect][:2]
    several = report.cause_sentence(problem, [effect, *others], [], gain, calm)
    for text in (found, tentative, several):
        _well_formed(text)
        assert text.startswith(f"The {problem.baseline_name} misses the data"), text
        assert text.count(description) == 1, text
        assert "RMSE 2.5 → 0.125" in text, text
    assert "Left unexplained" in tentative and "not claimed" in tentative
    # the verbs agree with the number of effects
    assert "; with it, " in found and "; with them, " in several
    assert " improves the fit " in tentative and " is not claimed" in tentative
    assert "term of the library" not in tentative  # the library was not searched
    searched = report.cause_sentence(problem, [], [effect], gain, _flagged(problem), (), True)
    assert "no registry effect or term of the library accounts" in searched
    first = problem.names.get(next(iter(problem.measured)))
    assert first is not None and first in found, (first, found)


@pytest.mark.parametrize("group", PROBLEMS)
def test_cause_sentences_without_effects(group):
    problem = PROBLEMS[group]
    gain = _gain(problem, held_out=False)
    assert report.cause_sentence(problem, [], [], gain, {"flag": False}).startswith("none: ")
    nothing = report.cause_sentence(problem, [], [], gain, _flagged(problem))
    _well_formed(nothing)
    assert nothing.startswith("No effect in the registry") and "Left unexplained" in nothing


def _term(problem, name: str, value: float, ci: list[float]) -> dict:
    """A named term as the report lists it."""
    (parameter,) = problem.terms[name].parameters
    return {
        "term": name,
        "description": problem.terms[name].description,
        "parameters": {parameter.name: value},
        "units": {parameter.name: parameter.unit},
        "ci95": {parameter.name: ci},
        "gain": {"gain_pct": 90.0},
        "alternatives": [],
    }


def test_phantom_sentences_with_a_named_term():
    problem = PROBLEMS["phantom"]
    name = next(n for n, t in problem.terms.items() if len(t.parameters) == 1)
    low = problem.terms[name].parameters[0].low
    term = _term(problem, name, 1.3 * low, [1.2 * low, 1.4 * low])
    library = {n: report.entry_spec(t) for n, t in problem.terms.items()}
    statement = summary.term_statement(term, library)
    assert statement.startswith("Hypothesis for the lab to check") and "90 %" in statement
    alone = report.cause_sentence(problem, [], [], _gain(problem), {"flag": False}, [term])
    beside = report.cause_sentence(
        problem, ["interface_compliance"], [], _gain(problem), {"flag": False}, [term]
    )
    for text in (alone, beside):
        _well_formed(text)
        assert text.endswith(statement), text


def test_an_estimate_at_a_search_bound_says_so():
    """'3 (at the upper search bound)', never '3 [3, 3]': in the tables and in the sentences."""
    assert summary.interval_text(3.0, [3.0, 3.0], "1", [1 / 3, 3.0]) == (
        "3.00 (at the upper search bound)"
    )
    reaching = summary.interval_text(2.5, [2.1, 3.0], "1", [1 / 3, 3.0])
    assert reaching == "2.50 [2.10, 3.00] (the interval reaches the upper search bound)"
    assert summary.interval_text(2.5, [2.1, 2.9], "1", [1 / 3, 3.0]) == "2.50 [2.10, 2.90]"
    problem = PROBLEMS["phantom"]
    name = next(n for n, t in problem.terms.items() if len(t.parameters) == 1)
    high = problem.terms[name].parameters[0].high
    term = _term(problem, name, high, [high, high])
    text = report.cause_sentence(problem, [], [], _gain(problem), {"flag": False}, [term])
    assert "(at the upper search bound" in text and f"[{summary.number(high)}," not in text
    (parameter,) = term["parameters"]
    rows = summary.effect_rows([term], {parameter: [0.0, high]})
    assert rows[0][2].endswith("(at the upper search bound)")


def _fake_report(problem, rng) -> dict:
    """A report with random numbers in the engine's schema (what the summary reads)."""
    effect = next(iter(problem.registry.values()))
    parameter = effect.parameters[0]
    value = float(rng.uniform(10, 100))
    keys = [f"{o}_{problem.units[o]}" for o in problem.measured]
    tests = [
        {
            "observable": o,
            "correlates_with": "phase",
            "statistic": 0.05,
            "threshold": 0.1,
            "size": 1.0,
            "size_floor": 2.0,
            "flag": False,
        }
        for o in problem.measured
    ]
    for test in tests:
        test["decision"] = structure.decision(test)
    return {
        "baseline": {"model": problem.baseline_name},
        "observables": dict(problem.units),
        "observable_names": {o: report.observable_name(problem, o) for o in problem.measured},
        "observable_order": list(problem.measured),
        "gain": {
            "held_out": True,
            "baseline_rmse": {k: float(rng.uniform(1, 9)) for k in keys},
            "extended_rmse": {k: float(rng.uniform(0.01, 0.9)) for k in keys},
        },
        "effects_found": [
            {
                "effect": effect.name,
                "parameters": {parameter.name: value},
                "units": {parameter.name: parameter.unit},
                "ci95": {parameter.name: [0.9 * value, 1.1 * value]},
            }
        ],
        "tentative": [],
        "discovery": {"named": [], "proposed": []},
        "unexplained": {"flag": False, "tests": tests},
        "cause": "The cause.",
    }


@pytest.mark.parametrize("group", PROBLEMS)
def test_the_summary_carries_the_reports_numbers(group):
    rng = np.random.default_rng(7)
    problem = PROBLEMS[group]
    fake = _fake_report(problem, rng)
    text = document.document([verdict.errors(fake), verdict.claims(fake)])
    for obs in problem.measured:
        key = f"{obs}_{problem.units[obs]}"
        row = next(
            line
            for line in text.splitlines()
            if line.startswith(f"| {fake['observable_names'][obs]} |")
        )
        cells = [c.strip() for c in row.strip("|").split("|")]
        assert float(cells[1]) == pytest.approx(fake["gain"]["baseline_rmse"][key], rel=5e-3)
        assert float(cells[2]) == pytest.approx(fake["gain"]["extended_rmse"][key], rel=5e-3)
    entry = fake["effects_found"][0]
    ((name, value),) = entry["parameters"].items()
    low, high = entry["ci95"][name]
    number = summary.number
    assert f"{number(value)} [{number(low)}, {number(high)}]" in text
    assert summary.title_block(fake)[0].startswith(problem.baseline_name)


def test_a_parameter_fitted_two_ways_is_shown_both_ways_with_the_reason():
    one = {
        "parameters": {"k_Nm_per_rad": 60.0, "c_Nms_per_rad": 1.0},
        "ci95": {"k_Nm_per_rad": [58.0, 62.0], "c_Nms_per_rad": [0.9, 1.1]},
        "units": {"k_Nm_per_rad": "N·m/rad", "c_Nms_per_rad": "N·m·s/rad"},
        "effects": ["stiffness", "damping"],
    }
    two = {
        "parameters": {"k_Nm_per_rad": 70.0},
        "ci95": {"k_Nm_per_rad": [66.0, 74.0]},
        "units": {"k_Nm_per_rad": "N·m/rad"},
        "effects": ["stiffness"],
    }
    rows = summary.fitted_twice({"recordings": one, "medians": two})
    assert [r["parameter"] for r in rows] == ["k_Nm_per_rad"]
    reason = rows[0]["reason"]
    assert "recordings: + damping" in reason and "do not overlap" in reason
    two["ci95"]["k_Nm_per_rad"] = [61.0, 74.0]
    reason = summary.fitted_twice({"recordings": one, "medians": two})[0]["reason"]
    assert "intervals overlap" in reason and "do not" not in reason
    text = document.document([verdict.fitted_more_than_once({"recordings": one, "medians": two})])
    assert "60.0 [58.0, 62.0] N·m/rad" in text and "70.0 [61.0, 74.0] N·m/rad" in text
    # why the fits differ is said once, not once per parameter
    assert text.count(summary.FITTED_TWICE) == 1


def test_set_against_recovered_pairs_each_setting_with_its_estimate():
    """With the twin the headline is each number set beside the estimate; an estimate whose
    interval misses the setting, or a claim of something not set, says so."""
    problem = PROBLEMS["phantom"]
    fake = _fake_report(problem, np.random.default_rng(3))
    fake["registry"] = {n: report.entry_spec(e) for n, e in problem.registry.items()}
    entry = fake["effects_found"][0]
    ((name, value),) = entry["parameters"].items()
    effects = {
        entry["effect"]: {"enabled": True, name: "calibrated"},
        "marker_noise": {"enabled": True, "sd_mm": 0.15},
        "clutch_miss": {"enabled": False, "probability": 0.0},
    }
    rows = verdict.twin_settings(effects, {name: value})
    assert [r["parameter"] for r in rows] == [name, "sd_mm"] and rows[0]["calibrated"]
    text = "\n".join(verdict.set_against_recovered(fake, rows))
    assert "(calibrated)" in text and "| yes |" in text
    assert "Also set, outside the engine's registry" in text and "sd_mm 0.15 mm" in text
    missed = verdict.twin_settings({entry["effect"]: {"enabled": True, name: 2 * value}}, {})
    text = "\n".join(verdict.set_against_recovered(fake, missed))
    assert "| no |" in text and "a bias, not noise" in text
    text = "\n".join(verdict.set_against_recovered(fake, []))
    assert "| not set |" in text


def test_residual_tests_read_in_plain_words():
    base = {"observable": "moment", "correlates_with": "angle", "flag": False}
    quiet = verdict.plain_decision({**base, "statistic": 0.01, "threshold": 0.02})
    small = verdict.plain_decision({**base, "statistic": 0.09, "threshold": 0.02, "size": 0.43,
                                    "size_floor": 3.2})  # fmt: skip
    loud = verdict.plain_decision({**base, "statistic": 0.5, "threshold": 0.02, "flag": True})
    assert quiet.startswith("within the noise")
    assert small.startswith("a pattern beyond the noise") and "0.430" in small
    assert loud.startswith("**flagged**")
    for text in (quiet, small, loud):
        assert "min_share" not in text and "size floor" not in text


def test_the_pooled_knee_moment_error_comes_with_its_range_per_spring():
    rows = []
    for spring, error in ((3400.0, 1.0), (21700.0, 4.0)):
        for stride in range(2):
            rows += [{"trial": f"k{spring:g}", "stride": stride,
                      "spring_stiffness_N_per_m": spring, "measured_moment_Nm": 5.0,
                      "baseline_moment_Nm": 5.0 + error, "extended_moment_Nm": 5.01}
                     for _ in range(3)]  # fmt: skip
    predictions = pd.DataFrame(rows)
    assert "from 1.00 N·m at 3.4 kN/m to 4.00 N·m at 21.7 kN/m" in verdict_context.pooled_range(
        predictions
    )
    text = verdict_context.per_spring(predictions)
    assert "2 springs (4 strides" in text
    # each stride's peak, median [quartiles], never a single sample's maximum
    assert "median [quartiles] of 5.00 [5.00, 5.00] N·m (3.4 kN/m, 2 strides)" in text


def test_peaks_are_per_stride_medians_with_quartiles_over_every_stride():
    """One stride with a high sample does not set the quoted peak; strides the engine did not
    fit count for the peaks, not for the model's error."""
    rows = []
    for stride, peak in enumerate([4.0, 5.0, 6.0, 40.0]):
        rows += [{"trial": "k3400", "stride": stride, "spring_stiffness_N_per_m": 3400.0,
                  "measured_moment_Nm": value, "baseline_moment_Nm": value + 1.0,
                  "extended_moment_Nm": value, "fitted": stride < 2}
                 for value in (1.0, peak)]  # fmt: skip
    peaks = verdict_context.peaks(pd.DataFrame(rows)).iloc[0]
    assert peaks["median"] == 5.5 and peaks["n"] == 4 and peaks["q3"] < 40.0
    text = verdict_context.per_spring(pd.DataFrame(rows))
    assert "(2 strides of the engine's window)" in text and "40" not in text


def test_an_interval_prints_the_digits_that_show_its_width():
    assert summary.interval_text(299.0, [298.9, 299.1], "mm") == "299.0 [298.9, 299.1] mm"
    assert summary.interval_text(65.5, [65.3, 65.7], "1") == "65.5 [65.3, 65.7]"
    assert summary.interval_text(1010.0, [956.0, 1060.0], "1") == "1010 [956, 1060]"
    assert summary.interval_text(3.0, [3.0, 3.0], "1").endswith("(an interval of zero width)")


def test_a_set_value_just_outside_its_interval_reads_outside():
    # three digits would print a set gain of 0.97 inside '[0.97, 1.03]' beside "no"
    assert summary.interval_text(0.978, [0.97031, 1.03], "1", apart=0.97) == (
        "0.9780 [0.9703, 1.0300]")  # fmt: skip
    # inside, or already told apart: the digits the interval alone needs
    assert summary.interval_text(0.978, [0.96, 1.03], "1", apart=0.97) == "0.98 [0.96, 1.03]"
    assert summary.interval_text(0.0086, [0.0083, 0.0117], "s", apart=0.012) == (
        "0.0086 [0.0083, 0.0117] s")  # fmt: skip
    assert summary.interval_text(21700.0, [21000.0, 22000.0], "N/m", apart=22500.0) == (
        "21.7 [21.0, 22.0] kN/m")  # fmt: skip


def test_the_twins_drive_stiffness_is_put_beside_the_medians_reading():
    refused = {"effect": "drive_compliance", "fitted_anyway": {"k_drive_N_per_m": 28000.0}}
    residuals = pd.DataFrame({"metric": ["peak_moment_Nm", verdict_context.DIFFERENCE],
                              "reported": [5.5, 0.6], "twin": [5.4, 0.48]})  # fmt: skip
    (note,) = verdict_context.drive_note({"not_claimed": [refused]},
                                         {"k_drive_N_per_m": 54800.0}, residuals)  # fmt: skip
    assert "54.8 kN/m" in note and "28.0 kN/m" in note and "0.48°" in note
    assert "not significant" in note and "neither is a measured property" in note
    assert (
        verdict_context.drive_note({"not_claimed": []}, {"k_drive_N_per_m": 1.0}, residuals) == []
    )
