"""Rule phantom_verdict: summary.md, the verdict in words, and residual_tests.md beside it, from
the recordings' discrepancy report and, when the run compares with W.S.B. et al., the report on
their medians and the twin's calibration to them."""

import json
from pathlib import Path

import pandas as pd

from exobench import document, studies, tables
from exobench.phantom.chain.metrics import min_excursion_deg
from exobench.phantom.model import assumptions, checks
from exobench.phantom.report import reproduced, verdict_context
from exobench.plumbing import runner
from exobench.selection import checks as direct_checks
from exobench.selection import summary, verdict


def stage(smk, provenance):
    recordings = json.loads(Path(smk.input.recordings).read_text())
    moments = tables.read_table(smk.input.predictions).data
    fitted = {}
    if "fit" in smk.input.keys():
        fitted = json.loads(Path(smk.input.fit).read_text())["parameters"]
    # the direct checks, and the parameter stability as the check of the between-trial rows
    direct = direct_checks.with_stability(pd.read_csv(smk.input.checks), recordings)
    head = [
        document.heading("Phantom: what the rigid theory gets wrong", smk.params.source),
        document.source(smk.params.source),
        document.cited([studies.PHANTOM]),
        direct_checks.warning(direct),
        verdict.verdict(recordings, verdict_context.pooled_range(moments)),
    ]
    if smk.params.source["acquisition"] == "synthetic":
        head.append(verdict.set_against_recovered(
            recordings, verdict.twin_settings(smk.params.effects, fitted)
        ))  # fmt: skip
    else:
        head.append(verdict.claims(recordings))
    head.append(verdict.unexplained(
        recordings, implicated=direct_checks.implicated(direct, recordings, assumptions.TABLE)
    ))  # fmt: skip
    paired = (pd.read_csv(smk.input.paired), pd.read_csv(smk.input.wilcoxon), smk.params.alpha)
    validity = (pd.read_csv(smk.input.table), min_excursion_deg(smk.params.slope_validity))
    head.append(reproduced.section(
        pd.read_csv(smk.input.kruskal), pd.read_csv(smk.input.outliers), smk.params.robust_z,
        paired, validity,
        *(pd.read_csv(smk.input[key]) if key in smk.input.keys() else None
          for key in ("comparison", "significance", "method")),
    ))  # fmt: skip
    context = {"moment": verdict_context.per_spring(moments)}
    body = [checks.markdown(direct), verdict.errors(recordings, context)]
    fits = {"recordings": summary.as_fit(recordings)}
    if "reported" in smk.input.keys():
        reported = json.loads(Path(smk.input.reported).read_text())
        calibration = pd.read_csv(smk.input.residuals)
        body.append(verdict.reported_medians(reported, studies.PHANTOM))
        body.append(document.notes(verdict_context.drive_note(reported, fitted, calibration),
                                  "The drive stiffness"))  # fmt: skip
        fits["reported medians"] = summary.as_fit(reported)
        effects = [name for name, entry in smk.params.effects.items()
                   if entry["enabled"] and any(key in fitted for key in entry)]  # fmt: skip
        units = {name: tables.unit_for(name) for name in fitted}
        fits["twin calibration"] = summary.point_fit(fitted, units, effects)
    body.append(verdict.fitted_more_than_once(fits))
    body.append(document.references([studies.PHANTOM]))
    tables.write_document(smk.output.summary, document.document([*head, *body]), provenance)
    reports = [("Recordings", recordings)]
    if "reported" in smk.input.keys():
        reports.append((f"The medians {studies.PHANTOM.key} report", reported))
    text = verdict.residual_tests("Phantom", reports)
    tables.write_document(smk.output.tests, text, provenance)


runner.run(snakemake, stage)
