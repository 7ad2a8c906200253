"""Rule emulator_figures: energy per step, angle and torque, encoder vs mocap, Table 6.1 check."""

import json

import pandas as pd

from exobench import runner, tables
from exobench.emulator import acquire, plots


def stage(smk, provenance):
    manifest = acquire.read_manifest(smk.input.manifest)
    conditions = manifest[manifest["trial"].isin(smk.params.trials)]
    samples = {
        trial: tables.read_table(path).data
        for trial, path in zip(smk.params.trials, smk.input.samples, strict=True)
    }
    out = smk.output
    plots.energy_per_step(pd.read_csv(smk.input.summary), out.energy_png, out.energy_pdf)
    plots.angle_torque(samples, conditions, out.curves_png, out.curves_pdf)
    plots.encoder_vs_mocap(samples, conditions, out.encoder_png, out.encoder_pdf)
    qc = json.loads(open(smk.input.qc, encoding="utf-8").read())["trials"]
    plots.activity_crosscheck(qc, conditions, out.activity_png, out.activity_pdf)


runner.run(snakemake, stage)
