"""A rig's assumptions as data, the same for every group: one row per assumption, the
relaxations that undo it, and the engine parameter of each relaxation's term.

Every row is something the rig contract (docs/rig.md) states or an analysis takes for granted:
a value (a mass, a length, a rate), a law (a rigid frame, a linear spring, a frictionless hinge,
an interface that behaves the same all trial), a direction or a channel's calibration and
independence. Each row says where the assumption lives (an element, a channel or a constant),
which observables it touches, and the relaxations that undo it, each of a family of
:mod:`exobench.selection.families`. A group keeps its own rows (its ``model.assumptions``) and
generates its term library from them; a row without relaxations is checked directly on the
recordings.

Each relaxation carries the sizes a recording can see (``visible``: the parameter's values from
a small to a large violation; for a relaxation of either sign, its distance from the neutral
value on either side), which the open-world validation draws from, and its law in one line:
an independent generator writes the violation from that line and the physics alone.
"""

from __future__ import annotations

from collections.abc import Iterable, Mapping
from dataclasses import dataclass

from exobench.selection.families import family
from exobench.selection.model import Constant, Effect, Parameter

# "between": a constant that must stay the same from one trial to the next
KINDS = ("law", "value", "direction", "channel", "timing", "between")


@dataclass(frozen=True)
class Relaxation:
    """One way an assumption fails: its family, the parameter that sizes it (name with its
    unit suffix, unit, neutral value where it vanishes), the law it follows in one line, the
    values a recording can see (``signed``: their distance from neutral, either side), the
    registry effect that is this relaxation (None: a library term), the relaxations it only
    exists on top of (term keys), ``checked``: the row's direct check sees it, no model term
    does (the analysis reads it from the markers, so the chain is not wrong, only the rig), and
    for a change between trials, the relaxation whose parameter changes (``varies``, its term
    key: the parameter stability refits that parameter per trial)."""

    family: str
    parameter: str
    unit: str
    law: str
    visible: tuple[float, float]
    neutral: float = 0.0
    signed: bool = False
    registry: str | None = None
    requires: tuple[str, ...] = ()
    checked: bool = False
    name: str = ""
    varies: str = ""

    def __post_init__(self) -> None:
        """An undeclared family raises when the table is built (at import); a change between
        trials names the relaxation whose parameter changes."""
        family(self.family)
        if (self.family == "between") != bool(self.varies):
            raise ValueError(
                f"{self.family} relaxation of {self.parameter}: a change between "
                "trials, and only one, names the relaxation it varies"
            )


@dataclass(frozen=True)
class Assumption:
    """One row: its key, kind, where it lives (element, channel or constant, in the rig's
    words), the assumption as the rig contract states it, the observables it touches, its
    relaxations, the direct check that needs no model (None: only a fit can test it) and the
    rows whose violation that check shows alike (``alike``: it cannot tell them apart; a row's
    key, or one relaxation's term key where only that one reads alike)."""

    key: str
    kind: str
    where: str
    statement: str
    observables: tuple[str, ...]
    relaxations: tuple[Relaxation, ...] = ()
    check: str | None = None
    short: str = ""
    alike: tuple[str, ...] = ()

    def term(self, family_name: str) -> str:
        """The key of the term that relaxes this row by ``family_name``."""
        return f"{self.key}.{family_name}"

    @property
    def label(self) -> str:
        """The row's short name in words."""
        return self.short or (self.key if self.kind == "channel" else self.key.replace("_", " "))

    def description(self, relaxation: Relaxation) -> str:
        """A relaxation's name with where it lives: "interface damping (soft tissue and straps
        between the phantom and the bars)"."""
        name = self.name(relaxation)
        return name if "(" in name else f"{name} ({self.where})"

    def name(self, relaxation: Relaxation) -> str:
        """A relaxation's name in words, one per effect wherever it is printed: its own, else
        the row's short name and the family's noun ("interface damping")."""
        return relaxation.name or f"{self.label} {family(relaxation.family).noun}"


def relaxations(table: Iterable[Assumption]) -> dict[str, tuple[Assumption, Relaxation]]:
    """Every relaxation of a table by its term key (``row.family``)."""
    return {row.term(r.family): (row, r) for row in table for r in row.relaxations}


def registry_terms(table: Iterable[Assumption]) -> dict[str, str]:
    """The registry effect each relaxation is, by term key (registry relaxations only)."""
    return {key: r.registry for key, (_, r) in relaxations(table).items() if r.registry}


def registry_effect(table: Iterable[Assumption], name: str, parameters: tuple[Parameter, ...],
                    transform, **options) -> Effect:  # fmt: skip
    """A registry entry: the table's relaxation that is effect ``name`` (its description, the
    observables its row touches) with the engine's parameters and transformation."""
    row, relaxation = next((row, r) for row in table for r in row.relaxations
                           if r.registry == name)  # fmt: skip
    return Effect(name, row.description(relaxation), parameters, row.observables, transform,
                  **options)  # fmt: skip


def term_library(table: Iterable[Assumption], transform_of, parameters_of=None,
                 early=None) -> dict[str, Effect]:  # fmt: skip
    """Every relaxation of a table that no registry effect and no direct check covers, as a
    term keyed row.family: its parameters (``parameters_of(row, r)``, else
    :func:`term_parameter`), its transform (``transform_of(row, r)``, which raises for a family
    the row's element lacks) and whether it changes the model's constants (``early(row, r)``);
    a term that needs another relaxation requires that effect (by its registry name)."""
    table = tuple(table)
    registry = registry_terms(table)
    out = {}
    for key, (row, r) in relaxations(table).items():
        if r.registry or r.checked:
            continue
        params = parameters_of(row, r) if parameters_of else (term_parameter(row, r),)
        out[key] = Effect(key, row.description(r), params, row.observables, transform_of(row, r),
                          requires=tuple(registry.get(q, q) for q in r.requires),
                          early=bool(early and early(row, r)))  # fmt: skip
    return out


def constants(table: Iterable[Assumption], registry: Mapping[str, Effect]) -> tuple[Constant, ...]:
    """The constants a table says must hold between trials: each ``between`` relaxation's
    varied relaxation, by the registry effect it is (its parameter that sizes it) or the
    library term it makes (``row.parameter``); the smallest departure that counts a quarter of
    the smallest visible spread; needed only where the model holds it when the change requires
    the relaxation it varies (a compliance must exist to change)."""
    every = relaxations(table)
    effects = registry_terms(table)
    out = []
    for row, r in every.values():
        if r.family != "between":
            continue
        varied_row, varied = every[r.varies]
        effect = effects.get(r.varies, r.varies)
        parameter = (next(p.name for p in registry[effect].parameters if not p.shape)
                     if effect in registry else f"{varied_row.key}.{varied.parameter}")  # fmt: skip
        out.append(Constant(row.key, varied_row.name(varied), effect, parameter,
                            r.visible[0] / 4.0, r.varies in r.requires, row.alike))  # fmt: skip
    return tuple(out)


def between_spreads(table: Iterable[Assumption]) -> dict[str, tuple[float, float]]:
    """The visible spread of each constant that must hold between trials, by its row."""
    return {row.key: r.visible for row, r in relaxations(table).values() if r.family == "between"}


def term_parameter(row: Assumption, r: Relaxation) -> Parameter:
    """A term's parameter from its relaxation: named row.parameter, its fit bounds a few times
    beyond the visible sizes (either side of neutral for a signed one, a factor above a tenth, a
    share of the steps from all of them, up to half as many again), negligible below a quarter of
    the smallest visible size."""
    low, high = r.visible
    name, meaning = f"{row.key}.{r.parameter}", family(r.family).meaning
    if r.signed:  # a factor stays positive
        floor = 0.1 * r.neutral if r.neutral else -4.0 * high
        return Parameter(name, r.unit, max(r.neutral - 4.0 * high, floor), r.neutral + 4.0 * high,
                         meaning,
                         log=False, start=r.neutral, neutral=r.neutral,
                         detectable=(r.neutral + low, r.neutral + high),
                         negligible=r.neutral + low / 4.0)  # fmt: skip
    if r.family == "event":  # a share of the steps acting at the other event: up to all
        return Parameter(name, r.unit, low / 100.0, 1.5 * high, meaning, start=high,
                         detectable=(low, high), negligible=low / 4.0)  # fmt: skip
    if r.neutral == 1.0:  # a factor that only grows (not far beyond what a recording sees)
        return Parameter(name, r.unit, 0.05, 1.5 * high, meaning, start=1.0, neutral=1.0,
                         detectable=(low, high), negligible=1.0 + (low - 1.0) / 4.0)  # fmt: skip
    return Parameter(name, r.unit, low / 100.0, 10.0 * high, meaning, start=low / 2.0,
                     detectable=(low, high), negligible=low / 4.0)  # fmt: skip


def markdown(table: Iterable[Assumption], title: str, source: str, rows_are: str) -> str:
    """A table in words (a group's docs/assumptions page): ``title``, the module it is
    generated from, and what its rows are (the contract and analysis they come from)."""
    lines = [
        f"# {title}",
        "",
        f"Generated from `{source}` (a test keeps this file equal to "
        f"it). One row per assumption of {rows_are}; each relaxation is a "
        "term the discrepancy engine can add (its key is `row.family`); a registry relaxation "
        "is one of the study's own effects, searched first. Visible sizes are the values a "
        "recording can see; ± marks a relaxation of either sign, sized by its distance from "
        "the neutral value. Rows "
        "without relaxations are checked directly on the recordings.",
        "",
    ]
    for row in table:
        touches = ", ".join(row.observables) or "—"
        lines += [f"## `{row.key}` — {row.label}: {row.where} ({row.kind})", "",
                  f"Assumed: {row.statement}.", "", f"Observables: {touches}."]  # fmt: skip
        if row.check:
            lines.append(f"Direct check: `{row.check}`.")
        if row.relaxations:
            lines += ["", "| term | name | law | parameter | neutral | visible sizes | registry |",
                      "|---|---|---|---|---|---|---|"]  # fmt: skip
            for r in row.relaxations:
                sign = "±" if r.signed else ""
                low, high = r.visible
                law = r.law.replace("|", "\\|")  # a cell's bar
                needs = f" (needs {', '.join(f'`{q}`' for q in r.requires)})" if r.requires else ""
                needs += f" (changes `{r.varies}` between trials)" if r.varies else ""
                lines.append(
                    f"| `{row.term(r.family)}` | {row.name(r)} | {law}{needs} | "
                    f"`{r.parameter}` ({r.unit}) | {r.neutral:g} | {sign}{low:g} to "
                    f"{sign}{high:g} | {r.registry or '—'} |"
                )
        lines.append("")
    return "\n".join(lines)
