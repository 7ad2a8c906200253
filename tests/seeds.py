"""Seeds of the tests that draw their cases: fixed by the case's name in the default suite,
fresh under ``pytest --explore`` (random exploration), printed either way;
``EXOBENCH_SEED=<n>`` replays one."""

from __future__ import annotations

import os
import secrets
import zlib

# Set by conftest.pytest_configure from the --explore option.
EXPLORE = {"on": False}


def fixed(name: str) -> int:
    """The default suite's seed of a drawn case: the CRC-32 of its name."""
    return zlib.crc32(name.encode()) % 2**31


def drawn(name: str) -> int:
    """The seed of a drawn case (fixed, or fresh under --explore), printed to replay it."""
    override = os.environ.get("EXOBENCH_SEED")
    if override:
        seed = int(override)
    else:
        seed = secrets.randbelow(2**31) if EXPLORE["on"] else fixed(name)
    print(f"{name}: seed {seed} (replay with EXOBENCH_SEED={seed})")
    return seed
