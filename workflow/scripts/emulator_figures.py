"""Rule emulator_figures: energy per step (with Heer's values), angle and torque, encoder vs
motion capture (raw and aligned), recorded activity vs Table 6.1, each with its caption."""

import json

import pandas as pd

from exobench import figures, tables
from exobench.emulator.recordings import acquire
from exobench.emulator.report import plots
from exobench.plumbing import runner


def stage(smk, provenance):
    manifest = acquire.read_manifest(smk.input.manifest)
    samples = {
        trial: tables.read_table(path).data
        for trial, path in zip(smk.params.trials, smk.input.samples, strict=True)
    }
    drawn = plots.all_figures(
        pd.read_csv(smk.input.summary),
        tables.read_table(smk.input.steps).data,
        samples,
        manifest[manifest["trial"].isin(smk.params.trials)],
        json.loads(open(smk.input.qc, encoding="utf-8").read())["trials"],
        pd.read_csv(smk.input.reported),
    )
    figures.publish(smk.output, smk.params.figures, drawn)


runner.run(snakemake, stage)
