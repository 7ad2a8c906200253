"""Benchmark summary: one folder per rule, every job of a rule counted under it."""

from __future__ import annotations

import numpy as np
import pandas as pd

from exobench.plumbing import bench

HEADER = "s\th:m:s\tmax_rss\tmax_vms\tmax_uss\tmax_pss\tio_in\tio_out\tmean_load\tcpu_time\n"


def _write(folder, rule, job, seconds, rss):
    path = folder / rule / f"{job}.tsv"
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_text(HEADER + f"{seconds}\t0:00:01\t{rss}\t1\t1\t1\t0\t0\t50\t1\n")


def test_jobs_are_grouped_by_rule_folder_whatever_their_names(tmp_path):
    rng = np.random.default_rng(0)
    jobs = {"emulator_trial": ["v08_k00", "v12_k35", "job"], "phantom_filter": ["job"]}
    times = {rule: rng.uniform(0.1, 5.0, len(names)) for rule, names in jobs.items()}
    rss = {rule: rng.uniform(100, 900, len(names)) for rule, names in jobs.items()}
    for rule, names in jobs.items():
        for name, s, r in zip(names, times[rule], rss[rule], strict=True):
            _write(tmp_path, rule, name, s, r)
    table = bench.summary(tmp_path)
    assert sorted(table.index) == sorted(jobs)
    for rule in jobs:
        assert table.loc[rule, "jobs"] == len(jobs[rule])
        assert np.isclose(table.loc[rule, "total_s"], times[rule].sum())
        assert np.isclose(table.loc[rule, "max_job_s"], times[rule].max())
        assert np.isclose(table.loc[rule, "max_rss_MB"], rss[rule].max())


def test_an_empty_folder_gives_an_empty_table_and_a_clear_exit(tmp_path, capsys):
    assert bench.summary(tmp_path).empty
    assert bench.main([str(tmp_path / "absent")]) == 2
    assert "no <rule>/<job>.tsv benchmark files" in capsys.readouterr().err
    (tmp_path / "rule").mkdir()
    (tmp_path / "rule" / "job.tsv").write_text("")  # a job killed before its record
    assert bench.main([str(tmp_path)]) == 2
    assert "job.tsv: field 's, max_rss'" in capsys.readouterr().err


def test_priorities_rank_rules_by_their_remaining_critical_path():
    dot = """digraph snakemake_dag {
        0[label = "a", color = "0.0 0.6 0.85", style="rounded"];
        1[label = "b", color = "0.1 0.6 0.85", style="rounded"];
        2[label = "c", color = "0.2 0.6 0.85", style="rounded"];
        3[label = "d", color = "0.3 0.6 0.85", style="rounded"];
        0 -> 1
        0 -> 2
        1 -> 3
        2 -> 3
    }"""
    edges = bench.rule_edges(dot)
    assert sorted(edges) == [("a", "b"), ("a", "c"), ("b", "d"), ("c", "d")]
    path = bench.remaining_path({"a": 2.0, "b": 7.0, "c": 1.0, "d": 3.0}, edges)
    # a's road: itself, then the longer of b and c, then d
    assert path == {"a": 12.0, "b": 10.0, "c": 4.0, "d": 3.0}
    assert bench.priorities(path, step=5.0) == {"a": 2, "b": 2, "c": 0, "d": 0}


def test_priorities_of_an_empty_folder_is_a_clear_error(tmp_path, capsys):
    assert bench.main(["priorities", str(tmp_path)]) == 2
    assert f"no <rule>/<job>.tsv benchmark files in {tmp_path}" in capsys.readouterr().err


def test_disk_counts_the_recordings_the_manifests_list_and_not_the_truth(tmp_path):
    raw, results = tmp_path / "raw", tmp_path / "results"
    for group, files in {"phantom": ["a.c3d"], "emulator": ["b_brace.csv", "b_mocap.csv"]}.items():
        (raw / group / "truth").mkdir(parents=True)
        (raw / group / "truth" / "t.json").write_bytes(b"x" * 5000)  # the twin's, not counted
        for name in files:
            (raw / group / name).write_bytes(b"r" * 1000)
    pd.DataFrame({"trial": ["a"], "file": ["a.c3d"]}).to_csv(raw / "phantom" / "manifest.csv")
    pd.DataFrame({"trial": ["b"], "file": ["b_brace.csv"], "mocap_file": ["b_mocap.csv"]}).to_csv(
        raw / "emulator" / "manifest.csv"
    )
    (results / "phantom").mkdir(parents=True)
    (results / "phantom" / "t.parquet").write_bytes(b"p" * 6000)
    found = bench.disk(results, raw)
    assert found["recordings_MB"] == 3000 / 1e6 and found["results_MB"] == 6000 / 1e6
    assert found["ratio"] == 2.0
