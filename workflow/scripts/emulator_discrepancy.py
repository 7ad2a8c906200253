"""Rule emulator_discrepancy: ideal spring model vs measured energy, cause, gain; condition 12."""

import json

import numpy as np
import pandas as pd

from exobench import atomic, emulator, runner, tables
from exobench.emulator import acquire, discrepancy


def stage(smk, provenance):
    settings = emulator.analysis_settings(smk.config)
    manifest = acquire.read_manifest(smk.input.manifest).set_index("trial")
    qc = json.loads(open(smk.input.qc, encoding="utf-8").read())["trials"]
    steps = tables.read_table(smk.input.steps).data
    trials = []
    for trial, path in zip(smk.params.trials, smk.input.samples, strict=True):
        stiffness = float(manifest.loc[trial, "stiffness_Nm_per_rad"])
        if stiffness <= 0.0:
            continue
        samples = tables.read_table(path).data
        trials.append(
            {
                "trial": trial,
                "stiffness": stiffness,
                "time_s": samples["t_s"].to_numpy(),
                "heel_strikes": np.flatnonzero(samples["heel_strike"].to_numpy()),
                "anatomical_deg": samples["anatomical_angle_deg"].to_numpy(),
                "encoder_deg": samples["brace_angle_deg"].to_numpy(),
                "encoder_error_deg": samples["encoder_error_deg"].to_numpy(),
                "compliance_deg_per_Nm": qc[trial]["cuff_compliance_deg_per_Nm"],
                "omega_deg_per_s": samples["velocity_deg_per_s"].to_numpy(),
                "engaged": samples["engaged"].to_numpy(),
                "torque_Nm": samples["brace_torque_Nm"].to_numpy(),
                "desired_Nm": samples["desired_torque_Nm"].to_numpy(),
                "energy_J": steps.loc[steps["trial"] == trial, "energy_J"].to_numpy(),
            }
        )
    obs = discrepancy.observations(
        trials, settings["equilibrium_deg"], settings["direction_blend_deg_per_s"]
    )
    report = discrepancy.analyse(obs, settings["folds"], settings["bootstrap"], settings["seed"])
    report["reported_condition_12"] = discrepancy.reported_condition_12(
        pd.read_csv(smk.input.reported),
        settings["equilibrium_deg"],
        smk.config["emulator"]["transmission"],
    )
    report["source"] = str(smk.input.manifest)
    runner.LOG.info("emulator discrepancy: %s", report["cause"])
    atomic.write_json(smk.output[0], {**report, "provenance": provenance})


runner.run(snakemake, stage)
