"""Acquisition stage: one checked C3D trial of the manifest to tidy Parquet tables."""

from __future__ import annotations

from exobench import tables
from exobench.errors import InputError
from exobench.phantom import c3d


def acquire(
    manifest_path, trial: str, markers_out, analog_out, provenance, stride_time_s: float
) -> dict:
    """Read and check one trial listed in the manifest (contract, duration for its ramp
    strides plus one stride of ``stride_time_s``); write markers and analog Parquet."""
    manifest = c3d.read_manifest(manifest_path)
    rows = manifest[manifest["trial"] == trial]
    if rows.empty:
        raise InputError(manifest_path, "trial", f"a row for trial '{trial}'")
    row = rows.iloc[0]
    path = manifest_path.parent / row["file"]
    markers, analog = c3d.read_trial(path)
    c3d.check_duration(path, len(markers), int(row["ramp_strides"]), stride_time_s)
    tables.write_table(markers_out, markers, provenance)
    tables.write_table(analog_out, analog, provenance)
    return row.to_dict()
