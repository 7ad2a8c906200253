"""Rule phantom_discrepancy_reported: the discrepancy engine on the medians seed 000 reports."""

from pathlib import Path

import pandas as pd

from exobench import atomic, runner
from exobench.phantom.model import discrepancy_reported
from exobench.phantom.rig import Rig


def stage(smk, provenance):
    settings = {"engine": smk.params.engine, "seed": smk.params.seed}
    report = discrepancy_reported.analyse(
        pd.read_csv(smk.input.reported), Rig.from_config(smk.params.rig), settings,
        source=Path(smk.input.reported).name,
    )  # fmt: skip
    runner.LOG.info("reported medians: %s", report["cause"])
    atomic.write_json(smk.output[0], {**report, "provenance": provenance})


runner.run(snakemake, stage)
