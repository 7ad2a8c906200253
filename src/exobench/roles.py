"""One role rule for every number a group sets beside its study's: what kind of agreement a row
can show, decided by the same questions in the same order for every table.

1. *measured*: the value comes from a lab's recordings (a finding about the lab and the study);
2. *derived*: the value is a function of other rows alone (named in ``derived_from``); it is
   never counted, so a restated number does not count twice;
3. *calibration target*: something was fitted or chosen so that this value lands near the
   study's (matching it shows the fit);
4. *setting*: what was put in (a protocol, twin or model setting, or a constant chosen without
   this number in view) determines the value; ``determined_by`` names those inputs;
5. *prediction*: nothing fitted or chosen determines the value; ``rests_on`` names the inputs
   taken from a source (the study, the rig contract) that it still rests on.

Only predictions (and a lab's measurements) test the project; every count leaves derived rows
out.
"""

from __future__ import annotations

from collections.abc import Iterable, Sequence
from dataclasses import dataclass, field

import pandas as pd

ROLES = {
    "measured": "from a lab's recordings",
    "derived": "a function of other rows alone (named); not counted",
    "calibration target": "fitted or chosen to match the study's number",
    "setting": "put in: a setting or a chosen constant determines it",
    "prediction": "nothing fitted or chosen determines it",
}
# Columns every comparison table carries for its role: the role, the rows a derived row is a
# function of (``;``-separated keys), and what determines or supports the value.
ROLE_COLUMNS = ["role", "derived_from", "role_basis"]


@dataclass(frozen=True)
class Provenance:
    """What determines one compared value: the facts the role rule reads."""

    lab: bool = False
    derived_from: Sequence[str] = ()
    matched_by: Sequence[str] = ()
    determined_by: Sequence[str] = ()
    rests_on: Sequence[str] = field(default_factory=tuple)


def role_of(facts: Provenance) -> str:
    """The role by the rule's first question that holds: measured, derived, calibration target,
    setting, else prediction."""
    if facts.lab:
        return "measured"
    if facts.derived_from:
        return "derived"
    if facts.matched_by:
        return "calibration target"
    if facts.determined_by:
        return "setting"
    return "prediction"


def basis_of(facts: Provenance) -> str:
    """The role's basis in words: what was matched, put in or rested on."""
    role = role_of(facts)
    if role == "measured":
        return "measured on the lab's recordings"
    if role == "derived":
        return "a function of " + ", ".join(facts.derived_from) + " alone"
    if role == "calibration target":
        return "fitted or chosen to match it: " + ", ".join(facts.matched_by)
    if role == "setting":
        return "determined by what was put in: " + ", ".join(facts.determined_by)
    if facts.rests_on:
        return "nothing fitted or chosen determines it; rests on " + ", ".join(facts.rests_on)
    return "nothing fitted or chosen determines it"


def columns(facts: Provenance) -> dict:
    """The role columns of one row (:data:`ROLE_COLUMNS`)."""
    return {
        "role": role_of(facts),
        "derived_from": ";".join(facts.derived_from),
        "role_basis": basis_of(facts),
    }


def check(table: pd.DataFrame, key: str, where: str) -> None:
    """Raise on an unknown role, or a derived row whose named rows are absent or itself."""
    unknown = sorted(set(table["role"]) - set(ROLES))
    if unknown:
        raise ValueError(f"{where}: unknown role(s) {unknown}; the rule has {list(ROLES)}")
    keys = set(table[key].astype(str))
    for row in table.itertuples(index=False):
        named = "" if pd.isna(row.derived_from) else str(row.derived_from)
        names = [n for n in named.split(";") if n]
        own = str(getattr(row, key))
        if row.role == "derived" and (not names or own in names or not set(names) <= keys):
            raise ValueError(
                f"{where}: derived row {own!r} must name other rows of the table "
                f"(derived_from={names!r})"
            )
        if row.role != "derived" and names:
            raise ValueError(f"{where}: row {own!r} names derived_from but is {row.role!r}")


def counts(roles: Iterable[str], hits: Iterable[bool] | None = None) -> dict[str, tuple[int, int]]:
    """Per counted role (derived left out): (rows, rows within tolerance), n = Σ rows."""
    roles = list(roles)
    hits = [True] * len(roles) if hits is None else [bool(h) for h in hits]
    out: dict[str, tuple[int, int]] = {}
    for role, hit in zip(roles, hits, strict=True):
        if role not in ROLES:
            raise ValueError(f"unknown role {role!r}; the rule has {list(ROLES)}")
        if role == "derived":
            continue
        n, k = out.get(role, (0, 0))
        out[role] = (n + 1, k + int(hit))
    return out
