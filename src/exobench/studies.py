"""The three studies the workflow implements: how every output cites them.

Each field is what the study's own text states (``None`` where it states nothing); running text
uses the short ``key``, a summary or README gives the full :func:`reference` once.
"""

from __future__ import annotations

from dataclasses import dataclass


@dataclass(frozen=True)
class Study:
    """One study: short key for running text, title, and authors, venue and year as stated."""

    key: str
    title: str
    authors: str | None
    venue: str | None
    year: str | None
    group: str
    missing: str = ""


PHANTOM = Study(
    key="W.S.B. et al.",
    title="Soft tissue can absorb surprising amounts of energy during knee exoskeleton use",
    authors="W.S.B., A.Y., M.-L.T. and D.P.F. (initials as the authors' contributions give them)",
    venue=None,
    year=None,
    group="phantom",
    missing="the text states no venue or year",
)
STS = Study(
    key="“Kinematic and force analysis”",
    title=(
        "Kinematic and force analysis of the pelvis-foot section of an exoskeleton for the "
        "rehabilitation of individuals with musculoskeletal disorders"
    ),
    authors=None,
    venue=None,
    year=None,
    group="sts",
    missing="the text states no authors, venue or year; it carries a Ukrainian abstract",
)
EMULATOR = Study(
    key="Heer",
    title=(
        "Design and control of a lower-limb exoskeleton emulator for accelerated development "
        "of gait exoskeletons"
    ),
    authors="Kyle B. Heer (thesis advisor: Ozkan Celik)",
    venue="MSc thesis (Mechanical Engineering), Colorado School of Mines, Golden, Colorado",
    year=None,
    group="emulator",
    missing="the text states no year",
)
STUDIES = {study.group: study for study in (PHANTOM, STS, EMULATOR)}


def reference(study: Study) -> str:
    """The full reference in one line: authors, title, venue, year, and what the text omits."""
    parts = [study.authors, f"“{study.title}”", study.venue, study.year]
    text = ". ".join(part for part in parts if part)
    return f"{text} ({study.missing})." if study.missing else f"{text}."


def cited(study: Study) -> str:
    """The key with the title, for a first mention: 'W.S.B. et al., “Soft tissue …”'."""
    return f"{study.key}, “{study.title}”"
