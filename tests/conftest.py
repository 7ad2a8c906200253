"""Shared fixtures: a private copy of the workflow to run Snakemake in."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import pytest

from exobench.bench import copy_workflow

REPO = Path(__file__).resolve().parents[1]
SNAKEMAKE = Path(sys.executable).with_name("snakemake")


@pytest.fixture
def workflow_copy(tmp_path: Path) -> Path:
    """The workflow copied into a fresh folder."""
    return copy_workflow(tmp_path / "wf")


def snakemake(workdir: Path, *args: str, check: bool = True) -> subprocess.CompletedProcess:
    """Run the Snakemake command line in ``workdir`` and return the finished process."""
    process = subprocess.run(
        [str(SNAKEMAKE), "--cores", "2", *args],
        cwd=workdir,
        capture_output=True,
        text=True,
        check=False,
    )
    if check and process.returncode != 0:
        raise AssertionError(f"snakemake {args} failed:\n{process.stdout}\n{process.stderr}")
    return process


SMALL_PHANTOM = {"phantom": {"protocol": {"strides": 30, "ramp_strides": 5}}}


@pytest.fixture(scope="session")
def phantom_run(tmp_path_factory) -> Path:
    """The default twin with 30 strides per trial, run through the whole phantom group."""
    import yaml

    root = copy_workflow(tmp_path_factory.mktemp("phantom_run"))
    (root / "small.yaml").write_text(yaml.safe_dump(SMALL_PHANTOM))
    snakemake(root, "phantom", "--configfile", "small.yaml")
    return root
