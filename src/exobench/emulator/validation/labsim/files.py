"""The files a lab would write: per trial the brace CSV (1000 Hz) and the motion-capture CSV
(100 Hz), manifest.csv, and the trial's truth as JSON in truth/ (atomic, byte-deterministic)."""

import json
import os
import tempfile
from collections.abc import Iterable, Mapping, Sequence
from pathlib import Path

import numpy as np

from .rig import BRACE_FORMATS, MANIFEST_COLUMNS, MOCAP_FORMATS, SIDE


def _atomic_text(path: Path, text: str) -> None:
    """Write text to path through a temporary file beside it and a rename."""
    path.parent.mkdir(parents=True, exist_ok=True)
    handle, temporary = tempfile.mkstemp(dir=path.parent, prefix=f".{path.name}.")
    try:
        with os.fdopen(handle, "w", encoding="utf-8", newline="\n") as stream:
            stream.write(text)
        os.chmod(temporary, 0o644)
        os.replace(temporary, path)
    except BaseException:
        Path(temporary).unlink(missing_ok=True)
        raise


def csv_text(formats: Mapping[str, str], rows: np.ndarray) -> str:
    """A header of the columns, then one line per row, each value in its column's format."""
    line = ",".join(formats.values())
    body = "".join(line.format(*row) + "\n" for row in rows.tolist())
    return ",".join(formats) + "\n" + body


def manifest_text(rows: Iterable[Sequence]) -> str:
    """manifest.csv: trial, file, mocap_file, speed, stiffness and side, one trial a line."""
    lines = [",".join(MANIFEST_COLUMNS)]
    lines += [
        ",".join(f"{value:g}" if isinstance(value, float) else value for value in row)
        for row in rows
    ]
    return "\n".join(lines) + "\n"


def write_trial_files(folder: Path, trials: Sequence) -> Path:
    """Each trial's two CSVs and truth/<trial>.json, then manifest.csv; return its path."""
    rows = []
    for trial in trials:
        brace, mocap = f"{trial.name}_brace.csv", f"{trial.name}_mocap.csv"
        _atomic_text(folder / brace, csv_text(BRACE_FORMATS, trial.brace))
        _atomic_text(folder / mocap, csv_text(MOCAP_FORMATS, trial.mocap))
        truth = json.dumps(trial.truth, indent=2, sort_keys=True) + "\n"
        _atomic_text(folder / "truth" / f"{trial.name}.json", truth)
        rows.append(
            (trial.name, brace, mocap, trial.speed_m_per_s, trial.stiffness_Nm_per_rad, SIDE)
        )
    manifest = folder / "manifest.csv"
    _atomic_text(manifest, manifest_text(rows))
    return manifest
