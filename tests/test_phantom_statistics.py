"""Statistics wrapper against published known answers (R via scikit-posthocs, R docs)."""

from __future__ import annotations

import numpy as np
import pandas as pd
import pytest

from exobench.phantom.study import statistics

# seaborn's "exercise" data set (pulse by kind), embedded. Known answer: Dunn's test with Holm
# adjustment as computed by R, published in scikit-posthocs' test suite (two-sided p).
EXERCISE_PULSE = {
    "rest": [85, 85, 88, 90, 92, 93, 97, 97, 94, 80, 82, 83, 91, 92, 91,
             83, 83, 84, 87, 88, 90, 92, 94, 95, 97, 99, 96, 100, 97, 100],
    "walking": [86, 86, 84, 93, 103, 104, 90, 92, 93, 95, 96, 100, 89, 96, 95,
                84, 86, 89, 103, 109, 90, 92, 96, 101, 97, 98, 100, 102, 104, 103],
    "running": [93, 98, 110, 98, 104, 112, 98, 105, 99, 87, 132, 120, 94, 110, 116,
                95, 126, 143, 100, 126, 140, 103, 124, 140, 94, 135, 130, 99, 111, 150],
}  # fmt: skip
R_DUNN_HOLM = {("rest", "running"): 9.570998e-09, ("rest", "walking"): 4.390066e-02,
               ("running", "walking"): 1.873208e-04}  # fmt: skip

# Hollander & Wolfe (1973, p. 116), the example of R's kruskal.test and dunn.test docs:
# Kruskal-Wallis chi-squared = 0.7714, df = 2, p-value = 0.68.
MUCOCILIARY = {"normal": [2.9, 3.0, 2.5, 2.6, 3.2], "obstructive": [3.8, 2.7, 4.0, 2.4],
               "asbestosis": [2.8, 3.4, 3.7, 2.2, 2.0]}  # fmt: skip


def long_form(groups: dict) -> tuple[pd.Series, pd.Series]:
    values = pd.Series([v for vs in groups.values() for v in vs], dtype=float)
    labels = pd.Series([k for k, vs in groups.items() for _ in vs])
    return values, labels


def test_kruskal_matches_r_kruskal_test():
    result = statistics.kruskal(*long_form(MUCOCILIARY))
    assert result["H"] == pytest.approx(0.7714, abs=5e-5)
    assert result["df"] == 2
    assert result["p"] == pytest.approx(0.68, abs=5e-3)
    assert result["n"] == 14


def test_dunn_matches_r_holm_two_sided():
    matrix = statistics.dunn(*long_form(EXERCISE_PULSE), p_adjust="holm")
    for (a, b), expected in R_DUNN_HOLM.items():
        assert matrix.loc[a, b] == pytest.approx(expected, rel=1e-5)
        assert matrix.loc[b, a] == pytest.approx(expected, rel=1e-5)


def test_dunn_bonferroni_is_three_times_the_unadjusted_p():
    """Unadjusted p from R's Holm values (step-down: sorted p × 3, 2, 1), then Bonferroni."""
    raw = {}
    for factor, (pair, held) in zip(
        (3, 2, 1), sorted(R_DUNN_HOLM.items(), key=lambda kv: kv[1]), strict=True
    ):
        raw[pair] = held / factor
    matrix = statistics.dunn(*long_form(EXERCISE_PULSE), p_adjust="bonferroni")
    for pair, p in raw.items():
        assert matrix.loc[pair] == pytest.approx(min(1.0, 3 * p), rel=1e-5)


def test_notation_of_seed_000():
    labels = [3400, 6100, 9200]
    p = pd.DataFrame([[1, 1e-5, 1e-5], [1e-5, 1, 0.3], [1e-5, 0.3, 1]], index=labels,
                     columns=labels)  # fmt: skip
    marks = statistics.notation(p, alpha=0.05)
    assert marks == {3400: "(*)", 6100: "(1)", 9200: "(1)"}


def test_summary_statistics():
    frame = pd.DataFrame(
        {
            "spring_stiffness_N_per_m": [1.0] * 4 + [2.0] * 4,
            "included": [True, True, True, False, True, True, True, True],
            "peak_moment_Nm": [1.0, 2.0, 3.0, 100.0, 4.0, 5.0, 6.0, 7.0],
        }
    )
    table = statistics.summary(frame, ["peak_moment_Nm"]).set_index("spring_stiffness_N_per_m")
    assert table.loc[1.0, "median"] == 2.0 and table.loc[1.0, "n"] == 3
    assert table.loc[2.0, "iqr"] == pytest.approx(np.percentile([4, 5, 6, 7], 75) - 4.75)
    assert table.loc[1.0, "sd"] == pytest.approx(1.0)
