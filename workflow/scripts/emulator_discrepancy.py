"""Rule emulator_discrepancy: the cable model vs the recordings on the shared engine (weighing
what the direct checks saw as other readings); Heer's condition 12."""

import json

import pandas as pd

from exobench import atomic, tables
from exobench.emulator.model import checks, discrepancy
from exobench.emulator.recordings import acquire
from exobench.plumbing import provenance as locations
from exobench.plumbing import runner


def stage(smk, provenance):
    params = smk.params
    manifest = acquire.read_manifest(smk.input.manifest).set_index("trial")
    qc = json.loads(open(smk.input.qc, encoding="utf-8").read())["trials"]
    parts = [
        (
            trial,
            float(manifest.loc[trial, "stiffness_Nm_per_rad"]),
            tables.read_table(path).data,
            qc[trial],
        )
        for trial, path in zip(params.trials, smk.input.samples, strict=True)
    ]
    data, scales = discrepancy.observations(
        parts,
        params.equilibrium_deg,
        params.direction_blend_deg_per_s,
        params.transmission,
        params.engine["folds"],
        params.torque_filter_Hz,
    )
    report = discrepancy.analyse(
        data,
        scales,
        params.engine,
        int(params.seed),
        source=locations.relative_name(smk.input.manifest, smk.config),
        suspects=checks.suspects(pd.read_csv(smk.input.checks)),
    )
    report["reported_condition_12"] = discrepancy.reported_condition_12(
        pd.read_csv(smk.input.reported), params.equilibrium_deg, params.transmission
    )
    runner.LOG.info("emulator discrepancy: %s", report["cause"])
    atomic.write_json(smk.output.report, {**report, "provenance": provenance})


runner.run(snakemake, stage)
