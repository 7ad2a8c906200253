"""Provenance of every output: input checksums, the hash of the config the rule uses, and
the hash of the package source it runs."""

from __future__ import annotations

import hashlib
import json
from collections.abc import Iterable, Mapping
from pathlib import Path

from exobench import __version__

# Where files live does not change what they contain: location keys stay out of the hash.
LOCATION_KEYS = ("raw_dir", "results_dir", "reference_dir")
PACKAGE_ROOT = Path(__file__).resolve().parents[1]
_CHUNK = 1 << 20


def _digest(handle) -> str:
    """SHA-256 hex digest of an open binary file's bytes from its start."""
    digest = hashlib.sha256()
    for block in iter(lambda: handle.read(_CHUNK), b""):
        digest.update(block)
    return digest.hexdigest()


def sha256_file(path: str | Path) -> str:
    """SHA-256 hex digest of a file's bytes."""
    with open(path, "rb") as handle:
        return _digest(handle)


def canonical_json(value: object) -> str:
    """JSON with sorted keys and no insignificant white space, for hashing and files."""
    return json.dumps(value, sort_keys=True, separators=(",", ":"), default=str)


def config_hash(config: Mapping) -> str:
    """SHA-256 of the canonical JSON of a config (block), location keys excluded."""
    kept = {key: value for key, value in config.items() if key not in LOCATION_KEYS}
    return hashlib.sha256(canonical_json(kept).encode()).hexdigest()


def code_sha256(
    files: Iterable[str | Path], root: Path = PACKAGE_ROOT, read=Path.read_bytes
) -> str:
    """SHA-256 over package source files (path within the package ``root``, then bytes as
    ``read`` gives them), in path order."""
    digest = hashlib.sha256()
    for path in sorted(Path(f).resolve() for f in files):
        digest.update(path.relative_to(root).as_posix().encode())
        digest.update(read(path))
    return digest.hexdigest()


def relative_name(path: str | Path, config: Mapping) -> str:
    """Location-independent name of an input (``<raw_dir>/…``, ``<reference_dir>/…``, …).

    Names are ``<raw_dir>/…``, ``<results_dir>/…``, ``<reference_dir>/…`` or relative to the
    working directory (the project): the deepest of these locations that holds the file wins; a
    file outside all of them keeps its path as given.
    """
    resolved = Path(path).resolve()
    roots = [(f"<{key}>", Path(config[key]).resolve()) for key in LOCATION_KEYS if config.get(key)]
    roots.append(("", Path.cwd().resolve()))
    holding = [(tag, root) for tag, root in roots if resolved.is_relative_to(root)]
    if not holding:
        return str(path)
    tag, root = max(holding, key=lambda item: len(item[1].parts))
    relative = resolved.relative_to(root).as_posix()
    return f"{tag}/{relative}" if tag else relative


def build(
    rule: str,
    inputs: Iterable[str | Path],
    config: Mapping,
    code: str,
    locations: Mapping,
) -> dict[str, object]:
    """Provenance record of one rule run: rule, inputs' sha256, config hash and code hash.

    Inputs are named relative to the ``locations``' raw, results and reference folders and
    hashed from their bytes (the files are only read); the config hash is of the config the
    rule uses, ``code`` the :func:`code_sha256` of the package source files it runs (its code
    param's files).
    """
    named = {relative_name(path, locations): sha256_file(path) for path in inputs}
    return {
        "rule": rule,
        "inputs": dict(sorted(named.items())),
        "config_sha256": config_hash(config),
        "exobench_version": __version__,
        "code_sha256": code,
    }


def restrict(record: Mapping, inputs: Iterable[str | Path], locations: Mapping) -> dict:
    """The record of one output of a job that writes several: only the inputs it came from."""
    wanted = {relative_name(path, locations) for path in inputs}
    return {**record, "inputs": {k: v for k, v in record["inputs"].items() if k in wanted}}
