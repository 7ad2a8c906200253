"""The Parquet writer and reader every stage uses: units per field, provenance per file.

Files are byte-deterministic: fixed compression, row-group size and Parquet version, no pandas
metadata, no timestamps. Each field carries ``unit`` metadata; the schema carries the JSON
provenance under ``exobench.provenance``.
"""

from __future__ import annotations

import json
from collections.abc import Mapping
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import pandas as pd
import pyarrow as pa
import pyarrow.parquet as pq

from exobench.atomic import write_atomic, write_json, write_text
from exobench.errors import InputError
from exobench.plumbing.provenance import canonical_json

PROVENANCE_KEY = b"exobench.provenance"
COMPRESSION = "zstd"
# Level 1: with byte-stream-split floats it compresses a filtered trial within 1 % of level 9
# (48.2 vs 47.8 MB) and writes it 5× faster (0.26 vs 1.24 s); writes were most of each stage.
COMPRESSION_LEVEL = 1
ROW_GROUP_SIZE = 1 << 17
# A per-sample table written ``single`` (float32: 24 significant bits, about 1e-7 of a value,
# far below every sensor's resolution: docs/running.md, "Disk") keeps its clock in float64:
# 1 ms steps over minutes need more digits than float32 holds.
SINGLE_KEPT = ("t_s",)

# Column-name suffixes and the unit they stand for; the longest matching suffix wins.
UNIT_SUFFIXES = {
    "_Nms_per_rad": "N·m·s/rad",
    "_Nm_per_Nm": "N·m/(N·m)",
    "_Nm_per_rad": "N·m/rad",
    "_N_per_m": "N/m",
    "_rad_per_s2": "rad/s²",
    "_rad_per_s": "rad/s",
    "_mm_per_s2": "mm/s²",
    "_mm_per_s": "mm/s",
    "_m_per_s2": "m/s²",
    "_deg_per_s": "deg/s",
    "_m_per_s": "m/s",
    "_Nm": "N·m",
    "_N": "N",
    "_rad": "rad",
    "_deg": "deg",
    "_J": "J",
    "_W": "W",
    "_s": "s",
    "_mm": "mm",
    "_m": "m",
    "_V": "V",
    "_Hz": "Hz",
    "_pct": "%",
    "_kg": "kg",
    "_MPa": "MPa",
}
# Identifiers, flags and labels: dimensionless by nature.
DIMENSIONLESS = {
    "trial",
    "stride",
    "n_strides",
    "included",
    "analysed",
    "exclusion_reason",
    "outlier_metrics",
    "outlier_reason",
    "fitted",
    "segmentation",
    "engaged",
    "clutch_level",
    "marker_gap",
    "load_cell_saturated",
    "law",
    "step",
    "heel_strike",
    "term",
    "observable",
}


def unit_for(column: str) -> str:
    """Unit implied by a column name's suffix, '1' for identifiers; KeyError if neither."""
    if column in DIMENSIONLESS:
        return "1"
    for suffix in sorted(UNIT_SUFFIXES, key=len, reverse=True):
        if column.endswith(suffix):
            return UNIT_SUFFIXES[suffix]
    raise KeyError(f"column '{column}' has no unit suffix; pass its unit explicitly")


@dataclass(frozen=True)
class Table:
    """A Parquet file's content: the data, each column's unit and the file's provenance."""

    data: pd.DataFrame
    units: dict[str, str]
    provenance: dict


def write_table(
    path: str | Path,
    data: pd.DataFrame,
    provenance: Mapping,
    units: Mapping[str, str] | None = None,
    single: bool = False,
) -> Path:
    """Atomically write ``data`` to Parquet with unit metadata on every field and provenance;
    ``single``: a per-sample table's floats as float32 (:data:`SINGLE_KEPT` stay float64)."""
    units = dict(units or {})
    if single:
        data = as_single(data)
    arrow = pa.Table.from_pandas(data, preserve_index=False)
    fields = []
    for field in arrow.schema:
        unit = units.pop(field.name, None) or unit_for(field.name)
        fields.append(field.with_metadata({"unit": unit}))
    if units:
        raise KeyError(f"units given for absent columns: {sorted(units)}")
    schema = pa.schema(fields, metadata={PROVENANCE_KEY: canonical_json(dict(provenance))})
    arrow = pa.Table.from_arrays(arrow.columns, schema=schema)

    floats = [f.name for f in arrow.schema if pa.types.is_floating(f.type)]
    others = [f.name for f in arrow.schema if f.name not in floats]

    def write(tmp: Path) -> None:
        pq.write_table(
            arrow,
            tmp,
            compression=COMPRESSION,
            compression_level=COMPRESSION_LEVEL,
            row_group_size=ROW_GROUP_SIZE,
            version="2.6",
            use_dictionary=others or False,
            use_byte_stream_split=floats or False,
            write_statistics=True,
        )

    return write_atomic(path, write)


def as_single(data: pd.DataFrame) -> pd.DataFrame:
    """``data`` with its float64 columns as float32, but the clock (:data:`SINGLE_KEPT`)."""
    wide = [c for c in data.columns if data[c].dtype == np.float64 and c not in SINGLE_KEPT]
    return data.astype(dict.fromkeys(wide, np.float32))


def read_table(path: str | Path, columns: list[str] | None = None) -> Table:
    """Read a Parquet file written by :func:`write_table` (all columns, or the ``columns`` named:
    each must be present; float32 fields come back as float64); every field must carry a
    unit."""
    try:
        with pq.ParquetFile(path) as parquet:  # the footer is parsed once, for both steps
            present = parquet.schema_arrow.names
            missing = [column for column in columns or () if column not in present]
            if missing:
                raise InputError(
                    path, ", ".join(missing), "a column the stage reads", sorted(present)
                )
            arrow = parquet.read(columns=columns)
    except (OSError, pa.ArrowInvalid) as error:
        raise InputError(path, "<file>", "a readable Parquet file", str(error)) from error
    units = {}
    for field in arrow.schema:
        unit = (field.metadata or {}).get(b"unit")
        if unit is None:
            raise InputError(path, field.name, "'unit' field metadata")
        units[field.name] = unit.decode()
    provenance = json.loads((arrow.schema.metadata or {}).get(PROVENANCE_KEY, b"{}"))
    data = arrow.to_pandas()
    single = [c for c in data.columns if data[c].dtype == np.float32]
    return Table(data.astype(dict.fromkeys(single, np.float64)), units, provenance)


def write_csv(path: str | Path, data: pd.DataFrame, provenance: Mapping, index: bool = False):
    """Atomically write a CSV table and its provenance beside it, ``<name>.csv.provenance.json``."""
    return write_document(path, data.to_csv(index=index, lineterminator="\n"), provenance)


def write_document(path: str | Path, text: str, provenance: Mapping) -> Path:
    """Atomically write a text file and its provenance beside it, ``<name>.provenance.json``."""
    path = Path(path)
    write_text(path, text)
    write_json(path.with_name(path.name + ".provenance.json"), dict(provenance))
    return path
