"""Checks every group's term library and assumption table share."""

from __future__ import annotations

import numpy as np

from conftest import REPO
from exobench import selection


def away_from_neutral(parameter: selection.Parameter) -> float:
    """A value a recording sees: the top of the parameter's visible sizes (a shape, such as an
    artefact's phase: its start)."""
    return parameter.initial() if parameter.shape else float(parameter.detectable[1])


def assert_acts_where_its_row_says(problem: selection.Problem, data: selection.Data, name: str):
    """A term, on top of the effects it needs (at their start values), changes some of the
    observables its row names and no other, and changes nothing at its neutral value."""
    term = problem.terms[name]
    needed = tuple(term.requires)
    start = {p.name: p.initial() for e in needed for p in problem.entries[e].parameters}
    values = {**start, **{p.name: away_from_neutral(p) for p in term.parameters}}
    base = selection.predict(problem, data, needed, start)
    moved = selection.predict(problem, data, (*needed, name), values)
    changed = {obs for obs in base if not np.allclose(moved[obs], base[obs], rtol=0, atol=1e-12)}
    assert changed and changed <= set(term.observables), changed
    neutral = {**values, **{p.name: p.neutral for p in term.parameters if not p.shape}}
    back = selection.predict(problem, data, (*needed, name), neutral)
    for obs in base:
        np.testing.assert_allclose(back[obs], base[obs], rtol=1e-9, atol=1e-9)


def assert_docs_hold(doc: str, markdown: str, module: str) -> None:
    """docs/<doc> is the table ``module`` generates (``markdown``), with the command that
    writes it when not."""
    written = (REPO / "docs" / doc).read_text(encoding="utf-8")
    assert written == markdown, (
        f"run: python -c 'from {module.rpartition('.')[0]} import {module.rpartition('.')[2]}; "
        f'open("docs/{doc}", "w").write({module.rpartition(".")[2]}.markdown())\''
    )
