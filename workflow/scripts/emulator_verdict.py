"""Rule emulator_verdict: summary.md, the verdict in words, and residual_tests.md beside it, from
the emulator's discrepancy report and the direct checks of its rig's assumptions."""

import json
from pathlib import Path

import pandas as pd

from exobench import document, studies, tables
from exobench.emulator.model import assumptions, checks, discrepancy
from exobench.emulator.study import comparison
from exobench.plumbing import runner
from exobench.selection import checks as direct_checks
from exobench.selection import verdict

# The twin's name for a parameter where the engine's differs.
ALIASES = {"size_deg": "drop_deg"}


def stage(smk, provenance):
    report = json.loads(Path(smk.input.report).read_text())
    direct = pd.read_csv(smk.input.checks)
    heer = pd.read_csv(smk.input.comparison)
    sections = [
        document.heading("Emulator: what the cable model gets wrong", smk.params.source),
        document.source(smk.params.source),
        document.cited([studies.EMULATOR]),
        direct_checks.warning(direct),
        verdict.verdict(
            report, comparison.energy_gap(heer, studies.EMULATOR.key, smk.params.torque_filter_Hz)
        ),
    ]
    if smk.params.source["acquisition"] == "synthetic":
        settings = verdict.twin_settings(smk.params.effects, {})
        sections.append(verdict.set_against_recovered(report, settings, ALIASES))
    else:
        sections.append(verdict.claims(report))
    said = checks.unaccounted_rows(direct, report)
    implicated = direct_checks.implicated(direct, report, assumptions.TABLE, said)
    sections.append(verdict.unexplained(report, direct=checks.unaccounted(direct, report),
                                        implicated=implicated))  # fmt: skip
    sections.append(checks.markdown(direct))
    resolution = {o: report["noise_scales"][f"{o}_{report['observables'][o]}"]
                  for o in discrepancy.problem().exact}  # fmt: skip
    sections.append(verdict.errors(report, resolution=resolution))
    reading = comparison.condition_12_reading(
        heer, comparison.planted_deg(smk.params.effects, heer)
    )
    sections.append(document.notes(
        [*discrepancy.condition_12_note(report["reported_condition_12"]), reading],
        f"Condition 12 of {studies.EMULATOR.key}"))  # fmt: skip
    line = comparison.prediction_line(heer, studies.EMULATOR.key)
    sections.append(document.notes([line], f"{studies.EMULATOR.key}'s numbers"))
    sections.append(document.references([studies.EMULATOR]))
    tables.write_document(smk.output.summary, document.document(sections), provenance)
    text = verdict.residual_tests("Emulator", [("Recordings", report)])
    tables.write_document(smk.output.tests, text, provenance)


runner.run(snakemake, stage)
