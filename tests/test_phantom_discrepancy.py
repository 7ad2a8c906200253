"""Hidden-effect tests of the phantom discrepancy engine, run through Snakemake as a lab would.

Each case writes twin recordings (docs/rig.md files only: no truth, no twin stamp) with a hidden
truth drawn at random — one registry effect or two, at a magnitude inside the entry's
documented detectable range — or none, or an effect no registry entry describes (made here:
a progressive spring, whose tension grows with the square of its stretch on top of Hooke's
law, 5–10 % extra at the peak). The phantom rules then run with ``acquisition=files`` and
the report is compared with the hidden truth only in the final assertions. The seed is
printed; more seeds:
``EXOBENCH_DISCREPANCY_SEEDS=13,14 pytest tests/test_phantom_discrepancy.py``.
"""

from __future__ import annotations

import json
import os

import numpy as np
import pytest
import yaml

from conftest import copy_workflow, snakemake
from exobench.phantom.model import effects
from exobench.phantom.rig import Rig
from exobench.phantom.twin import twin
from exobench.phantom.validation import recordings, twin_arm
from exobench.plumbing import stamp
from phantom_helpers import mean_cycle, settings, workflow_config

pytestmark = pytest.mark.slow

FAST_ENGINE = {
    "phantom": {"discrepancy": {"max_strides_per_trial": 8}},
    "discrepancy": {"folds": 3, "bootstrap": 20, "null_draws": 100},
}
SEEDS = [int(s) for s in os.environ.get("EXOBENCH_DISCREPANCY_SEEDS", "11").split(",")]
CASES = ("registry", "none", "outside registry")


def hidden_truth(case: str, rng) -> dict:
    """The hidden effects of a case: registry effects with magnitudes in their detectable range."""
    if case != "registry":
        return {}
    names = list(effects.REGISTRY)
    chosen = list(rng.choice(names, size=int(rng.integers(1, 3)), replace=False))
    for name in list(chosen):
        chosen += [r for r in effects.REGISTRY[name].requires if r not in chosen]
    return {str(name): twin_arm.magnitudes(effects.REGISTRY[name], rng, widen=1.0)
            for name in chosen}  # fmt: skip


def write_lab_recordings(folder, case: str, hidden: dict, seed: int, rng) -> None:
    config = recordings.twin_config(workflow_config(), hidden, strides=10, seed=seed)
    trials = list(twin.simulate_trials(mean_cycle(), Rig(), settings(config), {}))
    if case == "outside registry":
        share = rng.uniform(0.05, 0.10)  # a progressive spring: this much extra at the peak
        for trial in trials:
            stretch = trial.analogs["LC_SPRING"] - np.median(trial.analogs["LC_SPRING"])
            pulled = np.maximum(stretch, 0.0)
            trial.analogs["LC_SPRING"] += share * pulled**2 / pulled.max()
    twin.write_recordings(trials, folder / "phantom", {"rule": "test"}, ramp_strides=1)
    for path in (folder / "phantom").glob("truth/*"):
        path.unlink()
    (folder / "phantom" / stamp.STAMP).unlink()


@pytest.mark.parametrize("seed", SEEDS)
@pytest.mark.parametrize("case", CASES)
def test_engine_names_the_hidden_effect_or_says_what_is_unexplained(tmp_path, case, seed):
    rng = np.random.default_rng([seed, CASES.index(case)])
    hidden = hidden_truth(case, rng)
    print(f"seed {seed} (EXOBENCH_DISCREPANCY_SEEDS), case {case}")
    raw, results = tmp_path / "lab", tmp_path / "out"
    write_lab_recordings(raw, case, hidden, seed, rng)
    root = copy_workflow(tmp_path / "wf")
    config = FAST_ENGINE
    if case == "outside registry":  # the term search kept small: what it finds is the
        # open-world arm's (tests/test_phantom_openworld.py)
        config = {**FAST_ENGINE, "discrepancy": {**FAST_ENGINE["discrepancy"], "screen_terms": 3,
                                                 "max_terms": 1}}  # fmt: skip
    (root / "fast.yaml").write_text(yaml.safe_dump(config))
    snakemake(root, "phantom_discrepancy", "--configfile", "fast.yaml", "--config",
              f"raw_dir={raw}", f"results_dir={results}", "acquisition=files")  # fmt: skip
    report = json.loads((results / "phantom" / "discrepancy.json").read_text())
    found = {f["effect"]: f for f in report["effects_found"]}

    if case == "outside registry":
        assert report["unexplained"]["flag"], report["unexplained"]
        assert found == {}, list(found)
        assert "Left unexplained" in report["cause"]
        return
    assert set(found) == set(hidden), (report["selected"], hidden)
    assert not report["unexplained"]["flag"], report["unexplained"]
    for name, values in hidden.items():
        for parameter in effects.REGISTRY[name].parameters:
            fitted = found[name]["parameters"][parameter.name]
            truth = values[parameter.name]
            assert parameter.strength(fitted) == pytest.approx(parameter.strength(truth), rel=0.3)
    if not hidden:
        assert report["cause"].startswith("none")
