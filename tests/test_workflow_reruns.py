"""Reruns follow every change: a config value reruns exactly the rules downstream of the rules
that read it; editing a package module reruns exactly the rules whose scripts import it."""

from __future__ import annotations

import functools
import os
import re

import pytest
import yaml

from conftest import SMALL_RUN, snakemake
from exobench.plumbing import bench

pytestmark = [pytest.mark.slow, SMALL_RUN]

JOB_ROW = re.compile(r"^(\w+)\s+(\d+)$")

# A config value and the rules that read it (written out by hand: the truth of the test).
CONFIG_CHANGES = [
    ({"phantom": {"chain": {"filter_cutoff_Hz": 5.0}}}, ["phantom_chain"]),
    ({"phantom": {"chain": {"glitches": {"threshold_mad": 10.0}}}}, ["phantom_chain"]),
    ({"phantom": {"calibration": {"strides": 32}}}, ["phantom_calibrate"]),
    # a lab's label map: only the acquisition of a lab's files reads it, not of the twin's
    ({"phantom": {"rig": {"labels": {"SYNC": "Trigger"}}}}, []),
    ({"phantom": {"chain": {"unit_slips": {"length_factor": 4.0}}}}, ["phantom_chain"]),
    # the recordings' length: not the calibration's
    (
        {"phantom": {"protocol": {"strides": 32}}},
        ["phantom_twin", "phantom_metrics", "phantom_figures"],
    ),
    ({"phantom": {"discrepancy": {"max_strides_per_trial": 10}}}, ["phantom_discrepancy"]),
    # the corrected laws' postures balance the load against the links' weights
    # the study's loading (the corrected laws now sit on a modelled seat, sts.body)
    (
        {"sts": {"design_load_N": 1400.0}},
        ["sts_loads", "sts_beam", "sts_fe", "sts_verdict"],
    ),
    # the checks' block: the checks, and the corrected laws built to meet them
    ({"sts": {"checks": {"slight_lean_max_deg": 20.0}}}, ["sts_kinematics", "sts_checks"]),
    ({"sts": {"tuning": {"law": "piecewise"}}}, ["sts_modules"]),
    (
        {"discrepancy": {"bootstrap": 30}},
        ["phantom_discrepancy", "phantom_discrepancy_reported", "emulator_discrepancy"],
    ),
    ({"emulator": {"analysis": {"fault_threshold_deg": 2.0}}}, ["emulator_trial"]),
    ({"emulator": {"budget": {"transmission_loss": 0.25}}}, ["emulator_budget"]),
    # when the lab calibrates the cable: the session's QC, not the per-trial cable reading
    ({"emulator": {"transmission_calibrated": "session"}}, ["emulator_summary"]),
]
# A package module and the rules whose scripts import it, directly or through other modules.
MODULES = {
    "phantom/study/statistics.py": [
        "phantom_statistics",
        "phantom_paired",  # the paired tests adjust their p like the study's tests
        "phantom_summary",
        "phantom_compare",
        "phantom_curves",
        "phantom_figures",
        "phantom_discrepancy_figure",
        "phantom_terms_figure",  # its caption (discrepancy_captions) names the statistics
        "phantom_qc_figure",  # the figures module (plots) reads the spring column's name
    ],
    "sts/smoothing.py": ["sts_loads"],
    "emulator/study/budget.py": ["emulator_budget"],
}


def job_counts(text: str) -> dict[str, int]:
    """Rules in the job table a dry run printed, with their job counts."""
    rows = (JOB_ROW.match(line.strip()) for line in text.splitlines())
    return {row.group(1): int(row.group(2)) for row in rows if row and row.group(1) != "total"}


def job_table(text: str) -> set[str]:
    """Rules in the job table a dry run printed."""
    return set(job_counts(text))


def planned(root, *args: str) -> set[str]:
    """Rules a dry run of the small protocol would run (the job table of ``snakemake -n``)."""
    return job_table(snakemake(root, "-n", "--configfile", "small.yaml", *args).stdout)


@functools.cache
def children(root) -> dict[str, set[str]]:
    """Every rule and the rules that read its outputs, from Snakemake's rule graph (one call,
    not a ``--forcerun`` dry run per test)."""
    graph = snakemake(root, "--rulegraph", "--configfile", "small.yaml").stdout
    out: dict[str, set[str]] = {name: set() for _, name in bench.RULE_NODE.findall(graph)}
    for parent, child in bench.rule_edges(graph):
        out[parent].add(child)
    return out


def rerun_by(root, rules) -> set[str]:
    """What ``--forcerun rules`` would plan: the rules and every rule downstream of them."""
    seen, pending = set(rules), list(rules)
    while pending:
        for child in children(root)[pending.pop()] - seen:
            seen.add(child)
            pending.append(child)
    return seen


def test_the_shared_run_is_up_to_date(small_run):
    assert planned(small_run) == set()


@pytest.mark.parametrize(("change", "readers"), CONFIG_CHANGES)
def test_a_config_value_reruns_exactly_the_rules_downstream_of_its_readers(
    small_run, change, readers
):
    (small_run / "change.yaml").write_text(yaml.safe_dump(change))
    changed = planned(small_run, "change.yaml")
    assert set(readers) <= changed
    assert changed == rerun_by(small_run, readers)


def test_a_dry_run_says_why_each_rule_reruns(small_run):
    (small_run / "change.yaml").write_text(yaml.safe_dump(CONFIG_CHANGES[0][0]))
    text = snakemake(small_run, "-n", "--configfile", "small.yaml", "change.yaml").stdout
    lines = text.splitlines()
    jobs = [i for i, line in enumerate(lines[1:]) if line.startswith("    reason: ")]
    # every job planned (the job table of this very dry run) says why it runs, under its name
    assert {lines[i].split(":")[0] for i in jobs} == job_table(text)
    reader = next(i for i in jobs if lines[i].startswith("phantom_chain: "))
    assert "Params have changed since last execution" in lines[reader + 1]
    assert "input:" not in text
    # the job table once, each reason one short line (file lists as counts), no summary by rule
    assert text.count("Job stats:") == 1 and "Reasons:" not in text
    assert max(len(lines[i + 1]) for i in jobs) < 160


def edited(root, path, *args: str) -> set[str]:
    """Rules a dry run would run after appending a line to ``path`` (content and mtime are
    restored afterwards; Snakemake ignores a newer file whose checksum did not change)."""
    before, content = path.stat(), path.read_bytes()
    try:
        path.write_bytes(content + b"\n")
        return planned(root, *args)
    finally:
        path.write_bytes(content)
        os.utime(path, ns=(before.st_atime_ns, before.st_mtime_ns))


@pytest.mark.parametrize("module", sorted(MODULES))
def test_editing_a_module_reruns_exactly_the_rules_that_import_it(small_run, module):
    touched = edited(small_run, small_run / "src" / "exobench" / module)
    assert set(MODULES[module]) <= touched
    assert touched == rerun_by(small_run, MODULES[module])
    assert planned(small_run) == set()


def test_the_twin_truth_file_is_an_input_of_the_emulator_analysis(small_run):
    path = next((small_run / "raw" / "emulator" / "truth").glob("*.json"))
    touched = edited(small_run, path)
    assert "emulator_trial" in touched
    assert touched == rerun_by(small_run, ["emulator_trial"])


# A per-trial file of each stage and the rule that writes it (by hand: the truth of the test).
PER_TRIAL = [
    ("phantom/filtered", "phantom_chain"),
    ("phantom/angles", "phantom_chain"),
    ("phantom/kinetics", "phantom_chain"),
    ("emulator/steps", "emulator_trial"),
]


@pytest.mark.parametrize(("folder", "writer"), PER_TRIAL)
def test_a_removed_per_trial_file_reruns_its_trials_job_and_what_follows(small_run, folder, writer):
    """A failed job removes its files while the later ones stay; the next run must rebuild them
    and everything after them, however old the restored recordings are: that trial's job only,
    not the other trials'."""
    path = sorted((small_run / "results" / folder).glob("*.parquet"))[0]
    held = path.with_name("held")
    os.replace(path, held)
    try:
        counts = job_counts(snakemake(small_run, "-n", "--configfile", "small.yaml").stdout)
    finally:
        os.replace(held, path)
    assert set(counts) == rerun_by(small_run, [writer])
    assert counts[writer] == 1
    assert planned(small_run) == set()


def test_rule_priorities_never_rise_along_the_rule_graph(small_run):
    """A rule's priority is its remaining critical path (``bench priorities``): never below the
    priority of a rule that reads its outputs."""
    priority, rule = {}, None
    for path in sorted((small_run / "workflow" / "rules").glob("*.smk")):
        for line in path.read_text().splitlines():
            if found := re.match(r"^\s*rule (\w+):", line):
                rule = found.group(1)
            elif found := re.match(r"^\s+priority: (\d+)$", line):
                priority[rule] = int(found.group(1))
    assert priority, "no rule declares a priority"
    for parent, readers in children(small_run).items():
        for reader in readers:
            assert priority.get(parent, 0) >= priority.get(reader, 0), (parent, reader)
