"""MATLAB ``.mat`` recordings (v5 or v7) as a table of the contract's columns (docs/rig.md §3).

Read with ``scipy.io.loadmat``, the maintained reader of MATLAB's v4–v7 formats. Two layouts:

- named variables, one vector per contract column (the lab's names mapped by
  ``emulator.columns``);
- one 2-D array ``[time; channels]``, its rows (or, when the shape says so, its columns) time
  first, then the channels in the order ``emulator.mat_channels`` gives for the file's kind.

A v7.3 file is HDF5, which ``loadmat`` cannot read: it is refused with how to save it readably.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from pathlib import Path

import numpy as np
import pandas as pd

from exobench.errors import InputError

HDF5_SIGNATURE = b"\x89HDF\r\n\x1a\n"
HDF5_OFFSET = 512  # a v7.3 file's HDF5 superblock follows MATLAB's 512-byte user block
RESAVE = "a MATLAB v5 or v7 file (v7.3 is HDF5: save it with save(..., '-v7'))"


def read(
    path: Path,
    columns: tuple[str, ...],
    optional: tuple[str, ...],
    names: Mapping[str, str] | None,
    channels: Sequence[str],
) -> pd.DataFrame:
    """The file's ``columns`` (and the ``optional`` ones it has) under the contract's names, as
    floats; the array layout when ``channels`` is given, else named variables."""
    import scipy.io  # here: every emulator job imports the readers, few read a .mat

    with path.open("rb") as handle:
        head = handle.read(HDF5_OFFSET + len(HDF5_SIGNATURE))
    if head[HDF5_OFFSET:] == HDF5_SIGNATURE:
        raise InputError(path, "<file>", RESAVE, "a v7.3 (HDF5) MAT-file")
    try:
        variables = scipy.io.loadmat(path, squeeze_me=False)
    except (NotImplementedError, ValueError, TypeError, OSError) as error:
        raise InputError(path, "<file>", RESAVE, str(error)) from error
    variables = {k: v for k, v in variables.items() if not k.startswith("__")}
    if channels:
        return _array_layout(path, variables, columns, optional, list(channels))
    return _named_layout(path, variables, columns, optional, names or {})


def _named_layout(path, variables, columns, optional, names) -> pd.DataFrame:
    """One numeric vector per contract column, found under the lab's name for it."""
    lab = {column: str(names.get(column, column)) for column in columns + optional}
    columns = columns + tuple(c for c in optional if lab[c] in variables)
    table = {}
    for column in columns:
        if lab[column] not in variables:
            mapped = "" if lab[column] == column else f" ('{lab[column]}' by emulator.columns)"
            expected = f"variables {', '.join(columns)}{mapped}, or emulator.mat_channels"
            raise InputError(path, lab[column], expected, sorted(variables))
        value = np.asarray(variables[lab[column]])
        if value.dtype.kind not in "biuf" or value.ndim != 2 or min(value.shape) != 1:
            raise InputError(path, lab[column], "a numeric vector", f"{value.dtype} {value.shape}")
        table[column] = value.astype(float).ravel()
    lengths = {len(values) for values in table.values()}
    if len(lengths) > 1:
        found = {c: len(v) for c, v in table.items()}
        raise InputError(path, "<variables>", "vectors of one length", found)
    return pd.DataFrame(table)


def _array_layout(path, variables, columns, optional, channels) -> pd.DataFrame:
    """The one numeric 2-D array with 1 + len(channels) rows (or columns): time, then channels."""
    unknown = sorted(set(channels) - set(columns + optional))
    missing = [c for c in columns[1:] if c not in channels]
    if unknown or missing or columns[0] in channels:
        raise InputError(
            path,
            "emulator.mat_channels",
            f"the channels after time, each of {', '.join(columns[1:] + optional)} once "
            f"(all but {', '.join(optional) or 'none'})",
            channels,
        )
    width = 1 + len(channels)
    arrays = {name: np.asarray(value) for name, value in variables.items()}
    arrays = {
        name: value
        for name, value in arrays.items()
        if value.dtype.kind in "biuf" and value.ndim == 2 and width in value.shape
    }
    if len(arrays) != 1:
        expected = f"one numeric 2-D array [time; channels] with {width} rows or columns"
        raise InputError(path, "<variables>", expected, sorted(arrays) or sorted(variables))
    name, array = next(iter(arrays.items()))
    if array.shape[0] == array.shape[1]:
        raise InputError(path, name, "more samples than channels", f"shape {array.shape}")
    # rows are the channels when the first dimension is the channel count, else columns are
    rows = array if array.shape[0] == width else array.T
    frame = pd.DataFrame(dict(zip([columns[0], *channels], rows.astype(float), strict=True)))
    return frame[[c for c in columns + optional if c in frame.columns]]
