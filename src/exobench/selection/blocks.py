"""Term searches per block of observables that no effect or term joins.

A group's observables can fall apart into blocks: no registry effect and no library term shows
in two of them (the emulator's desired-torque impulse, which only the controller's rules move,
beside the brace's torque, encoder and energy, which only the hardware moves). A misfit in one
block then says nothing of the other, yet in the joint search it does: the block whose residual
is largest in its own units (a controller's output, exact to its resolution) takes every step of
the search and every share of the error. Where the joint search leaves structure, the term search
runs again on each block that misfits, alone; a term it keeps is named when its block's own
verdict flags nothing and it removes at least the share of the block's error a term offered
beside structure must, and what the other blocks leave stays unexplained.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import replace

from exobench.selection.beside import restricted
from exobench.selection.discovery import discover
from exobench.selection.model import Data, Problem, Settings, parameters
from exobench.selection.search import held_out
from exobench.selection.structure import verdict_from_tests


def blocks(problem: Problem) -> list[tuple[str, ...]]:
    """The measured observables in blocks no entry joins (connected components of the graph
    whose edges join the observables an entry shows in, with those of the entries it
    requires), in measured order."""
    measured = list(problem.measured)
    owner = {o: o for o in measured}

    def root(o: str) -> str:
        """The observable that stands for ``o``'s block so far."""
        while owner[o] != o:
            o = owner[o]
        return o

    entries = problem.entries
    for entry in entries.values():
        observables = {*entry.observables, *(o for r in entry.requires
                                             for o in entries[r].observables)}  # fmt: skip
        shown = sorted({root(o) for o in observables if o in owner}, key=measured.index)
        for other in shown[1:]:
            owner[other] = shown[0]
    groups: dict[str, list[str]] = {}
    for o in measured:
        groups.setdefault(root(o), []).append(o)
    return [tuple(g) for g in groups.values()]


def block_problem(problem: Problem, observables: Sequence[str]) -> Problem:
    """The problem on one block: its observables measured (:func:`beside.restricted`), and only
    the registry effects and terms that show in them."""
    part = restricted(problem, observables)
    shows = set(observables)
    registry = {n: e for n, e in problem.registry.items() if shows & set(e.observables)}
    terms = {n: e for n, e in problem.terms.items() if shows & set(e.observables)}
    return replace(part, registry=registry, terms=terms,
                   located=tuple(n for n in problem.located if n in registry))  # fmt: skip


def block_searches(problem: Problem, data: Data, scales, settings: Settings, model: Mapping,
                   verdict: Mapping) -> list[dict]:  # fmt: skip
    """Where the observables fall into two or more blocks (:func:`blocks`): per block a test of
    ``verdict`` flags, the term search (:func:`discovery.discover`) on that block alone, rooted
    at the settled ``model``'s effects that show in it (refitted there) and at none; each with
    the block's problem and observables."""
    groups = blocks(problem)
    if len(groups) < 2:
        return []
    flagged = {t["observable"] for t in verdict["tests"] if t["flag"]}
    out = []
    for group in groups:
        part = block_problem(problem, group)
        if not (flagged & set(group)) or not part.terms:
            continue
        effects = tuple(e for e in model["effects"] if e in part.registry)
        values = {p.name: model["values"][p.name] for p in parameters(part, effects)}
        own, none = held_out(part, data, [effects, ()], scales, settings)
        own = {**own, "values": values}
        root = {"effects": effects, "values": values, "chosen": own}
        search = discover(part, data, scales, settings, root, none, own)
        out.append({"problem": part, "observables": group, "search": search})
    return out


def named_blocks(found: Sequence[Mapping], share: float) -> list[Mapping]:
    """The block searches whose terms are named: their block's verdict flags nothing and each
    term removes at least ``share`` of the block's held-out error (the bar a term offered while
    structure remains meets: the other blocks still misfit)."""
    return [b for b in found if b["search"]["final"] is not None and b["search"]["named"]
            and all(b["search"]["gains"][t]["gain_pct"] >= 100.0 * share
                    for t in b["search"]["kept"])]  # fmt: skip


def remaining(verdict: Mapping, explained: Sequence[Mapping]) -> dict:
    """What is left unexplained once the blocks whose terms are named (``explained``,
    :func:`named_blocks`) are explained: the ``verdict``'s tests of every other observable beside
    those blocks' own tests with their terms (none flagged; their levels corrected for the
    block's own number of tests)."""
    shown = {o for b in explained for o in b["observables"]}
    rows = [dict(t) for t in verdict["tests"] if t["observable"] not in shown]
    rows += [dict(t) for b in explained for t in b["search"]["verdict"]["tests"]]
    return verdict_from_tests(rows)
