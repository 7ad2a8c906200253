"""Command line: ``python -m exobench.audit FILE.parquet`` shows units, provenance and data."""

from __future__ import annotations

import argparse
import json
import sys

import pandas as pd

from exobench import tables
from exobench.errors import InputError
from exobench.plumbing import provenance


def describe(path: str, rows: int = 5) -> str:
    """Text report of one Parquet file: columns with units, provenance, checksum, first rows."""
    table = tables.read_table(path)
    lines = [f"file: {path}", f"sha256: {provenance.sha256_file(path)}"]
    lines.append(f"rows: {len(table.data)}")
    lines.append("columns (dtype, unit):")
    lines += [
        f"  {name:<40} {table.data[name].dtype!s:<10} {unit}" for name, unit in table.units.items()
    ]
    lines.append("provenance:")
    lines.append(json.dumps(table.provenance, indent=2, sort_keys=True))
    with pd.option_context("display.width", 160, "display.max_columns", 30):
        lines.append(str(table.data.head(rows)))
    return "\n".join(lines)


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("files", nargs="+", help="Parquet files written by the workflow")
    parser.add_argument("--rows", type=int, default=5, help="rows of data to show")
    args = parser.parse_args(argv)
    for path in args.files:
        try:
            print(describe(path, args.rows))
        except InputError as error:
            print(f"exobench.audit: {error}", file=sys.stderr)
            return 2
    return 0


if __name__ == "__main__":
    sys.exit(main())
