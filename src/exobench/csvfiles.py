"""Reading a recording's CSV file: empty, header-only or unparsable files become InputError;
the files a manifest lists, checked."""

from __future__ import annotations

from pathlib import Path

import pandas as pd

from exobench.errors import InputError


def read_csv_table(path: str | Path, dtype: dict | None = None) -> pd.DataFrame:
    """The rows of a CSV file with a header row; InputError if it has no header or no rows."""
    try:
        table = pd.read_csv(path, dtype=dtype)
    except pd.errors.EmptyDataError as error:
        raise InputError(path, "<file>", "a CSV file with a header row", "an empty file") from error
    except (pd.errors.ParserError, UnicodeDecodeError, ValueError) as error:
        raise InputError(path, "<file>", "a well-formed CSV file", str(error)) from error
    if table.empty:
        raise InputError(path, "rows", "at least one data row", "a header only")
    return table


def check_listed_files(path: Path, table: pd.DataFrame, columns: tuple[str, ...]) -> None:
    """Every cell of the manifest's file ``columns`` names a file beside the manifest (by trial)."""
    for column in columns:
        for trial, file in zip(table["trial"], table[column], strict=True):
            if pd.isna(file) or not str(file).strip():
                raise InputError(path, column, f"a file name (trial {trial})", "an empty cell")
            if not (path.parent / file).is_file():
                expected = f"an existing file relative to the manifest (trial {trial})"
                raise InputError(path, column, expected, file)
