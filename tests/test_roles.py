"""The one role rule: the first question that holds decides, derived rows are never counted."""

import pandas as pd
import pytest

from exobench import roles
from exobench.roles import Provenance


def test_first_question_that_holds_decides():
    assert roles.role_of(Provenance(lab=True, matched_by=("k",))) == "measured"
    assert roles.role_of(Provenance(derived_from=("a",), matched_by=("k",))) == "derived"
    assert roles.role_of(Provenance(matched_by=("k",), determined_by=("f",))) == (
        "calibration target"
    )
    assert roles.role_of(Provenance(determined_by=("friction",))) == "setting"
    facts = Provenance(rests_on=("Heer's κ",))
    assert roles.role_of(facts) == "prediction"
    assert "Heer's κ" in roles.basis_of(facts)


def test_derived_rows_name_other_rows_and_are_not_counted():
    rows = [
        {"key": "a", **roles.columns(Provenance(matched_by=("theta_eq",)))},
        {"key": "b", **roles.columns(Provenance(derived_from=("a",)))},
        {"key": "c", **roles.columns(Provenance())},
    ]
    table = pd.DataFrame(rows)
    roles.check(table, "key", "t.csv")
    assert table.loc[1, "role"] == "derived" and table.loc[1, "derived_from"] == "a"
    got = roles.counts(table["role"], [True, False, False])
    assert got == {"calibration target": (1, 1), "prediction": (1, 0)}


def test_check_refuses_unknown_role_and_dangling_derivation():
    bad = pd.DataFrame([{"key": "a", "role": "twin setting", "derived_from": ""}])
    with pytest.raises(ValueError, match="unknown role"):
        roles.check(bad, "key", "t.csv")
    dangling = pd.DataFrame([{"key": "a", "role": "derived", "derived_from": "z"}])
    with pytest.raises(ValueError, match="must name other rows"):
        roles.check(dangling, "key", "t.csv")
    with pytest.raises(ValueError, match="unknown role"):
        roles.counts(["guess"])
