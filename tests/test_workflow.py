"""Whole-workflow runs through the Snakemake command line, as a user runs them."""

from __future__ import annotations

import pyarrow.parquet as pq
import pytest
import yaml

from conftest import SMALL, SMALL_RUN, snakemake

pytestmark = pytest.mark.slow

REFERENCE_TABLE = "phantom/reference/mean_cycle.parquet"


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
    (workflow_copy / "small.yaml").write_text(yaml.safe_dump(SMALL))
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
    dry = snakemake(workflow_copy, "-n", "--configfile", "small.yaml", "--config", *files)
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


@SMALL_RUN
def test_every_group_runs_and_report_builds(small_run):
    assert (small_run / "results" / "sts" / "beam_check.json").is_file()
    assert (small_run / "results" / "emulator" / "summary.csv").is_file()
    snakemake(small_run, "--configfile", "small.yaml", "--report", "report.html")
    html = (small_run / "report.html").read_text()
    assert "reference_mean_cycle.png" in html
    assert "paths.png" in html
    assert "energy_per_step.png" in html
