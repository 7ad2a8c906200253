"""The phantom's library of discovered terms: each acts where it says, and only there."""

from __future__ import annotations

import numpy as np
import pytest

from exobench import phantom, selection
from exobench.phantom.model import discrepancy, terms
from exobench.phantom.rig import Rig
from exobench.phantom.validation import recordings
from phantom_helpers import mean_cycle, small_config


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
        parts = recordings.chain_tables(manifest, config, 0.6, rig)
    block = phantom.settings(config)
    settings = {**block["discrepancy"], "engine": config["discrepancy"], "seed": 4}
    return discrepancy.observations(parts, settings, rig, block["chain"])


def away_from_neutral(parameter: selection.Parameter) -> float:
    """A value well beyond the parameter's negligible size, inside its bounds."""
    if parameter.neutral == 1.0:
        return 1.2
    return float(np.clip(5.0 * (parameter.negligible or 1.0), parameter.low, parameter.high))


@pytest.mark.parametrize("name", list(terms.LIBRARY))
def test_a_term_changes_the_observables_it_names_and_no_other(observed, name):
    data, _ = observed
    problem = discrepancy.problem()
    term = terms.LIBRARY[name]
    values = {p.name: away_from_neutral(p) for p in term.parameters}
    base = selection.predict(problem, data, (), {})
    moved = selection.predict(problem, data, (name,), values)
    changed = {obs for obs in base if not np.allclose(moved[obs], base[obs], rtol=0, atol=1e-12)}
    assert changed and changed <= set(term.observables)
    neutral = {p.name: p.neutral for p in term.parameters}
    back = selection.predict(problem, data, (name,), neutral)
    for obs in base:
        np.testing.assert_allclose(back[obs], base[obs], rtol=1e-9, atol=1e-9)


def test_the_terms_parameters_are_named_apart_from_the_registry():
    names = [p.name for e in discrepancy.problem().entries.values() for p in e.parameters]
    assert len(names) == len(set(names))
