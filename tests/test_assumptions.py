"""The assumption table: readable in docs/, complete against the rig contract, and the source of
the engine's registry names and term library."""

from __future__ import annotations

import re

import pytest

from conftest import REPO
from exobench.phantom.model import assumptions, effects, terms
from exobench.selection import assumptions as table
from exobench.selection.families import FAMILIES, UnknownFamily
from term_helpers import assert_docs_hold

# What docs/rig.md §1 states, by the name it uses, and the row that holds the assumption.
COVERAGE = {
    # the rig's values (phantom.rig)
    "thigh_length_m": "segment_lengths", "shank_length_m": "segment_lengths",
    "thigh_mass_kg": "thigh_mass", "thigh_com_m": "thigh_com",
    "thigh_inertia_kgm2": "thigh_inertia", "shank_mass_kg": "shank_mass",
    "shank_com_m": "shank_com", "shank_inertia_kgm2": "shank_inertia",
    "pulley_radius_m": "pulley_radius", "chain_ratio": "chain_ratio",
    "tensioner_stiffness_Nm_per_rad": "tensioner",
    # the manifest's spring rate
    "spring_stiffness_N_per_m": "spring",
    # the channels
    "LC_ANKLE_1": "LC_ANKLE_1", "LC_ANKLE_2": "LC_ANKLE_2", "LC_ANKLE_3": "LC_ANKLE_3",
    "LC_SPRING": "LC_SPRING", "SYNC": "clocks",
    # the markers: joint centres, bars, the spring's ends
    "PH_HIP_MED": "segment_lengths", "PH_HIP_LAT": "segment_lengths",
    "PH_KNEE_MED": "knee_markers", "PH_KNEE_LAT": "knee_markers",
    "PH_ANK_MED": "ankle_path", "PH_ANK_LAT": "ankle_path",
    "EX_THIGH_PROX": "bars", "EX_THIGH_DIST": "bars", "EX_SHANK_PROX": "bars",
    "EX_SHANK_DIST": "bars", "EX_SPRING_A": "spring", "EX_SPRING_B": "spring",
    # the protocol
    "clutch_on_pct": "clutch", "clutch_off_pct": "clutch_open",
    "stride_time_s": "clocks",
}  # fmt: skip
# Laws docs/rig.md states in words, and their rows.
LAWS = {
    "hangs from a hip joint that does not move": "hip",
    "straight up and down, directly below the hip": "ankle_path",
    "Hip, knee\nand ankle are hinges": "knee",
    "each bar is parallel to its segment": "bars",
    "their sum is the vertical ankle reaction": "channels_apart",
    "the hip, a hinge without friction": "hip",
    "k_θ = (k_spring − k_tensioner / r²)": "spring",
}


def rig_section() -> str:
    """docs/rig.md §1, the phantom's contract."""
    text = (REPO / "docs" / "rig.md").read_text(encoding="utf-8")
    return text[text.index("## 1.") : text.index("## 2.")]


def test_docs_hold_the_table_as_the_code_defines_it():
    assert_docs_hold("assumptions.md", assumptions.markdown(), "exobench.phantom.model.assumptions")


def test_every_assumption_of_the_rig_contract_has_its_row():
    section = rig_section()
    rig_keys = re.findall(r"^\| `([a-zA-Z_]+(?:_m|_kg|_kgm2|_rad|ratio))` \|", section, re.M)
    labels = re.findall(r"`((?:PH|EX|LC)_[A-Z_0-9]+|SYNC)`", section)
    protocol = re.findall(r"`(clutch_o[nf]+_pct|stride_time_s)`", section)
    stated = {*rig_keys, *labels, *protocol}
    assert len(rig_keys) == 12 and {"LC_SPRING", "SYNC", "EX_SPRING_B"} <= stated
    rows = {row.key for row in assumptions.TABLE}
    assert stated <= set(COVERAGE), sorted(stated - set(COVERAGE))
    assert set(COVERAGE.values()) <= rows
    for words, key in LAWS.items():
        assert words in section, words
        assert key in rows


def test_rows_are_well_formed_and_every_relaxation_is_a_registry_effect_or_a_term():
    keys = [row.key for row in assumptions.TABLE]
    assert len(keys) == len(set(keys))
    for row in assumptions.TABLE:
        assert row.kind in table.KINDS
        assert set(row.observables) <= set(assumptions.OBSERVABLES)
        assert row.relaxations or row.check, row.key
    registry = set()
    for key, (row, r) in assumptions.relaxations().items():
        assert r.family in FAMILIES, key
        assert all(q in assumptions.relaxations() for q in r.requires), key
        low, high = r.visible
        assert 0 < low < high, key
        if r.registry:
            registry.add(r.registry)
            assert effects.REGISTRY[r.registry].description == row.description(r)
        elif r.checked:
            assert row.check, key  # a direct check sees it
        else:
            assert key in terms.LIBRARY, key
    assert registry == set(effects.REGISTRY)  # every registry effect is a row's relaxation
    names = [row.name(r) for row, r in assumptions.relaxations().values()]
    assert len(names) == len(set(names))  # one name per effect


def test_a_family_nothing_declares_raises_and_never_gives_a_neutral_term():
    with pytest.raises(UnknownFamily, match="unknown family 'hysteresis'"):
        table.Relaxation("hysteresis", "width_rad", "rad", "a loop of width w", (0.01, 0.05))
    # a declared family on a row whose transform registry lacks it: the library raises
    row = assumptions.Assumption(
        "LC_ANKLE_1", "channel", "load cell LC_ANKLE_1", "reads as calibrated", assumptions.MOMENTS,
        (table.Relaxation("tilt", "tilt_rad", "rad", "tilted", (0.04, 0.12), signed=True),),
    )  # fmt: skip
    with pytest.raises(UnknownFamily, match="no term transform for family 'tilt' of load cell"):
        terms.transform_of(row, row.relaxations[0])
    knee = assumptions.Assumption("knee", "law", "the knee", "a hinge", assumptions.MOMENTS,
                                  (table.Relaxation("drifting", "drift_per_s", "1/s", "k(t)",
                                                    (0.004, 0.015)),))  # fmt: skip
    with pytest.raises(UnknownFamily, match="'drifting' of the phantom's knee"):
        terms.transform_of(knee, knee.relaxations[0])
