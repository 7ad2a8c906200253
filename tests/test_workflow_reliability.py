"""Whole-workflow reliability: one writer per results folder, same bytes in any folder."""

from __future__ import annotations

import subprocess
import time
from pathlib import Path

import pytest
import yaml

from conftest import SNAKEMAKE, copy_workflow, snakemake
from exobench.results_lock import LOCK_NAME

pytestmark = pytest.mark.slow

# A small protocol of every group: few strides, short emulator trials, light engines.
SMALL = {
    "phantom": {
        "protocol": {"strides": 12, "ramp_strides": 1},
        "discrepancy": {"max_strides_per_trial": 6},
    },
    "emulator": {
        "protocol": {"stiffnesses_Nm_per_rad": [0.0, 3.5], "duration_s": 8.0},
        "effects": {"encoder_count_drop": {"trials": ["v12_k35"]}},
    },
    "discrepancy": {"bootstrap": 20, "null_draws": 100},
}
SKIPPED = ("logs", "benchmarks")


def outputs(results: Path) -> dict[str, bytes]:
    """Every file under ``results`` except logs and benchmarks, by relative path."""
    names = [
        path.relative_to(results).as_posix()
        for path in sorted(results.rglob("*"))
        if path.is_file() and path.relative_to(results).parts[0] not in SKIPPED
    ]
    return {name: (results / name).read_bytes() for name in names}


def test_two_folders_give_the_same_bytes(tmp_path):
    root = copy_workflow(tmp_path / "wf")
    (root / "small.yaml").write_text(yaml.safe_dump(SMALL))
    runs = []
    for name in ("first", "second"):
        base = tmp_path / name / "deeper" if name == "second" else tmp_path / name
        snakemake(
            root,
            "--configfile",
            "small.yaml",
            "--config",
            f"raw_dir={base / 'raw'}",
            f"results_dir={base / 'results'}",
        )
        runs.append((outputs(base / "raw"), outputs(base / "results")))
    for first, second in zip(runs[0], runs[1], strict=True):
        assert sorted(first) == sorted(second)
        differing = [name for name in first if first[name] != second[name]]
        assert differing == []
    assert LOCK_NAME not in runs[0][1] and len(runs[0][1]) > 50
    raw_text = b"".join(runs[0][1].values())
    assert str(tmp_path).encode() not in raw_text


def test_second_concurrent_run_on_one_results_folder_is_refused(tmp_path):
    results = tmp_path / "shared_results"
    first_root = copy_workflow(tmp_path / "a")
    second_root = copy_workflow(tmp_path / "b")
    snakemake(first_root, "sts", "-n", "--config", f"results_dir={results}")
    assert not (results / LOCK_NAME).exists()  # a dry run takes no lock
    first = subprocess.Popen(
        [str(SNAKEMAKE), "--cores", "1", "sts", "--config", f"results_dir={results}"],
        cwd=first_root,
        stdout=subprocess.PIPE,
        stderr=subprocess.STDOUT,
        text=True,
    )
    try:
        deadline = time.monotonic() + 120
        while not (results / LOCK_NAME).exists() and first.poll() is None:
            assert time.monotonic() < deadline, "the first run never took the lock"
            time.sleep(0.2)
        second = snakemake(second_root, "sts", "--config", f"results_dir={results}", check=False)
        log = first.communicate(timeout=600)[0]
    finally:
        if first.poll() is None:
            first.kill()
            first.wait()
    assert second.returncode != 0
    message = second.stdout + second.stderr
    assert "lock" in message and f"delete {results / LOCK_NAME}" in message
    assert first.returncode == 0, log
    assert (results / "sts" / "beam_check.json").is_file()
    assert not (results / LOCK_NAME).exists()  # released at the end
