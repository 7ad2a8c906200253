"""Rule emulator_figures: energy per step, angle and torque, encoder vs mocap, Table 6.1 check,
each with its caption."""

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
        samples,
        manifest[manifest["trial"].isin(smk.params.trials)],
        json.loads(open(smk.input.qc, encoding="utf-8").read())["trials"],
    )
    figures.publish(smk.output, smk.params.figures, drawn)


runner.run(snakemake, stage)
