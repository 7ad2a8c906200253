"""A summary's frame, the same for every group's ``summary.md``: the title naming the source,
the source line, the studies cited, free notes, the references, and the sections joined into one
Markdown text. Light (no scientific imports)."""

from __future__ import annotations

from collections.abc import Mapping, Sequence

from exobench import sources, studies


def document(sections: Sequence[Sequence[str]]) -> str:
    """The sections, one after another, as one Markdown text."""
    lines = [line for section in sections for line in section]
    while lines and lines[-1] == "":
        lines.pop()
    return "\n".join(lines) + "\n"


def heading(title: str, spec: Mapping) -> list[str]:
    """The document's title, naming the source: '# Phantom, on simulated recordings of the
    phantom's digital twin: what the rigid theory gets wrong'."""
    group, _, question = title.partition(": ")
    return [f"# {group}, on {sources.kind(spec)}: {question}", ""]


def source(spec: Mapping) -> list[str]:
    """Where the data come from: the first line (:func:`exobench.sources.source_line`)."""
    return [sources.source_line(spec), ""]


def cited(group_studies: Sequence[studies.Study]) -> list[str]:
    """The studies the summary compares with, by key and title (references at the end)."""
    named = "; ".join(studies.cited(s) for s in group_studies)
    return [f"**Study:** {named} (full reference at the end).", ""]


def notes(paragraphs: Sequence[str], title: str = "Notes") -> list[str]:
    """Free paragraphs under a heading (none: no section)."""
    if not paragraphs:
        return []
    return [f"## {title}", "", *(line for p in paragraphs for line in (p, ""))]


def references(group_studies: Sequence[studies.Study]) -> list[str]:
    """The full reference of every study cited."""
    return ["## References", "", *(f"- {s.key}: {studies.reference(s)}" for s in group_studies),
            ""]  # fmt: skip
