"""Whole-workflow runs through the Snakemake command line, as a user runs them."""

from __future__ import annotations

import json
import re

import pyarrow.parquet as pq
import pytest
import yaml

from conftest import CONSOLE, SMALL_RUN, snakemake
from exobench import studies
from exobench.phantom.chain.metrics import METRIC_COLUMNS as PHANTOM_METRICS
from exobench.plumbing import results_index

pytestmark = pytest.mark.slow

REFERENCE_TABLE = "phantom/reference/mean_cycle.parquet"
# The paths a moved raw and results folder give, not the twins' numbers: the fewest strides
# and trials a twin writes (the phantom's six springs are the protocol's; two emulator trials)
TINY = {
    "phantom": {
        "protocol": {"strides": 8, "ramp_strides": 1},
        "calibration": {"strides": 8, "ramp_strides": 1},
    },
    "emulator": {
        "protocol": {
            "speeds_m_per_s": [1.2],
            "stiffnesses_Nm_per_rad": [0.0, 3.5],
            "duration_s": 5.0,
        }
    },
}


def test_stage_rerun_is_byte_identical_with_units(workflow_copy):
    snakemake(workflow_copy, "phantom_reference_cycle")
    table = workflow_copy / "results" / REFERENCE_TABLE
    first = table.read_bytes()
    snakemake(workflow_copy, "phantom_reference_cycle", "--forcerun", "phantom_reference_cycle")
    assert table.read_bytes() == first
    schema = pq.read_schema(table)
    assert all(field.metadata and field.metadata.get(b"unit") for field in schema)
    assert b"exobench.provenance" in schema.metadata


def test_config_overrides_move_raw_and_results(workflow_copy, tmp_path):
    raw, results = tmp_path / "elsewhere_raw", tmp_path / "elsewhere_results"
    (workflow_copy / "small.yaml").write_text(yaml.safe_dump(TINY))
    files = [f"raw_dir={raw}", f"results_dir={results}", "acquisition=files", "seed=7"]
    missing = snakemake(workflow_copy, "-n", "--config", *files, check=False)
    assert missing.returncode != 0
    assert str(raw / "phantom" / "manifest.csv") in missing.stdout + missing.stderr

    synthetic = [f"raw_dir={raw}", f"results_dir={results}", "seed=7"]
    snakemake(
        workflow_copy,
        "phantom_twin",
        "emulator_twin",
        "--configfile",
        "small.yaml",
        "--config",
        *synthetic,
    )
    assert (raw / "phantom" / "manifest.csv").is_file()
    assert (raw / "emulator" / "manifest.csv").is_file()
    # --verbose: every job's reason in full, with all its files
    dry = snakemake(
        workflow_copy, "-n", "--verbose", "--configfile", "small.yaml", "--config", *files
    )
    assert str(results / REFERENCE_TABLE) in dry.stdout
    assert str(results / "phantom" / "acquired" / "k03400_markers.parquet") in dry.stdout
    assert "phantom_twin" not in dry.stdout and "emulator_twin" not in dry.stdout
    # the lab's files read from there (the whole workflow with raw and results moved runs in
    # the cluster test, tests/test_workflow_cluster.py)
    snakemake(workflow_copy, "phantom_acquire", "--configfile", "small.yaml", "--config", *files)
    assert (results / "phantom" / "acquired" / "k03400_markers.parquet").is_file()
    assert not (workflow_copy / "results").exists()
    assert not (workflow_copy / "raw" / "phantom").exists()
    assert not (workflow_copy / "raw" / "emulator").exists()


def report_results(html: str) -> dict:
    """The results an HTML report embeds, by path: name, mimetype, caption (HTML), …"""
    start = list(re.finditer(r"var results = ", html))[-1].end()
    return json.JSONDecoder().raw_decode(html[start:])[0]


@SMALL_RUN
def test_every_group_runs_and_the_report_is_complete(small_run):
    assert (small_run / "results" / "sts" / "beam_check.json").is_file()
    assert (small_run / "results" / "emulator" / "summary.csv").is_file()
    snakemake(small_run, "--configfile", "small.yaml", "--report", "report.html")
    results = report_results((small_run / "report.html").read_text())
    names = {item["name"] for item in results.values()}
    assert {"reference_mean_cycle.png", "paths.png", "energy_per_step.png"} <= names
    # every JSON, CSV or Parquet result a caption mentions is in the report
    produced = {path.name for path in (small_run / "results").rglob("*") if path.is_file()}
    for item in results.values():
        mentioned = set(re.findall(r"[\w.-]+\.(?:json|csv|parquet)\b", item["caption"]))
        assert mentioned & produced <= names, item["name"]
    # Parquet files are attached as Parquet, not as text
    assert {
        item["mime_type"] for item in results.values() if item["name"].endswith(".parquet")
    } == {"application/vnd.apache.parquet"}
    # the tables the captions point to are in the report: Dunn tests, strides, QC, metrics
    labelled = [item for item in results.values() if item.get("labels")]
    assert {"metrics.parquet", "kruskal.csv"} <= names
    assert {item["labels"].get("table") for item in labelled} >= {"strides", "qc"}
    assert sum("metric" in item["labels"] for item in labelled) == len(PHANTOM_METRICS)
    # its first line names the source
    html = (small_run / "report.html").read_text()
    assert "Source: simulated recordings." in html and studies.PHANTOM.title in html
    # a figure's report caption is the caption file beside it
    fig06 = next(item for item in results.values() if item["name"] == "fig06_kinetics.png")
    beside = small_run / "results" / "figures" / "phantom" / "fig06_kinetics.caption.md"
    assert "whiskers: ± 1 SD" in beside.read_text() and "whiskers: ± 1 SD" in fig06["caption"]
    assert "(*)" in fig06["caption"] and "Panel (b)" in fig06["caption"]


@SMALL_RUN
def test_the_results_index_lists_every_file_of_the_run_and_nothing_absent(small_run):
    """index.md: every entry it lists matches a file of the run, every file of the run matches
    an entry it lists, and it says how to build the HTML report."""
    results = small_run / "results"
    text = (results / "index.md").read_text()
    listed = [a or b for a, b in re.findall(r"^- (?:\[`([^`]+)`\]|`([^`]+)`)", text, re.M)]
    files = results_index.results_files(results)
    assert len(listed) > 50
    for pattern in listed:
        assert any(results_index.fnmatchcase(f, pattern) for f in files), pattern
    for path in files:
        assert any(results_index.fnmatchcase(path, p) for p in listed), path
    assert "snakemake --report results/report.html" in text


@SMALL_RUN
def test_the_run_prints_one_line_a_job_and_ends_with_the_group_times(small_run):
    lines = (small_run / CONSOLE).read_text().splitlines()
    assert len(lines) < 100
    assert not [line for line in lines if "input:" in line or line.startswith("INFO ")]
    planned = int(next(line for line in lines if "jobs to run" in line).split()[0])
    jobs = [line for line in lines if re.match(r"^\[ *\d+/\d+\] \w+", line)]
    assert len(jobs) == planned
    ends = [line.split(":")[0] for line in lines if re.search(r": \d+ jobs, \d+:\d\d wall", line)]
    assert ends == ["phantom", "sts", "emulator"]


@SMALL_RUN
def test_summaries_open_with_the_source_the_study_and_the_verdict(small_run):
    """The first screen (40 lines) of each summary.md: where the data come from, the study's
    title, the verdict, what was set beside what was recovered and what is left unexplained;
    the residual tests in plain words in a file of their own; no study by its number."""
    results = small_run / "results"
    for group, study in (("phantom", studies.PHANTOM), ("emulator", studies.EMULATOR)):
        text = (results / group / "summary.md").read_text()
        screen = "\n".join(text.splitlines()[:40])
        assert "simulated recordings of the" in text.splitlines()[0]
        assert text.splitlines()[2].startswith("**Source: simulated recordings.**")
        assert study.title in screen and "## Verdict" in screen
        assert "## Set in the twin, recovered from its recordings" in screen
        assert "## Left unexplained" in screen and "residual_tests.md" in screen
        assert "| noise units" not in text and "size floor (" not in text
        tests = (results / group / "residual_tests.md").read_text()
        assert "within the noise" in tests
        assert studies.reference(study) in text
    phantom = (results / "phantom" / "summary.md").read_text()
    assert "calibration/fit.json" in phantom and "× stated uncertainty" in phantom
    # no interval of zero width printed, no single sample's maximum quoted as the peak
    assert not re.search(r"(-?[\d.]+) \[\1, \1\]", phantom)
    assert "peaks in that window at a median [quartiles]" in phantom
    assert "**Not claimed: drive compliance.**" in phantom
    assert "e-09" not in phantom
    emulator = (results / "emulator" / "summary.md").read_text()
    assert "below its resolution" in emulator
    written = [*results.rglob("*.md"), *results.rglob("*.caption.md")]
    for path in written:
        assert not re.search(r"\bseed 0\d\d\b", path.read_text(), re.I), path
