"""Whole-workflow reliability: one writer per results folder, same bytes in any folder."""

from __future__ import annotations

import json
import os
import signal
import subprocess
import time

import pytest

from conftest import CLUSTER_RUN, OUTPUTS, SNAKEMAKE, copy_workflow, digests, snakemake
from exobench.plumbing.results_lock import LOCK_NAME

pytestmark = pytest.mark.slow


@CLUSTER_RUN  # compares with the digests the small run saved as built (conftest.OUTPUTS)
def test_two_folders_give_the_same_bytes(cluster_run, small_run):
    """The same protocol run locally in the workflow folder and through the cluster executor
    (per-trial jobs submitted apart) with raw, results and reference data moved deeper
    elsewhere: every raw and result file the same bytes, and no path of either folder in them."""
    local = json.loads((small_run / OUTPUTS).read_text())
    for name in ("raw", "results"):
        cluster = digests(cluster_run[name])
        assert sorted(local[name]) == sorted(cluster)
        differing = [path for path in local[name] if local[name][path] != cluster[path]]
        assert differing == []
    assert LOCK_NAME not in local["results"] and len(local["results"]) > 50
    folder = cluster_run["results"]
    text = b"".join((folder / path).read_bytes() for path in digests(folder))
    assert str(cluster_run["root"]).encode() not in text
    assert str(cluster_run["raw"].parent).encode() not in text


def test_second_concurrent_run_on_one_results_folder_is_refused(tmp_path):
    results = tmp_path / "shared_results"
    first_root = copy_workflow(tmp_path / "a")
    second_root = copy_workflow(tmp_path / "b")
    # the file the first run must leave: its job and the two it needs, not the whole group
    target = "sts_beam"
    snakemake(first_root, target, "-n", "--config", f"results_dir={results}")
    assert not (results / LOCK_NAME).exists()  # a dry run takes no lock
    first = subprocess.Popen(
        [str(SNAKEMAKE), "--cores", "1", target, "--config", f"results_dir={results}"],
        cwd=first_root,
        stdout=subprocess.PIPE,
        stderr=subprocess.STDOUT,
        text=True,
    )
    held = False
    try:
        deadline = time.monotonic() + 120
        while not (results / LOCK_NAME).exists() and first.poll() is None:
            assert time.monotonic() < deadline, "the first run never took the lock"
            time.sleep(0.2)
        # the first run paused while it holds the lock (its running job goes on): the second
        # starts during the first, however short the first's jobs and however loaded the machine
        assert first.poll() is None, first.communicate()[0]
        os.kill(first.pid, signal.SIGSTOP)
        held = True
        assert (results / LOCK_NAME).exists(), "the first run released the lock before its pause"
        second = snakemake(second_root, target, "--config", f"results_dir={results}", check=False)
        os.kill(first.pid, signal.SIGCONT)
        held = False
        log = first.communicate(timeout=600)[0]
    finally:
        if held:
            os.kill(first.pid, signal.SIGCONT)
        if first.poll() is None:
            first.kill()
            first.wait()
    assert second.returncode != 0
    message = second.stdout + second.stderr
    assert "lock" in message and f"delete {results / LOCK_NAME}" in message
    assert first.returncode == 0, log
    assert (results / "sts" / "beam_check.json").is_file()
    assert not (results / LOCK_NAME).exists()  # released at the end
