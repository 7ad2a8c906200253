"""The families a rig's assumption can fail by, declared once for every group.

A family is how an assumption fails whatever it is about: a law of an element (elastic, stiffening,
viscous, Coulomb friction, a friction bias, drifting over the trial, play), a fault of a channel
(gain, offset, drift, delay, crosstalk, a step, a nonlinearity its datasheet bounds, an artefact
locked to the gait), a value, direction or timing off the rig's (value, offset, tilt), a rule
acting at another event than its table's (event) or where its signal crosses a level other than
its table's (threshold), or a constant that changes between trials. Each family has the noun
that names a relaxation after its row ("interface" + "damping") and what its parameter measures.
A group's term transforms are registries keyed by family (:func:`transform`): a family the
registry does not know raises, never a silent zero.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass
from typing import TypeVar


@dataclass(frozen=True)
class Family:
    """One way any assumption can fail: its name, the noun that names a relaxation after its
    row, and what the relaxation's parameter measures."""

    name: str
    noun: str
    meaning: str


FAMILIES: dict[str, Family] = {
    f.name: f
    for f in (
        Family("elastic", "compliance", "stiffness"),
        Family("stiffening", "stiffening", "stiffening coefficient"),
        Family("viscous", "damping", "damping"),
        Family("coulomb", "friction", "friction moment"),
        Family("bias", "friction bias", "torque lost while it pulls"),
        Family("drifting", "stiffness drift over the trial",
               "relative change of the stiffness per second"),
        Family("value", "off the rig's value", "real over rated"),
        Family("gain", "gain error", "recorded over true"),
        Family("offset", "offset", "offset"),
        Family("drift", "drift", "drift rate"),
        Family("delay", "lag", "lag"),
        Family("crosstalk", "crosstalk", "share of the other channel"),
        Family("play", "play", "play"),
        Family("tilt", "tilt", "tilt anterior of vertical"),
        Family("step", "step", "size of the step"),
        Family("harmonic", "artefact", "amplitude"),
        Family("nonlinearity", "nonlinearity", "relative error per unit of the reading"),
        Family("between", "change between trials", "spread between trials"),
        Family("threshold", "at a threshold", "level its signal must cross"),
        Family("event", "at another event",
               "share of the way to the other event, or of the steps that act at it"),
    )
}  # fmt: skip


class UnknownFamily(KeyError):
    """A family no registry declares (raised, never answered with a neutral term)."""


def family(name: str) -> Family:
    """The family called ``name``; an undeclared one raises :class:`UnknownFamily`."""
    try:
        return FAMILIES[name]
    except KeyError:
        raise UnknownFamily(
            f"unknown family {name!r}: declare it in exobench.selection.families.FAMILIES "
            f"(known: {', '.join(sorted(FAMILIES))})"
        ) from None


T = TypeVar("T")


def transform(registry: Mapping[str, T], name: str, where: str) -> T:
    """The entry of a group's family registry (a term transform) for family ``name`` of the
    assumption at ``where``; a family it has no transform for raises :class:`UnknownFamily`."""
    family(name)
    if name not in registry:
        raise UnknownFamily(
            f"no term transform for family {name!r} of {where} (it has: "
            f"{', '.join(sorted(registry))})"
        )
    return registry[name]
