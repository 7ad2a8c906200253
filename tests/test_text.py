"""What a reader reads: the studies cited by key and full reference, the source named first, a
README whose first screen is enough, and no link that leads nowhere."""

from __future__ import annotations

import re

import pytest

from conftest import REPO
from exobench import sources, studies

# What users read, written by hand (generated text is checked on the small run).
READ = [
    REPO / "README.md",
    *sorted((REPO / "docs").glob("*.md")),
    *sorted((REPO / "workflow" / "report").glob("*.rst")),
    REPO / "config" / "config.yaml",
    REPO / "raw" / "reference" / "README.md",
    REPO / "workflow" / "schemas" / "config.schema.yaml",
    *sorted((REPO / "workflow" / "rules").glob("*.smk")),
]
# The studies by their workplace numbers: names of files and settings may keep them, text not.
NUMBERED = re.compile(r"\bseed[ -]?0\d\d\b(?!_)|\bseed's\b|\bthe seed\b|\bseed (?:fig|eq)", re.I)
HISTORY = re.compile(
    r"\bissue \d+|\b20\d\d-\d\d-\d\d\b|\bno longer\b(?! runs)|\bchanged since\b(?! last execution)"
)


def flat(text: str) -> str:
    return " ".join(text.split())


@pytest.mark.parametrize("path", READ, ids=lambda p: p.relative_to(REPO).as_posix())
def test_text_cites_the_studies_by_key_not_by_number(path):
    text = path.read_text()
    if path.suffix in (".smk", ".yaml"):  # names such as compare_seed000 stay
        text = re.sub(r"\w*seed0\d\d\w*", "", text)
    assert not NUMBERED.findall(text), path


def test_every_study_is_cited_in_full_in_the_readme_and_the_report():
    keys = [s.key for s in studies.STUDIES.values()]
    assert len(set(keys)) == len(keys)
    readme = flat((REPO / "README.md").read_text())
    report = flat((REPO / "workflow" / "report" / "workflow.rst").read_text())
    for study in studies.STUDIES.values():
        assert flat(studies.reference(study)) in readme, study.key
        assert flat(studies.reference(study)) in report, study.key
        assert study.title in studies.reference(study)


def test_the_readme_first_screen_holds_what_a_newcomer_needs():
    lines = (REPO / "README.md").read_text().splitlines()
    first = "\n".join(lines[:60])
    for needed in ("make run", "make test", "Time", "Disk", "summary.md", "docs/rig.md",
                   "docs/assumptions.md", "docs/engine.md", "--report"):  # fmt: skip
        assert needed in first, needed
    assert re.search(r"\d+(\.\d+)? GB", first) and re.search(r"\d+ min", first)


@pytest.mark.parametrize(
    "path", [REPO / "README.md", *sorted((REPO / "docs").glob("*.md"))], ids=lambda p: p.name
)
def test_docs_hold_no_history_and_no_dead_links(path):
    text = path.read_text()
    assert not HISTORY.findall(text), HISTORY.findall(text)
    for target in re.findall(r"\]\(([^)#\s]+)(?:#[^)]*)?\)", text):
        if "://" not in target:
            assert (path.parent / target).exists(), target


def test_the_source_line_names_the_twin_or_the_manifest():
    spec = {"acquisition": "synthetic", "group": "phantom", "twin_blocks": ["phantom.twin"],
            "manifest": "<raw_dir>/phantom/manifest.csv", "calibration": "calibration/fit.json",
            "engine": "discrepancy.json"}  # fmt: skip
    twin = sources.source_line(spec)
    assert twin.startswith("**Source: simulated recordings.**")
    assert "`phantom.twin`" in twin and "calibration/fit.json" in twin
    assert "not a physical finding about a real rig" in twin
    lab = sources.source_line({**spec, "acquisition": "files"})
    assert lab.startswith("**Source: the lab's recordings**")
    assert "<raw_dir>/phantom/manifest.csv" in lab and "twin" not in lab


def test_every_emulator_figure_the_doc_names_is_one_its_rules_draw():
    """docs/emulator.md names no figure the emulator_figures rule does not make."""
    doc = (REPO / "docs" / "emulator.md").read_text()
    rules = (REPO / "workflow" / "rules" / "emulator.smk").read_text()
    declared = re.search(r"EMULATOR_FIGURE_NAMES = \[(.*?)\]", rules, re.S)
    declared = set(re.findall(r'"(\w+)"', declared.group(1)))
    row = next(line for line in doc.splitlines() if line.startswith("| `emulator_figures`"))
    named = set(re.findall(r"`(\w+)`:", row)) | set(re.findall(r"(\w+)\.png", doc))
    assert "activity_vs_table61" in named
    assert named <= declared, named - declared
