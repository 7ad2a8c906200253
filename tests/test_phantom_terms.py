"""The phantom's library of terms, generated from the assumption table: each acts where its
row says, and only there, and vanishes at its neutral value."""

from __future__ import annotations

import numpy as np
import pytest

from exobench import phantom, selection
from exobench.phantom.model import discrepancy, effects, terms
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


def test_a_nonlinear_cell_reads_back_its_true_force():
    # where its law rises with the force (|F| < 1/(2|q|) for q < 0)
    force = np.linspace(-300.0, 1200.0, 50)
    for q in (-0.4, 0.3):
        recorded = terms.recorded_by_nonlinear_cell(force, q)
        np.testing.assert_allclose(terms.true_of_nonlinear_cell(recorded, q), force, rtol=1e-12)


def test_a_drifting_clock_lags_each_unit_by_its_time_in_the_trial(observed):
    # ε × a unit's time in its trial: the registry's clock lag of that unit
    data, _ = observed
    problem = discrepancy.problem()
    rate = 2e-4
    drifting = selection.predict(problem, data, ("clocks.drift",), {"clocks.rate_error": rate})
    times = effects.unit_time(data)
    for unit in (0, data.units // 2, data.units - 1):
        alone = data.take(np.array([unit]))
        lag = {"analog_delay_s": rate * float(times[unit])}
        clock = selection.predict(problem, alone, ("clock_offset",), lag)
        for obs in ("moment", "force", "swing"):
            np.testing.assert_allclose(drifting[obs][unit], clock[obs][0], atol=1e-9)
