"""Rule emulator_summary: energy per step of every trial, Table 6.3 analogue, session QC file."""

import json

import pandas as pd

from exobench import atomic, tables
from exobench.emulator.chain import triangulation
from exobench.emulator.recordings import acquire
from exobench.errors import InputError
from exobench.plumbing import runner


def stage(smk, provenance):
    manifest = acquire.read_manifest(smk.input.manifest).set_index("trial")
    parts = {path: tables.read_table(path) for path in smk.input.steps}
    units = next(iter(parts.values())).units
    for path, part in parts.items():
        if part.units != units:
            raise InputError(
                path, "unit", f"the units of the other trials' steps {units}", part.units
            )
    steps = pd.concat([part.data for part in parts.values()], ignore_index=True)
    tables.write_table(smk.output.steps, steps, provenance, units)
    grouped = steps.groupby("trial", sort=False)["energy_J"]
    summary = pd.DataFrame(
        {
            "trial": smk.params.trials,
            "speed_m_per_s": [manifest.loc[t, "speed_m_per_s"] for t in smk.params.trials],
            "stiffness_Nm_per_rad": [
                manifest.loc[t, "stiffness_Nm_per_rad"] for t in smk.params.trials
            ],
        }
    )
    summary["n_steps"] = summary["trial"].map(grouped.size()).fillna(0).astype(int)
    summary["mean_energy_J"] = summary["trial"].map(grouped.mean())
    summary["sd_energy_J"] = summary["trial"].map(grouped.std(ddof=1))
    # Heer's definition beside it: over the clutch's window (the spring active, Heer §6.3)
    active = steps.groupby("trial", sort=False)["energy_active_J"]
    summary["mean_energy_active_J"] = summary["trial"].map(active.mean())
    summary["sd_energy_active_J"] = summary["trial"].map(active.std(ddof=1))
    tables.write_csv(smk.output.summary, summary, provenance)
    qc = {}
    for path in smk.input.qc:
        record = json.loads(open(path, encoding="utf-8").read())
        record.pop("provenance")
        qc[record.pop("trial")] = record
    session = triangulation.session(
        qc, float(smk.params.fault_threshold_deg), smk.params.calibration
    )
    atomic.write_json(smk.output.qc, {**session, "provenance": provenance})


runner.run(snakemake, stage)
