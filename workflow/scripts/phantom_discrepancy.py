"""Rule phantom_discrepancy: what the rigid theory gets wrong, its cause and the gain."""

from pathlib import Path

import pandas as pd

from exobench import atomic, runner, tables
from exobench.phantom import c3d, discrepancy, discrepancy_reported
from exobench.phantom.rig import ANALOG_RATE_HZ, Rig


def stage(smk, provenance):
    rig = Rig.from_config(smk.params.rig)
    manifest = c3d.read_manifest(Path(smk.input.manifest)).set_index("trial")
    parts = [
        (
            trial,
            manifest.loc[trial, "spring_stiffness_N_per_m"],
            tables.read_table(kinetics).data,
            tables.read_table(strides).data,
        )
        for trial, kinetics, strides in zip(
            smk.params.trials, smk.input.kinetics, smk.input.strides, strict=True
        )
    ]
    settings = {**smk.params.discrepancy, "seed": int(smk.params.seed)}
    obs = discrepancy.observations(parts, settings, 1.0 / ANALOG_RATE_HZ)
    report = discrepancy.analyse(obs, rig, settings, source=str(Path(smk.input.manifest).parent))
    runner.LOG.info("recordings: %s", report["cause"])
    atomic.write_json(smk.output.recordings, {**report, "provenance": provenance})
    tables.write_table(
        smk.output.predictions, discrepancy.prediction_table(obs, report, rig), provenance
    )
    reported = discrepancy_reported.analyse(
        pd.read_csv(smk.input.reported), rig, source=str(smk.input.reported)
    )
    runner.LOG.info("reported medians: %s", reported["cause"])
    atomic.write_json(smk.output.reported, {**reported, "provenance": provenance})


runner.run(snakemake, stage)
