"""Rule emulator_trial: events, energy per step and the encoder cross-check of one trial."""

import json
from pathlib import Path

import numpy as np

from exobench import atomic, emulator, runner, tables
from exobench.emulator import acquire, analysis


def stage(smk, provenance):
    trial = smk.wildcards.trial
    manifest = acquire.read_manifest(smk.input.manifest).set_index("trial")
    stiffness = float(manifest.loc[trial, "stiffness_Nm_per_rad"])
    duration_s = float(smk.config["emulator"]["protocol"]["duration_s"])
    brace = acquire.read_brace(smk.input.brace, duration_s)
    mocap = acquire.read_mocap(smk.input.mocap, duration_s)
    samples, steps, qc = analysis.analyse(
        trial, brace, mocap, stiffness, emulator.analysis_settings(smk.config)
    )
    acquire.check_steps(smk.input.brace, steps)
    truth_path = smk.params.truth
    if truth_path and Path(truth_path).is_file():
        truth = json.loads(Path(truth_path).read_text())
        detected = samples["t_s"].to_numpy()[samples["heel_strike"].to_numpy()]
        qc["gait_event_accuracy"] = analysis.event_accuracy(
            detected, np.asarray(truth["heel_strikes_s"])
        )
    else:
        qc["gait_event_accuracy"] = None
    runner.LOG.info("%s: %s", trial, qc)
    tables.write_table(smk.output.samples, samples, provenance, analysis.SAMPLE_UNITS)
    tables.write_table(smk.output.steps, steps, provenance, analysis.STEP_UNITS)
    atomic.write_json(smk.output.qc, {"trial": trial, **qc, "provenance": provenance})


runner.run(snakemake, stage)
