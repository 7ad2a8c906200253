"""The digital twins' ownership stamp: a twin rewrites only recordings it wrote itself."""

from __future__ import annotations

import json
from pathlib import Path

from exobench import atomic
from exobench.errors import InputError
from exobench.plumbing.provenance import sha256_file

STAMP = "twin_stamp.json"


def write_stamp(folder, files: list[str]) -> None:
    """Record the sha256 of each file the twin wrote in ``folder``."""
    folder = Path(folder)
    stamp = {
        "written_by": "exobench digital twin",
        "files": {f: sha256_file(folder / f) for f in files},
    }
    atomic.write_json(folder / STAMP, stamp)


def check_writable(folder, files: list[str]) -> None:
    """Refuse to overwrite recordings in ``folder`` that the twin did not write itself."""
    folder = Path(folder)
    present = [name for name in files if (folder / name).exists()]
    if not present:
        return
    stamp_path = folder / STAMP
    owned = json.loads(stamp_path.read_text())["files"] if stamp_path.is_file() else {}
    foreign = [n for n in present if owned.get(n) != sha256_file(folder / n)]
    if foreign:
        raise InputError(
            folder / foreign[0],
            "acquisition",
            "'files' for existing recordings (the digital twin would overwrite them); "
            "use --config acquisition=files or another raw_dir",
        )
