"""The cluster path: the whole workflow through snakemake-executor-plugin-cluster-generic, with a
submit command that starts each job script as a local background process (no scheduler)."""

from __future__ import annotations

import pandas as pd
import pytest
import yaml

from conftest import CLUSTER_PROFILE, CLUSTER_RUN, REPO, snakemake

pytestmark = [pytest.mark.slow, CLUSTER_RUN]

# Groups of the shipped profiles (workflow/profiles/cluster and slurm) and their member rules.
GROUPS = {
    "phantom_source": {"phantom_calibrate", "phantom_twin"},
    "phantom_study": {
        "phantom_metrics",
        "phantom_statistics",
        "phantom_paired",
        "phantom_summary",
        "phantom_curves",
        "phantom_truth_metrics",
        "phantom_compare",
        "phantom_figures",
    },
    "phantom_engine": {"phantom_discrepancy", "phantom_discrepancy_figure", "phantom_terms_figure"},
    "phantom_report": {"phantom_checks", "phantom_verdict"},
    "emulator_steps": {
        "emulator_summary",
        "emulator_budget",
        "emulator_checks",
        "emulator_compare",
    },
    "emulator_engine": {"emulator_discrepancy", "emulator_verdict"},
    "sts": {
        "sts_kinematics",
        "sts_loads",
        "sts_modules",
        "sts_beam",
        "sts_checks",
        "sts_verdict",
        "sts_fe",
        "sts_figures",
    },
}


@pytest.mark.parametrize("profile", ["cluster", "slurm"])
def test_both_cluster_profiles_group_the_same_rules(profile):
    config = yaml.safe_load((REPO / "workflow" / "profiles" / profile / "config.yaml").read_text())
    assert config["groups"] == {rule: group for group, rules in GROUPS.items() for rule in rules}


def test_whole_workflow_runs_through_the_cluster_profile(cluster_run):
    root, results = cluster_run["root"], cluster_run["results"]
    moved = cluster_run["config"]
    local = ("--executor", "local")
    dry = snakemake(root, "-n", "--configfile", "small.yaml", *moved, *CLUSTER_PROFILE, *local)
    assert "Nothing to be done" in dry.stdout + dry.stderr
    assert (results / "figures" / "phantom" / "fig10_work.pdf").is_file()
    assert (results / "emulator" / "discrepancy.json").is_file()
    # raw and results went where the config put them, nothing into the workflow folder
    assert not (root / "results").exists()
    assert not (root / "raw" / "phantom").exists() and not (root / "raw" / "emulator").exists()

    jobs, record = cluster_run["record"].parent, cluster_run["record"]
    submitted = [line.split() for line in record.read_text().splitlines()]
    names = [name for name, *_ in submitted]
    members = set().union(*GROUPS.values())
    # each group is one cluster job; every other rule is its own job, once (a per-trial rule
    # once per trial)
    once = [name for name in names if name not in ("phantom_chain", "emulator_trial")]
    assert sorted(once) == sorted(set(once))
    # a group job's name is the group's, then its member rules (cut short when long)
    grouped = {
        group: [n for n in names if any(n.startswith(f"{group}_{rule}") for rule in rules)]
        for group, rules in GROUPS.items()
    }
    scripts = {
        name: (jobs / script.rsplit("/", 1)[-1]).read_text() for name, *_, script in submitted
    }
    for group, rules in GROUPS.items():
        assert len(grouped[group]) == 1
        # the group's one job script runs every member rule
        assert all(f"'{rule}:'" in scripts[grouped[group][0]] for rule in rules)
    assert not members & set(names)
    # the per-trial jobs stay out of the groups: one submission per trial
    for rule, group in (("phantom_chain", "phantom"), ("emulator_trial", "emulator")):
        trials = pd.read_csv(cluster_run["raw"] / group / "manifest.csv")["trial"]
        assert names.count(rule) == len(trials) > 1
    resources = {name: (int(mem), int(runtime)) for name, mem, runtime, _ in submitted}
    # declared per rule in workflow/rules (the profile's defaults are 1000 MB and 10 min)
    assert resources["emulator_twin"] == (1000, 30)
    assert resources["phantom_reference_cycle"] == (500, 5)
    # a group asks at least for what its largest member needs, and for its members' time where
    # one waits for another (the sts chain; the engine, then its figures side by side)
    sts_mem, sts_runtime = resources[grouped["sts"][0]]
    assert sts_mem >= 500 and sts_runtime >= 5 + 5 + 5
    engine_mem, engine_runtime = resources[grouped["phantom_engine"][0]]
    assert engine_mem >= 1000 and engine_runtime >= 30 + 5
    for text in scripts.values():
        assert "snakemake" in text and "--target-jobs" in text
