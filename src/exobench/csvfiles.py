"""Reading a recording's CSV file: empty, header-only or unparsable files become InputError."""

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
