"""Rule sts_verdict: summary.md, the sit-to-stand verdict in words, from the checks, the
corrected postures, the tuned modules and the finite-element report."""

import json
from pathlib import Path

import pandas as pd

from exobench import tables
from exobench.plumbing import runner
from exobench.sts import summary


def stage(smk, provenance):
    read = {name: json.loads(Path(smk.input[name]).read_text())
            for name in ("postures", "modules", "fe")}  # fmt: skip
    checks = pd.read_csv(smk.input.checks, keep_default_na=False, na_values=[""])
    checks["cause"] = checks["cause"].fillna("")
    text = summary.document(checks, read["postures"], read["modules"], read["fe"])
    tables.write_document(smk.output[0], text, provenance)


runner.run(snakemake, stage)
