"""Rule phantom_verdict: the verdict in words (summary.md) from the recordings' discrepancy
report and, when the run compares with seed 000, its medians' report and the twin's calibration
to them, where they fit the same parameters."""

import json
from pathlib import Path

import pandas as pd

from exobench import runner, tables
from exobench.phantom.model import checks
from exobench.selection import summary


def stage(smk, provenance):
    recordings = json.loads(Path(smk.input.recordings).read_text())
    sections, fits = [("Recordings", recordings)], {"recordings": summary.as_fit(recordings)}
    if "reported" in smk.input.keys():
        reported = json.loads(Path(smk.input.reported).read_text())
        sections.append(("Medians seed 000 reports", reported))
        fits["reported medians"] = summary.as_fit(reported)
        fitted = json.loads(Path(smk.input.fit).read_text())["parameters"]
        effects = [name for name, entry in smk.params.effects.items()
                   if entry["enabled"] and any(key in fitted for key in entry)]  # fmt: skip
        units = {name: tables.unit_for(name) for name in fitted}
        fits["twin calibration"] = summary.point_fit(fitted, units, effects)
    text = summary.markdown(sections, fits, heading="Phantom: what the rigid theory gets wrong")
    text += "\n".join(["", *checks.markdown(pd.read_csv(smk.input.checks, comment="#"))])
    tables.write_document(smk.output[0], text, provenance)


runner.run(snakemake, stage)
