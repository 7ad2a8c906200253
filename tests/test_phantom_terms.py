"""The phantom's library of terms, generated from the assumption table: each acts where its
row says, and only there, and vanishes at its neutral value."""

from __future__ import annotations

import pytest

from exobench import phantom
from exobench.phantom.model import discrepancy, terms
from exobench.phantom.rig import Rig
from exobench.phantom.validation import recordings
from phantom_helpers import mean_cycle, small_config
from term_helpers import assert_acts_where_its_row_says


@pytest.fixture(scope="module")
def observed():
    """Observations of a short twin recording (three springs, every effect off but noise)."""
    import tempfile
    from pathlib import Path

    config = small_config(strides=8, ramps=1, seed=4)
    config["phantom"]["protocol"].update(
        springs_N_per_m=list(recordings.SPRINGS_N_PER_M),
        test_order_N_per_m=list(recordings.SPRINGS_N_PER_M),
    )
    rig = Rig()
    with tempfile.TemporaryDirectory() as tmp:
        manifest = recordings.write(Path(tmp), config, mean_cycle(), rig)
        parts = recordings.engine_parts(recordings.chain_tables(manifest, config, 0.6, rig))
    block = phantom.settings(config)
    settings = {**block["discrepancy"], "engine": config["discrepancy"], "seed": 4}
    return discrepancy.observations(parts, settings, rig, block["chain"])


@pytest.mark.parametrize("name", list(terms.LIBRARY))
def test_a_term_changes_the_observables_it_names_and_no_other(observed, name):
    # on top of the effects it needs (a compliance a friction belongs to) at their start values
    assert_acts_where_its_row_says(discrepancy.problem(), observed[0], name)


def test_the_terms_parameters_are_named_apart_from_the_registry():
    names = [p.name for e in discrepancy.problem().entries.values() for p in e.parameters]
    assert len(names) == len(set(names))
