"""One writer per results folder: a lock file holding the owner's pid and host.

Snakemake's own lock covers one working directory; two copies of the workflow pointed at the
same ``results_dir`` would otherwise overwrite and delete each other's files.
"""

from __future__ import annotations

import json
import logging
import os
import socket
from pathlib import Path

from exobench.errors import InputError

LOCK_NAME = ".exobench.lock"
LOG = logging.getLogger("exobench")


def lock_path(results_dir: str | Path) -> Path:
    """The lock file of a results folder."""
    return Path(results_dir) / LOCK_NAME


def _owner() -> dict:
    return {"pid": os.getpid(), "host": socket.gethostname()}


def _alive(pid: int) -> bool:
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    except PermissionError:  # exists, owned by someone else
        return True
    return True


def _read(path: Path) -> dict | None:
    try:
        owner = json.loads(path.read_text())
        return {"pid": int(owner["pid"]), "host": str(owner["host"])}
    except FileNotFoundError:
        return None
    except (ValueError, KeyError, TypeError):
        return {"pid": -1, "host": "<unreadable lock file>"}


def acquire(results_dir: str | Path) -> Path:
    """Take the results folder's lock, or raise InputError naming its owner and how to clear it.

    A stale lock (same host, owner pid no longer running) is taken over with a warning.
    """
    path = lock_path(results_dir)
    path.parent.mkdir(parents=True, exist_ok=True)
    me = _owner()
    for _attempt in range(2):
        try:
            descriptor = os.open(path, os.O_CREAT | os.O_EXCL | os.O_WRONLY, 0o644)
        except FileExistsError:
            owner = _read(path)
            if owner is None:
                continue
            if owner == me:
                return path
            if owner["host"] == me["host"] and not _alive(owner["pid"]):
                LOG.warning("taking over the stale lock %s of pid %d", path, owner["pid"])
                path.unlink(missing_ok=True)
                continue
            raise InputError(
                path,
                "lock",
                "a results folder no other run is writing to; if no run of pid "
                f"{owner['pid']} on host {owner['host']} is using it, delete {path} and rerun",
                owner,
            ) from None
        with os.fdopen(descriptor, "w") as handle:
            json.dump(me, handle)
        return path
    raise InputError(path, "lock", "a lock file that can be taken", "raced twice")


def release(results_dir: str | Path) -> None:
    """Remove the results folder's lock if this process holds it."""
    path = lock_path(results_dir)
    if _read(path) == _owner():
        path.unlink(missing_ok=True)
