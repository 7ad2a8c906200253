"""Rule emulator_checks: the direct checks of the rig's assumptions (no model) on every trial."""

import json

import pandas as pd

from exobench import tables
from exobench.emulator.model import checks
from exobench.emulator.recordings import acquire
from exobench.plumbing import runner


def stage(smk, provenance):
    params = smk.params
    manifest = acquire.read_manifest(smk.input.manifest).set_index("trial")
    qc = json.loads(open(smk.input.qc, encoding="utf-8").read())["trials"]
    parts = [
        {
            "trial": trial,
            "stiffness": float(manifest.loc[trial, "stiffness_Nm_per_rad"]),
            "samples": tables.read_table(path).data,
            "qc": qc[trial],
        }
        for trial, path in zip(params.trials, smk.input.samples, strict=True)
    ]
    settings = {
        "checks": params.checks,
        "sensors": params.sensors,
        "transmission": params.transmission,
        "velocity_cutoff_Hz": params.controller["velocity_cutoff_Hz"],
        "direction_blend_deg_per_s": params.controller["direction_blend_deg_per_s"],
        "torque_filter_Hz": params.controller["torque_filter_Hz"],
        "activity_tolerance_s": params.activity_tolerance_s,
    }
    table = checks.checks(parts, settings)
    for _, row in table[table["decision"] != "holds"].iterrows():
        runner.LOG.info("%s: %s %s (%s)", row["assumption"], row["quantity"], row["decision"],
                        row["detail"] or f"{row['measured']:.3g} {row['unit']}")  # fmt: skip
    tables.write_csv(smk.output[0], pd.DataFrame(table), provenance)


runner.run(snakemake, stage)
