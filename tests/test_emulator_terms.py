"""The emulator's library of terms, generated from its assumption table: each acts where its row
says, and only there, and vanishes at its neutral value."""

from __future__ import annotations

import numpy as np
import pytest

from emulator_helpers import analysis_settings, emulator_config
from exobench import selection
from exobench.emulator.chain import analysis, triangulation
from exobench.emulator.model import discrepancy, terms
from exobench.emulator.twin import twin
from exobench.selection.families import UnknownFamily
from term_helpers import assert_acts_where_its_row_says


@pytest.fixture(scope="module")
def observed():
    """Observations of two short twin trials (one per speed, the stiffest spring; every effect
    off but noise)."""
    cfg = emulator_config(cuff_compliance=False, transmission_friction=False,
                          encoder_count_drop=False, mocap_alignment=False,
                          soft_tissue_artefact=False)  # fmt: skip
    cfg["protocol"]["duration_s"] = 8.0
    settings = analysis_settings(cfg)
    records = {}
    for i, speed in enumerate((0.8, 1.2)):
        name = twin.trial_name(speed, 3.5)
        rec = twin.simulate(speed, 3.5, cfg, np.random.default_rng([3, i]), name)
        records[name] = analysis.analyse(name, rec.brace, rec.mocap, 3.5, settings)
    qc = triangulation.session({n: r[2] for n, r in records.items()}, 1.5, "per_trial")["trials"]
    parts = [(n, 3.5, r[0], qc[n]) for n, r in records.items()]
    return discrepancy.observations(parts, 40.0, settings["direction_blend_deg_per_s"],
                                    cfg["transmission"], 2,
                                    cfg["controller"]["torque_filter_Hz"])  # fmt: skip


@pytest.mark.parametrize("name", list(terms.LIBRARY))
def test_a_term_changes_the_observables_it_names_and_no_other(observed, name):
    # on top of the effects it needs (a cuff compliance its stiffening belongs to), at their
    # start values
    assert_acts_where_its_row_says(discrepancy.problem(), observed[0], name)


def test_a_family_an_element_has_no_transform_for_raises():
    row = terms.assumptions.Assumption(
        "cuff", "law", "the cuffs", "rigid", ("encoder",),
        (selection.assumptions.Relaxation("crosstalk", "share", "1", "a share", (0.01, 0.1)),),
    )  # fmt: skip
    with pytest.raises(UnknownFamily, match="no term transform for family 'crosstalk' of the"):
        terms.transform_of(row, row.relaxations[0])
    nowhere = terms.assumptions.Assumption(
        "exhaust", "law", "the exhaust", "none", ("encoder",),
        (selection.assumptions.Relaxation("gain", "gain", "1", "g", (0.01, 0.1)),),
    )  # fmt: skip
    with pytest.raises(UnknownFamily, match=r"no term transform for exhaust\.gain"):
        terms.transform_of(nowhere, nowhere.relaxations[0])


def test_a_play_stays_put_until_its_edge_pulls_it_along():
    line = np.array([[0.0, 1.0, 2.0, 1.5, 0.0, -1.0]])
    np.testing.assert_allclose(terms.backlash(line, 1.0),
                               [[0.0, 0.5, 1.5, 1.5, 0.5, -0.5]])  # fmt: skip


def test_a_late_engagement_keeps_the_run_after_the_delay_and_any_later_one():
    engaged = np.array([[0.0, 1.0, 1.0, 1.0, 0.0, 1.0]])
    np.testing.assert_allclose(terms.late_engagement(engaged, 1.5),
                               [[0.0, 0.0, 0.5, 1.0, 0.0, 1.0]])  # fmt: skip
