"""The Parquet helper: units on every field, provenance, byte-determinism, atomicity."""

from __future__ import annotations

import numpy as np
import pandas as pd
import pyarrow.parquet as pq
import pytest

from exobench import tables
from exobench.errors import InputError

PROVENANCE = {"rule": "test", "inputs": {"a.csv": "0" * 64}, "config_sha256": "1" * 64}


def sample_frame(seed: int = 0) -> pd.DataFrame:
    rng = np.random.default_rng(seed)
    n = 5000
    return pd.DataFrame(
        {
            "stride": np.repeat(np.arange(50), 100),
            "t_s": np.arange(n) / 1000.0,
            "knee_moment_Nm": rng.normal(size=n),
            "spring_stiffness_N_per_m": np.full(n, 3400.0),
            "included": np.ones(n, bool),
        }
    )


def test_units_follow_column_suffixes():
    assert tables.unit_for("knee_moment_Nm") == "N·m"
    assert tables.unit_for("spring_stiffness_N_per_m") == "N/m"
    assert tables.unit_for("exo_stiffness_Nm_per_rad") == "N·m/rad"
    assert tables.unit_for("spring_force_N") == "N"
    assert tables.unit_for("stride") == "1"
    with pytest.raises(KeyError, match="no unit suffix"):
        tables.unit_for("mystery")


def test_every_field_has_unit_metadata_and_provenance(tmp_path):
    path = tables.write_table(tmp_path / "t.parquet", sample_frame(), PROVENANCE)
    schema = pq.read_schema(path)
    units = {field.name: field.metadata[b"unit"].decode() for field in schema}
    assert units == {
        "stride": "1",
        "t_s": "s",
        "knee_moment_Nm": "N·m",
        "spring_stiffness_N_per_m": "N/m",
        "included": "1",
    }
    assert b"pandas" not in schema.metadata
    table = tables.read_table(path)
    assert table.provenance == PROVENANCE
    pd.testing.assert_frame_equal(table.data, sample_frame())


def test_rewrite_is_byte_identical(tmp_path):
    first = tables.write_table(tmp_path / "a.parquet", sample_frame(), PROVENANCE)
    second = tables.write_table(tmp_path / "b.parquet", sample_frame(), PROVENANCE)
    assert first.read_bytes() == second.read_bytes()
    changed = tables.write_table(tmp_path / "c.parquet", sample_frame(seed=1), PROVENANCE)
    assert changed.read_bytes() != first.read_bytes()


def test_column_without_unit_is_refused_and_nothing_written(tmp_path):
    frame = sample_frame().assign(mystery=1.0)
    with pytest.raises(KeyError, match="mystery"):
        tables.write_table(tmp_path / "t.parquet", frame, PROVENANCE)
    assert list(tmp_path.iterdir()) == []


def test_explicit_units_override_and_unknown_names_fail(tmp_path):
    frame = sample_frame().assign(mystery=1.0)
    path = tables.write_table(tmp_path / "t.parquet", frame, PROVENANCE, units={"mystery": "K"})
    assert tables.read_table(path).units["mystery"] == "K"
    with pytest.raises(KeyError, match="absent"):
        tables.write_table(tmp_path / "u.parquet", sample_frame(), PROVENANCE, units={"x": "K"})


def test_failed_write_keeps_previous_file(tmp_path, monkeypatch):
    path = tables.write_table(tmp_path / "t.parquet", sample_frame(), PROVENANCE)
    before = path.read_bytes()

    def explode(*args, **kwargs):
        raise OSError("disk full")

    monkeypatch.setattr(tables.pq, "write_table", explode)
    with pytest.raises(OSError, match="disk full"):
        tables.write_table(path, sample_frame(seed=2), PROVENANCE)
    assert path.read_bytes() == before
    assert sorted(p.name for p in tmp_path.iterdir()) == ["t.parquet"]


def test_reader_names_file_and_field_without_unit(tmp_path):
    path = tmp_path / "plain.parquet"
    sample_frame().to_parquet(path)
    with pytest.raises(InputError, match=r"plain\.parquet: field 'stride': expected 'unit'"):
        tables.read_table(path)


def test_audit_shows_units_and_provenance(tmp_path, capsys):
    from exobench import audit

    path = tables.write_table(tmp_path / "t.parquet", sample_frame(), PROVENANCE)
    assert audit.main([str(path), "--rows", "2"]) == 0
    shown = capsys.readouterr().out
    assert "knee_moment_Nm" in shown and "N·m" in shown
    assert '"rule": "test"' in shown


def test_audit_refuses_a_file_that_is_no_workflow_table_in_one_line(tmp_path, capsys):
    from exobench import audit

    path = tmp_path / "summary.csv"
    path.write_text("a,b\n1,2\n")
    assert audit.main([str(path)]) == 2
    error = capsys.readouterr().err
    assert error.count("\n") == 1 and "summary.csv: field '<file>'" in error


def test_a_missing_column_is_named(tmp_path):
    path = tables.write_table(tmp_path / "few.parquet", pd.DataFrame({"t_s": [0.0]}), {})
    assert list(tables.read_table(path, columns=["t_s"]).data.columns) == ["t_s"]
    expected = r"few\.parquet: field 'knee_moment_Nm': expected a column"
    with pytest.raises(InputError, match=expected):
        tables.read_table(path, columns=["t_s", "knee_moment_Nm"])
