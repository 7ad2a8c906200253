"""Rule sts_verdict: summary.md, the sit-to-stand verdict in words, and study_comparison.csv,
the study's numbers beside the project's with their roles."""

import json
from pathlib import Path

import pandas as pd

from exobench import tables
from exobench.plumbing import runner
from exobench.sts import study_comparison, summary


def stage(smk, provenance):
    read = {
        name: json.loads(Path(smk.input[name]).read_text())
        for name in ("readings", "postures", "modules", "fe")
    }
    checks = pd.read_csv(smk.input.checks, keep_default_na=False, na_values=[""])
    sections = pd.read_csv(smk.input.sections)
    reported = pd.read_csv(smk.input.reported)
    table = study_comparison.table(reported, smk.params, read["fe"], sections)
    tables.write_csv(smk.output.comparison, table, provenance)
    text = summary.document(
        checks, read["readings"], read["postures"], read["modules"], read["fe"], sections, table
    )
    tables.write_document(smk.output.summary, text, provenance)


runner.run(snakemake, stage)
