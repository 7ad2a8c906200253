"""Terms per block of observables (issue 54, item 1): where no effect or term joins two
observables, a misfit in one names nothing wrong in the other and silences no term the other
earns.

A toy group observes two curves per unit: y, with a noise of 0.05, and z, a controller's output
recorded to 0.001. Every entry shows in one of them. The data carry, in y, an offset the term
library holds and, in z, a bump nothing in the registry or the library makes (its residual, in
z's own units, dwarfs y's). Data are drawn here from a printed seed; the truth is read only in
the final assertions.
"""

from __future__ import annotations

from dataclasses import replace

import numpy as np

from exobench import selection
from exobench.selection import blocks
from test_claims_per_observable import X, two_curves

SEED = 29
P = selection.Parameter
SCALES = {"y": 0.05, "z": 0.001}


def _gain(observable: str):
    def transform(state, values, data):
        return {**state, observable: state[observable] * values[f"gain_{observable}"]}

    return transform


def _offset(state, values, data):
    return {**state, "y": state["y"] + values["offset_y"]}


def _tilt(state, values, data):
    return {**state, "z": state["z"] + values["tilt_z"] * X}


REGISTRY = {
    o: selection.Effect(o, f"a gain of {o}", (P(f"gain_{o}", "1", 0.2, 5.0, f"gain of {o}",
                                                start=1.0, neutral=1.0),), (o,), _gain(o))
    for o in ("y", "z")
}  # fmt: skip
TERMS = {
    "offset": selection.Effect("offset", "an offset of y", (P("offset_y", "1", -2.0, 2.0,
                               "offset of y", log=False, start=0.0, negligible=0.01),), ("y",),
                               _offset),
    "tilt": selection.Effect("tilt", "a tilt of z", (P("tilt_z", "1", -2.0, 2.0, "slope of z",
                             log=False, start=0.0, negligible=0.01),), ("z",), _tilt),
}  # fmt: skip


def two_blocks(noise: dict) -> selection.Problem:
    """The toy problem: y and z, each x per unit in the baseline, z exact to its resolution."""
    return replace(two_curves(noise), registry=REGISTRY, terms=TERMS, exact=("z",))


def test_the_observables_fall_into_the_blocks_no_entry_joins():
    problem = two_blocks({})
    assert blocks.blocks(problem) == [("y",), ("z",)]
    part = blocks.block_problem(problem, ("y",))
    assert list(part.registry) == ["y"] and list(part.terms) == ["offset"]
    both = selection.Effect("both", "a gain of both", (P("g", "1", 0.2, 5.0, "gain", start=1.0,
                            neutral=1.0),), ("y", "z"), _gain("y"))  # fmt: skip
    assert blocks.blocks(replace(problem, terms={**TERMS, "both": both})) == [("y", "z")]


def test_a_term_is_named_on_its_block_while_the_other_block_misfits():
    print(f"seed {SEED}")
    rng = np.random.default_rng([SEED, 1])
    units, gain, offset = 60, rng.uniform(1.1, 1.3), rng.uniform(0.2, 0.4)
    bump = rng.uniform(0.05, 0.1) * np.sin(2.0 * np.pi * 2.0 * X)
    y = (np.tile(X, (units, 1)) * gain + offset
         + rng.normal(0.0, SCALES["y"], (units, X.size)))  # fmt: skip
    z = np.round((np.tile(X, (units, 1)) + bump) / SCALES["z"]) * SCALES["z"]
    data = selection.Data({"y": y, "z": z}, np.repeat(np.arange(3), units // 3),
                          np.arange(units))  # fmt: skip
    noise = {"y": rng.normal(0.0, 1.0, (units, 80))}
    settings = selection.Settings(folds=5, bootstrap=50, seed=SEED, null_draws=100, max_terms=2)
    report = selection.analyse(two_blocks(noise), data, scales=SCALES, settings=settings,
                               source="toy")  # fmt: skip
    named = {t["term"]: t for t in report["discovery"]["named"]}
    flagged = {t["observable"] for t in report["unexplained"]["tests"] if t["flag"]}
    assert set(named) == {"offset"} and named["offset"]["found_on"] == ["y"]
    assert flagged == {"z"}
    assert "Left unexplained: the held-out residual of the curve z" in report["cause"]
    assert "found on the curve y alone" in report["cause"]
    assert "found on the curve y alone" in named["offset"]["statement"]
    # y's gain is the block model's, fitted with the offset beside it
    fitted = {e["effect"]: e for e in [*report["effects_found"], *report["tentative"]]}
    # a 95 % interval misses one draw in twenty: each truth within three half-widths
    for entry, name, truth in ((named["offset"], "offset_y", offset),
                               (fitted["y"], "gain_y", gain)):  # fmt: skip
        low, high = entry["ci95"][name]
        assert abs(entry["parameters"][name] - truth) < 1.5 * (high - low), (name, truth, entry)
