"""Rule emulator_discrepancy: ideal spring model vs measured energy, cause, gain; condition 12."""

import json

import pandas as pd

from exobench import atomic, runner, tables
from exobench import provenance as locations
from exobench.emulator import acquire, discrepancy


def stage(smk, provenance):
    settings = smk.params
    manifest = acquire.read_manifest(smk.input.manifest).set_index("trial")
    qc = json.loads(open(smk.input.qc, encoding="utf-8").read())["trials"]
    steps = tables.read_table(smk.input.steps).data
    obs = []
    for trial, path in zip(smk.params.trials, smk.input.samples, strict=True):
        stiffness = float(manifest.loc[trial, "stiffness_Nm_per_rad"])
        if stiffness <= 0.0:
            continue
        samples = tables.read_table(path).data
        energy_J = steps.loc[steps["trial"] == trial, "energy_J"].to_numpy()
        obs.append(
            discrepancy.observation(
                trial,
                stiffness,
                samples,
                qc[trial],
                energy_J,
                settings["equilibrium_deg"],
                settings["direction_blend_deg_per_s"],
            )
        )
    report = discrepancy.analyse(
        obs, int(settings["folds"]), int(settings["bootstrap"]), int(settings["seed"])
    )
    report["reported_condition_12"] = discrepancy.reported_condition_12(
        pd.read_csv(smk.input.reported),
        settings["equilibrium_deg"],
        smk.params.transmission,
    )
    report["source"] = locations.relative_name(smk.input.manifest, smk.config)
    runner.LOG.info("emulator discrepancy: %s", report["cause"])
    atomic.write_json(smk.output[0], {**report, "provenance": provenance})


runner.run(snakemake, stage)
