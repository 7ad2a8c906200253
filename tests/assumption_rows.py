"""The relaxation rows of a generated assumption table (docs/assumptions.md,
docs/emulator_assumptions.md), read from the doc as a reader would: term, parameter, neutral
value, visible sizes, needs."""

import math
import re
from pathlib import Path

# | `key` | name | law | `parameter` (unit) | neutral | visible sizes | registry |
_ROW = re.compile(r"^\| `([^`]+)` \| (.*) \| `([^`]+)` \((.*)\) \| ([^|]+) \| ([^|]+) \| [^|]+ \|$")


def relaxations(doc: Path) -> dict[str, dict]:
    """Term key → its parameter, neutral value, visible sizes (low, high), sign and needs."""
    rows = {}
    for line in doc.read_text(encoding="utf-8").splitlines():
        if match := _ROW.match(line):
            key, law, parameter, _unit, neutral, sizes = (g.strip() for g in match.groups())
            low, high = (float(x.replace("±", "")) for x in sizes.split(" to "))
            rows[key] = {
                "parameter": parameter,
                "neutral": float(neutral),
                "sizes": (low, high),
                "either_sign": "±" in sizes,
                "needs": tuple(re.findall(r"needs `([^`]+)`", law)),
            }
    return rows


def table_lines(doc: Path) -> int:
    """How many lines of the doc are a relaxation's row (start with a term in backticks)."""
    return sum(line.startswith("| `") for line in doc.read_text(encoding="utf-8").splitlines())


def least_visible(row: dict) -> list[float]:
    """A row's smallest visible sizes as values (both signs where ±; a stiffness: its largest)."""
    low, high = row["sizes"]
    if math.isinf(row["neutral"]):  # a stiffness: the largest is nearest the rigid neutral
        return [high]
    if row["either_sign"]:
        return [row["neutral"] + low, row["neutral"] - low]
    return [row["neutral"] + low]
