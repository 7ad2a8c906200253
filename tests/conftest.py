"""Shared fixtures: a private copy of the workflow to run Snakemake in."""

from __future__ import annotations

import os
import shutil
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
    """Run the Snakemake command line in ``workdir`` and return the finished process.

    With a copy of the package in ``workdir/src`` (see :func:`small_run`), the workflow and its
    jobs import that copy, so a test may touch its modules without touching the checkout.
    """
    env = dict(os.environ)
    if (workdir / "src").is_dir():
        env["PYTHONPATH"] = str(workdir / "src")
    process = subprocess.run(
        [str(SNAKEMAKE), "--cores", "2", *args],
        cwd=workdir,
        capture_output=True,
        text=True,
        check=False,
        env=env,
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


SMALL = {
    "phantom": {"protocol": {"strides": 8, "ramp_strides": 1}},
    "emulator": {"protocol": {"duration_s": 10.0}},
    "discrepancy": {"bootstrap": 20, "null_draws": 100},
}


@pytest.fixture(scope="session")
def small_run(tmp_path_factory) -> Path:
    """Every group on a small protocol, run once and shared (tests mark themselves
    ``xdist_group("small_run")`` to share it under pytest-xdist). The folder holds its own copy
    of the package (``src/``), so tests may touch modules; they must leave the run up to date."""
    import yaml

    root = copy_workflow(tmp_path_factory.mktemp("small_run"))
    shutil.copytree(REPO / "src", root / "src", ignore=shutil.ignore_patterns("__pycache__"))
    (root / "small.yaml").write_text(yaml.safe_dump(SMALL))
    snakemake(root, "--configfile", "small.yaml")
    return root
