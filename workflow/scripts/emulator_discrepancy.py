"""Rule emulator_discrepancy: ideal spring model vs the recordings on the shared engine;
condition 12."""

import json

import pandas as pd

from exobench import atomic, emulator, runner, tables
from exobench.emulator import acquire, discrepancy


def stage(smk, provenance):
    settings = emulator.analysis_settings(smk.config)
    manifest = acquire.read_manifest(smk.input.manifest).set_index("trial")
    qc = json.loads(open(smk.input.qc, encoding="utf-8").read())["trials"]
    parts = [
        (
            trial,
            float(manifest.loc[trial, "stiffness_Nm_per_rad"]),
            tables.read_table(path).data,
            qc[trial],
        )
        for trial, path in zip(smk.params.trials, smk.input.samples, strict=True)
    ]
    engine = smk.config["discrepancy"]
    data, scales = discrepancy.observations(
        parts,
        settings["equilibrium_deg"],
        settings["direction_blend_deg_per_s"],
        smk.config["emulator"]["transmission"],
        engine["folds"],
    )
    report = discrepancy.analyse(
        data, scales, engine, settings["seed"], source=str(smk.input.manifest)
    )
    report["reported_condition_12"] = discrepancy.reported_condition_12(
        pd.read_csv(smk.input.reported),
        settings["equilibrium_deg"],
        smk.config["emulator"]["transmission"],
    )
    runner.LOG.info("emulator discrepancy: %s", report["cause"])
    atomic.write_json(smk.output[0], {**report, "provenance": provenance})


runner.run(snakemake, stage)
