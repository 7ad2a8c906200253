"""The paired analysis of the design the study ran (exobench.phantom.study.paired): a planted
paired shift the unpaired test cannot see, the Friedman test's level under within-trajectory
shuffles, and a twin run with repeated, re-mounted trials whose between-trial variance the
spring is tested against. Data generators draw from stated distributions, not from the code
under test; seeds are fixed and printed."""

from __future__ import annotations

import numpy as np
import pandas as pd
import pytest
from scipy import stats as scipy_stats

from exobench import phantom
from exobench.phantom.report import reproduced
from exobench.phantom.rig import Rig
from exobench.phantom.study import paired, significance, statistics
from exobench.phantom.twin import truth, twin
from phantom_helpers import mean_cycle, settings, small_config

SEED = 56
SPRINGS = (3400.0, 6100.0, 9200.0, 13600.0, 18000.0, 21700.0)
PEAK = "peak_moment_Nm"


def table_of(values: np.ndarray, column: str = PEAK, trial_of=None) -> pd.DataFrame:
    """A per-stride metrics table of a (trajectory × spring) array: one trial per spring
    unless ``trial_of`` names each cell's trial."""
    strides, springs = values.shape
    spring = np.tile(np.asarray(SPRINGS[:springs]), strides)
    trial = [f"k{s:05.0f}" for s in spring] if trial_of is None else trial_of.ravel()
    return pd.DataFrame({"trial": trial, "stride": np.repeat(np.arange(strides), springs),
                         "spring_stiffness_N_per_m": spring, "included": True,
                         column: values.ravel()})  # fmt: skip


def planted_shift(rng: np.random.Generator, trajectories: int = 130) -> np.ndarray:
    """Each trajectory's peak moment at one spring (a spread of programmed flexions: 6 ± 1.5
    N·m) copied to all six springs, independent noise of SD 0.01 N·m added, then 0.02 N·m × the
    spring's rank."""
    base = rng.normal(6.0, 1.5, trajectories)
    noise = rng.normal(0.0, 0.01, (trajectories, len(SPRINGS)))
    return base[:, None] + noise + 0.02 * np.arange(len(SPRINGS))[None, :]


def test_a_planted_paired_shift_is_found_in_every_pair_and_never_called_no_effect():
    """Kruskal–Wallis cannot see a shift of 0.02 N·m per spring rank under a 1.5 N·m spread of
    trajectories; matched by trajectory, every pair differs, and the study's 'not different'
    statements are traced to the pairing, never reported as no effect."""
    rng = np.random.default_rng(SEED)
    print(f"seed {SEED}")
    metrics = table_of(planted_shift(rng))
    kruskal, dunn, _ = statistics.test_all(metrics, [PEAK], 0.05, 200, SEED)
    omnibus, pairs = paired.test_all(metrics, [PEAK], 0.05, 1e-6)
    alike = " ".join(f"{a:.0f}-{b:.0f}" for i, a in enumerate(SPRINGS) for b in SPRINGS[i + 1 :])
    statement = pd.DataFrame([{"statement": "3", "metric": PEAK, "section": "§3.2",
                               "different": "", "not_different": alike, "stated_test": "",
                               "claim": "the springs do not differ"}])  # fmt: skip
    wide = paired.matched(metrics, PEAK)
    tost = {(PEAK, a, b): {"tost_margin": 0.01, "tost_margin_source": "test",
                           **paired.tost(wide, a, b, 0.01)}
            for i, a in enumerate(SPRINGS) for b in SPRINGS[i + 1 :]}  # fmt: skip
    table = significance.compare(
        statement, dunn, kruskal, {PEAK: pairs}, omnibus, tost,
        {"alpha": 0.05, "study_n": 126.0, "power": 0.8},
    )  # fmt: skip
    text = " ".join(
        [reproduced.verdict(omnibus, table, None, 0.05),
         reproduced.paired_design(omnibus, pairs, 0.05), reproduced.significance(table)]
    )  # fmt: skip
    # the truth, read only now: a shift of 0.02 N·m per rank at every trajectory
    assert kruskal["p"].iloc[0] > 0.05
    assert len(pairs) == 15 and (pairs["p_adjusted"] < 0.05).all()
    assert (pairs["median_difference"] > 0).all()
    assert omnibus["friedman_p"].iloc[0] < 1e-6 and omnibus["mixed_p"].iloc[0] < 1e-6
    assert (table["reproduced"] == "not different").all() and (table["paired"] == "different").all()
    assert table["depends_on_ignoring_pairing"].all()
    assert (table["cause"] == "design (pairing)").all()
    assert (table["mixed_model"] == "springs differ").all()
    assert (table["equivalent"] == "not shown equivalent").all()
    assert "no effect" not in text.lower() and "no spring effect" not in text.lower()


def test_the_friedman_test_holds_its_level_under_shuffles_within_trajectories():
    """1000 draws (seeds [56, i]) of one table's values shuffled within each trajectory: the
    Friedman omnibus rejects at 5 % in 3.5–6.5 % of them, and a two-sided binomial test at
    α = 0.01 does not reject a 5 % rate."""
    base = planted_shift(np.random.default_rng(SEED))
    print(f"seeds [{SEED}, i], i < 1000")
    rejected = 0
    for draw in range(1000):
        rng = np.random.default_rng([SEED, draw])
        rejected += paired.friedman(rng.permuted(base, axis=1))["friedman_p"] < 0.05
    rate = rejected / 1000
    assert 0.035 <= rate <= 0.065, rate
    assert scipy_stats.binomtest(rejected, 1000, 0.05).pvalue >= 0.01, rejected


def test_the_trial_model_tests_the_spring_against_a_hidden_between_trial_variance():
    """Three mountings per spring, each shifting every stride by a draw of SD 0.3 N·m, and no
    spring effect: matched by trajectory the springs look different, tested against the
    between-trial variance they do not; the trial variance is found near its truth."""
    rng = np.random.default_rng([SEED, 1])
    print(f"seed [{SEED}, 1]")
    trajectories, repeats = 60, 3
    springs = np.repeat(np.asarray(SPRINGS), repeats)
    base = rng.normal(6.0, 1.5, trajectories)
    mounting = rng.normal(0.0, 0.3, springs.size)
    values = base[:, None] + mounting[None, :] + rng.normal(0.0, 0.02, (trajectories, springs.size))
    trials = np.array([f"k{s:05.0f}_r{r % repeats + 1}" for r, s in enumerate(springs)])
    metrics = pd.DataFrame({"trial": np.tile(trials, trajectories),
                            "stride": np.repeat(np.arange(trajectories), springs.size),
                            "spring_stiffness_N_per_m": np.tile(springs, trajectories),
                            "included": True, PEAK: values.ravel()})  # fmt: skip
    result = paired.trial_model(metrics, PEAK)
    naive = paired.friedman(paired.matched(metrics, PEAK))
    # the truth, read only now: a mounting SD of 0.3 N·m (variance 0.09), no spring effect
    assert result["trials_per_spring"] == repeats
    assert naive["friedman_p"] < 1e-6
    assert result["trial_p"] > 0.01
    assert (result["trial_df"], result["trial_df_denominator"]) == (5, 12)
    assert 0.02 < result["trial_variance"] < 0.3


def nested_null(rng: np.random.Generator, trajectories: int = 20, repeats: int = 3):
    """6 springs × 3 mountings (SD 0.3 N·m each), no spring effect, trajectories 6 ± 1.5 N·m."""
    springs = np.repeat(np.asarray(SPRINGS), repeats)
    base = rng.normal(6.0, 1.5, trajectories)
    mounting = rng.normal(0.0, 0.3, springs.size)
    values = base[:, None] + mounting[None, :] + rng.normal(0.0, 0.02, (trajectories, springs.size))
    trials = np.array([f"k{s:05.0f}_r{r % repeats + 1}" for r, s in enumerate(springs)])
    return pd.DataFrame({"trial": np.tile(trials, trajectories),
                         "stride": np.repeat(np.arange(trajectories), springs.size),
                         "spring_stiffness_N_per_m": np.tile(springs, trajectories),
                         PEAK: values.ravel()})  # fmt: skip


def test_the_spring_tested_against_the_trials_holds_its_level():
    """200 null draws (seeds [56, 2, i]) of the nested design: the spring's F on the trial means
    rejects at 5 % in 2.5–9 % of them, and a binomial test at α = 0.01 does not reject 5 %."""
    print(f"seeds [{SEED}, 2, i], i < 200")
    rejected = sum(
        paired.spring_against_trials(nested_null(np.random.default_rng([SEED, 2, i])), PEAK)[
            "trial_p"
        ]
        < 0.05
        for i in range(200)
    )
    assert 0.025 <= rejected / 200 <= 0.09, rejected
    assert scipy_stats.binomtest(rejected, 200, 0.05).pvalue >= 0.01, rejected


@pytest.fixture(scope="module")
def repeated_run():
    """A small twin run with two re-mounted trials of each of two springs (the remount spread
    widened so that the test stays small), through the twin's true per-stride metrics."""
    config = small_config(strides=10, ramps=1, seed=SEED, interface_compliance=55.0,
                          interface_damping=0.8)  # fmt: skip
    block = config["phantom"]
    block["protocol"]["springs_N_per_m"] = [3400, 21700]
    block["protocol"]["test_order_N_per_m"] = [21700, 3400]
    block["protocol"]["trials"]["repeats"] = 3
    block["protocol"]["trials"]["remount"]["interface_stiffness_log_sd"] = 0.3
    trials = list(twin.simulate_trials(mean_cycle(), Rig(), settings(config), {}))
    parts = []
    for trial in trials:
        part = truth.true_metrics(trial.name, trial.spring_stiffness_N_per_m, trial.truth,
                                  block["protocol"])  # fmt: skip
        parts.append(part[(part["stride"] >= 1) & (part["stride"] < 9)].assign(included=True))
    return config, trials, pd.concat(parts, ignore_index=True)


def test_a_repeated_trial_run_names_its_trials_in_random_order_and_remounts_each(repeated_run):
    """Trial names carry spring and repeat, the order mixes the springs, and each mounting
    has its own interface (the twin's true interface deflection differs between repeats)."""
    config, trials, _ = repeated_run
    names = phantom.twin_trial_names(config)
    assert [t.name for t in trials] == names and len(names) == 6
    assert sorted(names) == ["k03400_r1", "k03400_r2", "k03400_r3", "k21700_r1", "k21700_r2",
                             "k21700_r3"]  # fmt: skip
    assert [t.repeat for t in trials] == [int(n[-1]) for n in names]
    springs = [t.spring_stiffness_N_per_m for t in trials]
    assert springs != sorted(springs) and springs != sorted(springs, reverse=True)
    same = [t for t in trials if t.spring_stiffness_N_per_m == 3400.0]
    peaks = [t.truth["interface_deflection_rad"].abs().max() for t in same]
    assert len(set(np.round(peaks, 9))) == 3


def test_a_repeated_trial_run_shows_a_between_trial_variance_tested_against(repeated_run):
    """With three mountings per spring the trial is a random effect: its variance is estimated
    (positive) and the spring is tested against it (F on the trial means)."""
    _, _, metrics = repeated_run
    result = paired.trial_model(metrics, PEAK)
    assert result["trials_per_spring"] == 3
    assert result["trial_variance"] > 0 and np.isfinite(result["trial_p"])
    assert result["trial_note"].startswith("spring tested against the between-trial variance")
    assert (result["trial_df"], result["trial_df_denominator"]) == (1, 4)
    single = paired.trial_model(metrics[metrics["trial"].str.endswith("_r1")], PEAK)
    assert np.isnan(single["trial_p"]) and "confounded" in single["trial_note"]
