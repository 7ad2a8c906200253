"""W.S.B. et al.'s numbers and significance statements against the reproduction: roles,
tolerances and reasons; the twin's prediction against the chain's measurement of its own
recordings, with the side that is wrong found from the twin's truth; the causes of a
disagreement with a significance statement. Small tables built here, no workflow run."""

from __future__ import annotations

import os

import numpy as np
import pandas as pd
import pytest

from conftest import REPO
from exobench import roles
from exobench.phantom import reference
from exobench.phantom.study import comparison, method_check, significance

SEED = int(os.environ.get("EXOBENCH_REPRODUCTION_SEED", "7"))
METRICS = ("peak_moment_Nm", "work_frame_positive_J", "phantom_stance_flexion_deg")
SPRINGS = (3400.0, 21700.0)


def strides(rng, bias: dict | None = None, n: int = 60) -> pd.DataFrame:
    """Per-stride metrics of two springs (stride-to-stride spread as a twin's), each metric
    shifted by ``bias`` (metric -> added value)."""
    rows = []
    for spring in SPRINGS:
        rows.append(pd.DataFrame({
            "trial": f"k{spring:05.0f}", "stride": np.arange(n), "spring_stiffness_N_per_m": spring,
            "included": np.arange(n) < n - 3,
            "peak_moment_Nm": rng.normal(5.5 if spring < 1e4 else 8.0, 1.0, n),
            "work_frame_positive_J": rng.normal(0.01, 0.002, n),
            "phantom_stance_flexion_deg": rng.normal(9.0, 1.0, n),
        }))  # fmt: skip
    table = pd.concat(rows, ignore_index=True)
    for metric, value in (bias or {}).items():
        table[metric] += value
    return table


def reported_table() -> pd.DataFrame:
    rows = [("strides_analysed", "", "60"), ("strides_kept", "", "57"),
            ("peak_moment_Nm", "3400", "5.5"), ("peak_moment_Nm", "21700", "8.0"),
            ("work_frame_positive_J", "21700", "0.010"),
            ("phantom_stance_flexion_median_difference_deg", "", "2.0")]  # fmt: skip
    return pd.DataFrame({
        "metric": [r[0] for r in rows],
        "spring_stiffness_N_per_m": [float(r[1]) if r[1] else np.nan for r in rows],
        "value": [r[2] for r in rows], "unit": ["1", "1", "N·m", "N·m", "J", "deg"],
        "source": "§3",
    })  # fmt: skip


def test_roles_tolerances_and_reasons():
    """A calibration target is marked so; a prediction the twin misses says the twin
    mispredicts it; the protocol's stride count is a setting; a number within its rounding
    and sampling error is reproduced."""
    rng = np.random.default_rng(SEED)
    twin = comparison.medians(strides(rng), METRICS, 300, 1)
    chain = comparison.medians(strides(rng), METRICS, 300, 2)
    targets = {("peak_moment_Nm", 3400.0), ("peak_moment_Nm", 21700.0)}
    table = comparison.compare(reported_table(), chain, 0.05, targets, twin).set_index("metric")
    assert table.loc["strides_analysed", "role"] == "setting"
    assert (table.loc["peak_moment_Nm", "role"] == "calibration target").all()
    assert table.loc["work_frame_positive_J", "role"] == "prediction"
    assert list(table.reset_index().columns) == comparison.COLUMNS
    peak = table.loc["peak_moment_Nm"]
    assert (peak["tolerance"] > peak["rounding"]).all() and peak["within_tolerance"].all()
    difference = table.loc["phantom_stance_flexion_median_difference_deg"]
    assert not difference["within_tolerance"] and "the twin mispredicts it" in difference["reason"]
    assert "the chain measures" in difference["reason"]
    assert (table.loc[table["within_tolerance"], "reason"] == "").all()
    got, total = comparison.rate(table.reset_index(), ["prediction"])
    assert total == 2 and got == int(table.loc[table["role"] == "prediction",
                                               "within_tolerance"].sum())  # fmt: skip


@pytest.mark.parametrize("wrong", ["chain", "twin"])
def test_a_difference_between_twin_and_chain_names_the_wrong_side(wrong):
    """The chain measures the frame's positive work 50 % high (or the twin's calibration
    simulated it 50 % low): the method check finds the difference and, from the truth of the
    same strides, names the side that is wrong; the numbers without a bias agree."""
    rng = np.random.default_rng([SEED, len(wrong)])
    truth_table = strides(rng)
    shift = {"work_frame_positive_J": 0.005}
    chain_table = truth_table.copy()
    for metric in METRICS:  # the chain's own measurement noise
        chain_table[metric] += rng.normal(0, 1e-4, len(chain_table))
    twin_table = truth_table.copy()
    if wrong == "chain":
        chain_table["work_frame_positive_J"] += shift["work_frame_positive_J"]
    else:
        twin_table["work_frame_positive_J"] -= shift["work_frame_positive_J"]
    twin, chain, truth = (comparison.medians(t, METRICS, 400, 3)
                          for t in (twin_table, chain_table, truth_table))  # fmt: skip
    numbers = method_check.predicted(reported_table(), twin, chain)
    assert ("work_frame_positive_J", 21700.0, "J") in numbers
    table = method_check.check(numbers, twin, chain, truth, 0.05)
    flagged = table[table["beyond"]]
    assert list(flagged["metric"]) == ["work_frame_positive_J"], table
    assert flagged["side"].iloc[0] == wrong
    assert f"the {wrong} is wrong" in flagged["finding"].iloc[0]
    assert (table.loc[~table["beyond"], "side"] == "").all()


def test_the_role_rule_counts_settings_and_derived_numbers_apart():
    """A fit to the flexion difference makes both flexions calibration targets; the chosen inputs
    set the strides kept; derived rows are not counted; no prediction remains."""
    rng = np.random.default_rng([SEED, 5])
    table = strides(rng)
    table["exo_stance_flexion_deg"] = table["phantom_stance_flexion_deg"] / 3
    table["exo_phantom_peak_angle_difference_deg"] = 7.0
    table["work_spring_net_J"] = 0.0
    metrics = (*METRICS, "exo_stance_flexion_deg", "exo_phantom_peak_angle_difference_deg",
               "work_spring_net_J")  # fmt: skip
    rows = [("strides_analysed", "", "60", "1"), ("strides_kept", "", "57", "1"),
            ("phantom_stance_flexion_deg", "3400", "9.0", "deg"),
            ("phantom_stance_flexion_deg", "21700", "9.0", "deg"),
            ("phantom_stance_flexion_median_difference_deg", "", "0.5", "deg"),
            ("exo_stance_flexion_deg", "21700", "3.0", "deg"),
            ("exo_phantom_peak_angle_difference_deg", "21700", "6.0", "deg"),
            ("work_spring_net_abs_max_J", "", "0.0007", "J")]  # fmt: skip
    reported = pd.DataFrame({
        "metric": [r[0] for r in rows],
        "spring_stiffness_N_per_m": [float(r[1]) if r[1] else np.nan for r in rows],
        "value": [r[2] for r in rows], "unit": [r[3] for r in rows], "source": "§3",
    })  # fmt: skip
    targets = {("exo_stance_flexion_deg", 21700.0),
               ("phantom_stance_flexion_median_difference_deg", None)}  # fmt: skip
    medians = comparison.medians(table, metrics, 100, 1)
    out = comparison.compare(reported, medians, 0.05, targets, medians).set_index("key")
    assert (out.loc[["strides_analysed", "strides_kept", "work_spring_net_abs_max_J"],
                    "role"] == "setting").all()  # fmt: skip
    assert "flexion_sd_deg" in out.loc["strides_kept", "role_basis"]
    flexions = ["phantom_stance_flexion_deg@3400", "phantom_stance_flexion_deg@21700"]
    assert (out.loc[flexions, "role"] == "calibration target").all()
    assert (
        out.loc[flexions, "role_basis"]
        .str.contains("through phantom_stance_flexion_median_difference_deg")
        .all()
    )
    assert out.loc["phantom_stance_flexion_median_difference_deg", "role"] == "derived"
    assert out.loc["exo_phantom_peak_angle_difference_deg@21700", "derived_from"] == (
        "phantom_stance_flexion_deg@21700;exo_stance_flexion_deg@21700"
    )
    assert out.loc["exo_stance_flexion_deg@21700", "role"] == "calibration target"
    tally = roles.counts(out["role"], out["within_tolerance"])
    assert "prediction" not in tally and "derived" not in tally
    assert "per-stride difference" in out.loc["exo_phantom_peak_angle_difference_deg@21700",
                                              "role_basis"]  # fmt: skip


def wilcoxon_rows(p: float) -> pd.DataFrame:
    return pd.DataFrame([{"spring_a_N_per_m": 3400.0, "spring_b_N_per_m": 21700.0,
                          "p_adjusted": p, "median_difference": 0.1}])  # fmt: skip


def dunn_rows(metric: str, p: float, delta: float, ci: tuple[float, float]) -> pd.DataFrame:
    return pd.DataFrame([{
        "metric": metric, "analysis": "as_study", "spring_a_N_per_m": 3400.0,
        "spring_b_N_per_m": 21700.0, "n_a": 130, "n_b": 130, "z": 3.0, "p_unadjusted": p / 15,
        "p_adjusted": p, "p_adjust_method": "bonferroni", "cliffs_delta": delta,
        "cliffs_delta_ci_low": ci[0], "cliffs_delta_ci_high": ci[1],
        "cliffs_delta_ci_level": 1 - 0.05 / 15,
    }])  # fmt: skip


def statement(metric: str, called: str) -> pd.DataFrame:
    return pd.DataFrame([{"statement": "1", "metric": metric, "section": "§3",
                          "different": "3400-21700" if called == "different" else "",
                          "not_different": "3400-21700" if called != "different" else "",
                          "stated_test": "", "claim": ""}])  # fmt: skip


@pytest.mark.parametrize(
    ("study", "p", "paired_p", "delta", "true_p", "cause"),
    [
        ("not different", 0.5, 1e-9, 0.05, 0.5, "design (pairing)"),
        ("different", 0.5, 1e-9, 0.05, 0.5, ""),
        ("different", 0.2, 0.2, 0.02, 0.001, "the chain"),
        ("not different", 1e-3, 1e-3, 0.12, 1e-3, "power"),
        ("not different", 1e-9, 1e-9, 0.9, 1e-9, "unexplained"),
        ("different", 0.9, 0.9, 0.02, 0.9, "unexplained"),
        ("different", 1e-9, 1e-9, 0.7, 1e-9, ""),
    ],
)
def test_where_the_study_departs_from_the_design_the_rule_names_the_cause(
    study, p, paired_p, delta, true_p, cause
):
    """Pairing only where the unpaired test alone gives the study's decision, then chain, power,
    unexplained; where the paired test gives it, no cause (the unpaired miss in the detail)."""
    metric = "peak_moment_Nm"
    truth = {metric: pd.DataFrame([[1.0, true_p], [true_p, 1.0]], index=[3400.0, 21700.0],
                                  columns=[3400.0, 21700.0])}  # fmt: skip
    omnibus = pd.DataFrame([{"metric": metric, "friedman_p": paired_p, "mixed_p": paired_p}])
    tost = {(metric, 3400.0, 21700.0): {"tost_margin": 0.1, "tost_margin_source": "test",
                                         "tost_p": 0.3}}  # fmt: skip
    table = significance.compare(
        statement(metric, study), {metric: dunn_rows(metric, p, delta, (delta - 0.1, delta + 0.1))},
        pd.DataFrame(), {metric: wilcoxon_rows(paired_p)}, omnibus, tost,
        {"alpha": 0.05, "study_n": 126.0, "power": 0.8}, truth,
    )  # fmt: skip
    (row,) = table.to_dict("records")
    assert row["cause"] == cause, row["detail"]
    assert list(table.columns) == significance.COLUMNS
    if cause == "power":
        assert row["study_power"] < 0.8 and "power" in row["detail"]
    if cause == "unexplained":
        assert "twin lacks" not in row["detail"]
    if study == "different" and p > 0.05 and paired_p < 0.05:
        assert row["depends_on_ignoring_pairing"] is False
        assert "only the reproduced unpaired test misses it" in row["detail"]
    if study == "not different":
        assert row["tost_margin"] == 0.1 and row["equivalent"] == "not shown equivalent"


def test_every_statement_of_the_study_is_read_and_counted():
    """The reference holds one row per significance statement of §3; the statement naming no
    pair (knee work: 'only slightly', no test) is kept and counted as not compared."""
    statements = reference.read_significance(
        REPO / "raw" / "reference" / "seed000_significance.csv"
    )
    assert len(statements) == 14 and statements["statement"].is_unique
    named = statements[statements["different"].str.len() + statements["not_different"].str.len()
                       > 0]  # fmt: skip
    assert set(statements["metric"]) - set(named["metric"]) == {
        "work_knee_net_J", "work_knee_positive_J", "work_knee_negative_J"}  # fmt: skip
    peak = statements[statements["metric"] == "peak_moment_Nm"].iloc[0]
    assert len(reference.pairs(peak["different"])) == 5
    assert len(reference.pairs(peak["not_different"])) == 10
    # statement 4 fails the unpaired test in one pair and is flipped by pairing in another: it
    # does not hold by ignoring the pairing; statement 2 does (every pair unpaired, one flips)
    table = pd.DataFrame({"statement": ["1", "1", "2", "3", "4", "4"],
                          "agree": [True, False, True, pd.NA, False, True],
                          "study": ["different", "different", "not different", "no test stated",
                                    "not different", "not different"],
                          "paired": ["different", "different", "different", "", "different",
                                     "different"],
                          "depends_on_ignoring_pairing": [False, False, True, pd.NA, False, True],
                          "equivalent": ["", "", "different but equivalent within ±0.6", "",
                                         "not shown equivalent", "equivalent"]})  # fmt: skip
    assert significance.counts(table) == {
        "pairs": 5, "pairs_agree": 3, "pairs_paired_agree": 2, "statements": 3,
        "statements_agree": 1, "statements_paired_agree": 1, "statements_pairing": 1,
        "pairs_pairing": 2, "alike_pairs": 3, "equivalent": 2, "different_but_equivalent": 1,
        "not_compared": 1,
    }  # fmt: skip


def test_a_statement_with_a_pair_written_backwards_is_refused(tmp_path):
    path = tmp_path / "significance.csv"
    frame = statement("peak_moment_Nm", "different").assign(different="21700-3400")
    frame.to_csv(path, index=False)
    with pytest.raises(reference.InputError, match="softer spring first"):
        reference.read_significance(path)
