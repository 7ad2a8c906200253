"""Shared fixtures: a private copy of the workflow to run Snakemake in."""

from __future__ import annotations

import atexit
import fcntl
import hashlib
import json
import os
import shutil
import subprocess
import sys
import tempfile
from pathlib import Path

import pytest

import seeds
from exobench.plumbing.bench import copy_workflow

REPO = Path(__file__).resolve().parents[1]
SNAKEMAKE = Path(sys.executable).with_name("snakemake")


def pytest_addoption(parser):
    parser.addoption(
        "--explore",
        action="store_true",
        help="random exploration: fresh seeds (printed) for drawn cases, and the explore tests",
    )


def pytest_configure(config):
    config.addinivalue_line(
        "markers", "explore: random exploration with fresh seeds (runs only with --explore)"
    )
    seeds.EXPLORE["on"] = bool(config.getoption("--explore"))


def pytest_collection_modifyitems(config, items):
    if config.getoption("--explore"):
        return
    skip = pytest.mark.skip(reason="random exploration: run with --explore")
    for item in items:
        if "explore" in item.keywords:
            item.add_marker(skip)


def _checkout_outputs() -> dict[str, tuple[int, int]]:
    """(size, mtime in ns) of every file under the checkout's raw/ and results/, by path."""
    folders = (REPO / "raw", REPO / "results")
    files = (p for folder in folders for p in folder.rglob("*") if p.is_file())
    return {str(p.relative_to(REPO)): (p.stat().st_size, p.stat().st_mtime_ns) for p in files}


@pytest.fixture(scope="session", autouse=True)
def checkout_outputs_untouched():
    """The suite adds, changes or removes nothing in the checkout's raw/ or results/ (`make run`
    indexes them after it; a run in the same checkout during the suite fails this too)."""
    before = _checkout_outputs()
    yield
    after = _checkout_outputs()
    touched = sorted(
        path for path in before.keys() | after.keys() if before.get(path) != after.get(path)
    )
    assert not touched, f"tests wrote into the checkout: {touched[:5]}"


@pytest.fixture
def workflow_copy(tmp_path: Path) -> Path:
    """The workflow copied into a fresh folder."""
    return copy_workflow(tmp_path / "wf")


class _Server:
    """This process's :mod:`snakemake_server`: started at the first command line, ended with the
    process (each pytest-xdist worker has its own)."""

    process: subprocess.Popen | None = None
    folder: Path | None = None

    @classmethod
    def run(cls, workdir: Path, args: list[str], env: dict) -> tuple[int, str, str]:
        if cls.process is None or cls.process.poll() is not None:
            if cls.process is None:
                atexit.register(cls.stop)
            cls.stop()  # a server that died: its folder goes too
            cls.folder = Path(tempfile.mkdtemp(prefix="snakemake_server_"))
            server = Path(__file__).with_name("snakemake_server.py")
            cls.process = subprocess.Popen(
                [sys.executable, str(server)], stdin=subprocess.PIPE, stdout=subprocess.PIPE,
                text=True)  # fmt: skip
        out, err = cls.folder / "stdout", cls.folder / "stderr"
        request = {"cwd": os.path.abspath(workdir), "env": env, "args": args,
                   "stdout": str(out), "stderr": str(err)}  # fmt: skip
        cls.process.stdin.write(json.dumps(request) + "\n")
        cls.process.stdin.flush()
        reply = cls.process.stdout.readline()
        if not reply.strip():
            raise AssertionError(f"the Snakemake server ended (exit code {cls.process.wait()})")
        return int(reply), out.read_text(), err.read_text()

    @classmethod
    def stop(cls) -> None:
        if cls.process is not None and cls.process.poll() is None:
            cls.process.stdin.close()
            cls.process.wait()
        if cls.folder is not None:
            shutil.rmtree(cls.folder, ignore_errors=True)


def snakemake(workdir: Path, *args: str, check: bool = True) -> subprocess.CompletedProcess:
    """Run the Snakemake command line in ``workdir`` and return the finished process.

    With a copy of the package in ``workdir/src`` (see :func:`small_run`), the workflow and its
    jobs import that copy, so a test may touch its modules without touching the checkout. The
    command line is forked from a process that has imported Snakemake (``snakemake_server.py``:
    about half a dry run's time), and runs as the ``snakemake`` script would.
    """
    env = dict(os.environ)
    if (workdir / "src").is_dir():
        env["PYTHONPATH"] = str(workdir / "src")
    command = [str(SNAKEMAKE), "--cores", "2", *args]
    code, stdout, stderr = _Server.run(workdir, command[1:], env)
    process = subprocess.CompletedProcess(command, code, stdout, stderr)
    if check and process.returncode != 0:
        raise AssertionError(f"snakemake {args} failed:\n{process.stdout}\n{process.stderr}")
    return process


SMALL = {
    # 30 strides: the phantom statistics tests need 20 included strides per trial; the calibration
    # simulates as many, for speed (its fit then differs from the default's)
    "phantom": {"protocol": {"strides": 30, "ramp_strides": 5}, "calibration": {"strides": 30}},
    "emulator": {"protocol": {"duration_s": 10.0}},
    # the engine is tested elsewhere: here fewer folds, screened candidates and draws
    "discrepancy": {"folds": 3, "screen": 2, "bootstrap": 20, "null_draws": 100},
}
# Tests that share a run mark themselves ``xdist_group(...)``: pytest-xdist gives the group one
# worker. Tests that change a shared run's folder (even for a moment) stay in its group.
SMALL_RUN = pytest.mark.xdist_group("small_run")
CLUSTER_RUN = pytest.mark.xdist_group("cluster_run")
CONSOLE = "console.txt"  # the small run's command-line output, beside its results
OUTPUTS = "outputs.json"  # the small run's raw and result files as it left them, beside them
UNCOMPARED = ("logs", "benchmarks")  # per-run records: times and paths, not results


def digests(folder: Path) -> dict[str, str]:
    """SHA-256 of every file under ``folder`` but those :data:`UNCOMPARED`, by relative path."""
    paths = [p for p in sorted(folder.rglob("*")) if p.is_file()]
    return {
        path.relative_to(folder).as_posix(): hashlib.sha256(path.read_bytes()).hexdigest()
        for path in paths
        if path.relative_to(folder).parts[0] not in UNCOMPARED
    }


def built_once(tmp_path_factory, name: str, build) -> Path:
    """A folder ``build(folder)`` fills once per test session however many pytest-xdist workers
    ask: the first builds it under a file lock in the folder the workers share, the others wait
    and reuse it (a failed build is retried by the next worker that asks)."""
    if "PYTEST_XDIST_WORKER" not in os.environ:
        folder = tmp_path_factory.mktemp(name)
        build(folder)
        return folder
    shared = tmp_path_factory.getbasetemp().parent
    folder, done = shared / name, shared / f"{name}.built"
    with open(shared / f"{name}.lock", "w") as lock:
        fcntl.flock(lock, fcntl.LOCK_EX)
        if not done.exists():
            shutil.rmtree(folder, ignore_errors=True)
            build(folder)
            done.touch()
    return folder


def small_copy(root: Path, small: dict) -> Path:
    """The workflow copied into ``root`` with ``small`` as its config file ``small.yaml``."""
    import yaml

    copy_workflow(root)
    (root / "small.yaml").write_text(yaml.safe_dump(small))
    return root


def _small_run(root: Path) -> None:
    small_copy(root, SMALL)
    shutil.copytree(REPO / "src", root / "src", ignore=shutil.ignore_patterns("__pycache__"))
    run = snakemake(root, "--configfile", "small.yaml")
    (root / CONSOLE).write_text(run.stdout + run.stderr)  # what a user saw
    # before any test touches the run: what another test compares with, from another worker
    outputs = {name: digests(root / name) for name in ("raw", "results")}
    (root / OUTPUTS).write_text(json.dumps(outputs, indent=1, sort_keys=True))


@pytest.fixture(scope="session")
def small_run(tmp_path_factory) -> Path:
    """Every group on a small protocol, run once per session and shared (also across workers,
    :func:`built_once`). The folder holds its own copy of the package (``src/``), so tests may
    touch modules; they must leave the run up to date. Its command-line output is in
    :data:`CONSOLE`, the digests of its raw and result files as built in :data:`OUTPUTS`."""
    return built_once(tmp_path_factory, "small_run", _small_run)


CLUSTER_SUBMIT = REPO / "tests" / "cluster" / "local_submit.sh"
CLUSTER_PROFILE = ("--workflow-profile", "workflow/profiles/cluster")


def _cluster_layout(base: Path) -> dict:
    """Where the cluster run keeps its workflow, moved folders and submit record, and the
    ``--config`` arguments that move raw, results and the reference data."""
    moved = base / "elsewhere" / "deeper"
    config = ("--config", *(f"{key}_dir={moved / key}" for key in ("raw", "results")),
              f"reference_dir={moved / 'raw' / 'reference'}")  # fmt: skip
    return {"root": base / "wf", "raw": moved / "raw", "results": moved / "results",
            "record": base / "jobs" / "submitted.txt", "config": config}  # fmt: skip


def _cluster_run(base: Path) -> None:
    layout = _cluster_layout(base)
    root, record = small_copy(layout["root"], SMALL), layout["record"]
    record.parent.mkdir(parents=True)
    # a lab's data folder: its recordings (written here by the twins) beside the reference data
    shutil.copytree(root / "raw" / "reference", layout["raw"] / "reference")
    submit = f"sh {CLUSTER_SUBMIT} {record} {{name}} {{resources.mem_mb}} {{resources.runtime}}"
    snakemake(
        root,
        "--configfile",
        "small.yaml",
        *layout["config"],
        *CLUSTER_PROFILE,
        "--cluster-generic-submit-cmd",
        submit,
        "--seconds-between-status-checks",
        "1",
    )


@pytest.fixture(scope="session")
def cluster_run(tmp_path_factory) -> dict:
    """The small protocol of :func:`small_run` again, through the shipped cluster profile and
    snakemake-executor-plugin-cluster-generic (a submit command that starts each job script as
    a local background process and records its name and resources), with raw, results and the
    reference data moved by config into a deeper folder elsewhere; built once per session
    (:func:`built_once`). Returns the workflow folder, the moved folders, the submit record and
    the ``--config`` arguments."""
    return _cluster_layout(built_once(tmp_path_factory, "cluster_run", _cluster_run))
