"""Rule phantom_discrepancy_reported: the discrepancy engine on the medians W.S.B. et al. report,
each number held out in turn."""

from pathlib import Path

import pandas as pd

from exobench import atomic
from exobench.phantom import reference
from exobench.phantom.model import discrepancy_reported
from exobench.phantom.rig import Rig
from exobench.plumbing import runner


def stage(smk, provenance):
    settings = {"engine": smk.params.engine, "seed": smk.params.seed}
    engagement = discrepancy_reported.engagement_deg(
        pd.read_csv(smk.input.cycle), smk.params.clutch_on_pct
    )
    report = discrepancy_reported.analyse(
        reference.read_reported(smk.input.reported), Rig.from_config(smk.params.rig),
        settings, source=Path(smk.input.reported).name, engagement_deg=engagement,
    )  # fmt: skip
    runner.LOG.info("reported medians: %s", report["cause"])
    atomic.write_json(smk.output[0], {**report, "provenance": provenance})


runner.run(snakemake, stage)
