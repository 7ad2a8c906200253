"""Readings before causes: every reading of the study's law through the same checks, and the
verdict on what the study's words admit, what rejects each reading and whether a cause can be
named.

A reading is rejected by a check it fails that another admitted reading holds (the reading, not
the law, decides that check); a check that every admitted reading fails is the law's own, the
same whichever way the text is read. The readings that fail no check of their own survive. A
cause is named only where the surviving readings agree on it: each reading's odd signs (the
coordinates whose sense in the forward frame differs from a human's, CD φ3, BC φ3 − φ2,
AB φ3 − φ2 + φ1) must be the same for all of them; otherwise the verdict names the ambiguity
and what would settle it.
"""

from __future__ import annotations

from collections.abc import Mapping

import numpy as np
import pandas as pd

from exobench.sts.kinematics import CONVENTIONS
from exobench.sts.laws import Law
from exobench.sts.motion import COORDINATES

SETTLE = (
    "a sentence or figure fixing the way the subject faces along Dx (Fig. 2b drawn with the "
    "subject), or a measurement of the prototype's shank tilt at the seat (knee ahead of or "
    "behind the ankle)"
)


def odd_signs(law: Law) -> list[str]:
    """The coordinates whose sense in the forward frame differs from a human's, in any link."""
    forward = law.facing * np.array(law.signs)
    human = CONVENTIONS["corrected"]
    differs = np.any((np.sign(forward) != np.sign(human)) & (human != 0), axis=0)
    return [COORDINATES[i] for i in np.flatnonzero(differs)]


def failed(table: pd.DataFrame, law: str) -> dict[str, list[str]]:
    """A law's violated checks by category, in table order."""
    rows = table[(table["law"] == law) & (table["decision"] == "violated")]
    return {c: list(g["check"]) for c, g in rows.groupby("category", sort=False)}


def verdict(table: pd.DataFrame, readings: Mapping[str, tuple[Law, str, bool]]) -> dict:
    """Admitted, rejected, survivors, common failures and cause or ambiguity from the checks."""
    per = {name: failed(table, name) for name in readings}
    admitted = [n for n, (_, _, ok) in readings.items() if ok]
    sets = {n: {c for checks in per[n].values() for c in checks} for n in readings}
    common = set.intersection(*(sets[n] for n in admitted)) if admitted else set()
    out = {}
    for name, (law, basis, ok) in readings.items():
        own = {cat: [c for c in checks if c not in common] for cat, checks in per[name].items()}
        own = {cat: checks for cat, checks in own.items() if checks}
        status = ("survives" if not own else "rejected") if ok else "not admitted"
        out[name] = {
            "basis": basis,
            "admitted": ok,
            "status": status,
            "failed": per[name],
            "rejected_by": own,
            "odd_signs": odd_signs(law),
        }
    survivors = [n for n in admitted if out[n]["status"] == "survives"]
    signs = {tuple(out[n]["odd_signs"]) for n in survivors}
    order = list(dict.fromkeys(table["check"]))
    result = {
        "readings": out,
        "admitted": admitted,
        "survivors": survivors,
        "common_failures": [c for c in order if c in common],
    }
    listing = "; ".join(f"{n}: " + (", ".join(out[n]["odd_signs"]) or "none") for n in survivors)
    if len(signs) == 1:
        result["cause"] = {
            "readings": survivors,
            "odd_signs": list(next(iter(signs))),
            "law_own_failures": result["common_failures"],
        }
        result["ambiguity"] = None
    else:
        result["cause"] = None
        result["ambiguity"] = (
            f"{len(survivors)} readings survive and differ in their odd signs ({listing})"
            if survivors
            else "no admitted reading survives: each fails a check another holds"
        )
    result["settle"] = SETTLE if result["cause"] is None else None
    return result
