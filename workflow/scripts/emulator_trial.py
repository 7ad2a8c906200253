"""Rule emulator_trial: events, energy per step and the encoder cross-check of one trial."""

import json
from pathlib import Path

import numpy as np

from exobench import atomic, emulator, tables
from exobench.emulator.chain import analysis
from exobench.emulator.recordings import acquire
from exobench.errors import InputError
from exobench.plumbing import runner


def stage(smk, record):
    trial = smk.wildcards.trial
    manifest = acquire.read_manifest(smk.input.manifest).set_index("trial")
    if trial not in manifest.index:
        raise InputError(smk.input.manifest, "trial", f"a row for trial '{trial}'")
    settings = emulator.analysis_settings(
        {"emulator": {"analysis": smk.params.analysis, "controller": smk.params.controller,
                      "transmission": smk.params.transmission}, "seed": smk.params.seed}
    )  # fmt: skip
    duration_s = float(smk.params.duration_s)
    stiffness = float(manifest.loc[trial, "stiffness_Nm_per_rad"])
    brace, mocap = acquire.read_trial(
        smk.input.brace,
        smk.input.mocap,
        duration_s,
        settings,
        smk.params.columns,
        smk.params.mat_channels,
    )
    samples, steps, qc = analysis.analyse(trial, brace, mocap, stiffness, settings)
    acquire.check_steps(smk.input.brace, steps)
    qc["gait_event_accuracy"] = None
    if smk.input.truth:
        truth = json.loads(Path(smk.input.truth[0]).read_text())
        detected = samples["t_s"].to_numpy()[samples["heel_strike"].to_numpy()]
        qc["gait_event_accuracy"] = analysis.event_accuracy(
            detected, np.asarray(truth["heel_strikes_s"]), settings["match_window_s"]
        )
    runner.LOG.info("%s: %s", trial, qc)
    out = smk.output
    tables.write_table(out.samples, samples, record, analysis.SAMPLE_UNITS, single=True)
    tables.write_table(out.steps, steps, record, analysis.STEP_UNITS)
    atomic.write_json(out.qc, {"trial": trial, **qc, "provenance": record})


runner.run(snakemake, stage)
