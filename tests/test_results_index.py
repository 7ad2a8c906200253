"""The results folder's index: a registry of glob patterns, one line each; a file no entry
describes stops it, naming the file (the whole-run check is in test_workflow.py)."""

from __future__ import annotations

import pytest

from exobench.errors import InputError
from exobench.plumbing import results_index


def test_a_results_file_no_entry_describes_stops_the_index_naming_it(tmp_path):
    (tmp_path / "phantom").mkdir()
    (tmp_path / "phantom" / "summary.md").write_text("x")
    (tmp_path / "phantom" / "new_table.csv").write_text("x")
    with pytest.raises(InputError, match=r"phantom/new_table\.csv") as error:
        results_index.build(tmp_path)
    assert "results_index.ENTRIES" in str(error.value)
    (tmp_path / "phantom" / "new_table.csv").unlink()
    assert "[`phantom/summary.md`](phantom/summary.md)" in results_index.build(tmp_path)


def test_every_entry_is_reachable_and_figures_cover_their_three_files():
    """No entry is shadowed by an earlier one, and a figure's entry covers its PNG, PDF and
    caption."""
    for group, rows in results_index.ENTRIES.items():
        for pattern, _ in rows:
            example = pattern.replace("*", "x")
            assert results_index.entry(example)[1] == pattern, (group, pattern)
    for suffix in ("png", "pdf", "caption.md"):
        found = results_index.entry(f"figures/phantom/fig10_work.{suffix}")
        assert found[0] == "phantom"
    assert results_index.entry("logs/phantom_metrics/job.log")[0] == results_index.RUN
