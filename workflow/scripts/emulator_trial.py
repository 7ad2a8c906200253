"""Rule emulator_trial: events, energy per step and the encoder cross-check of every trial."""

from exobench.plumbing import jobserver

jobserver.delegate()

import json
from pathlib import Path

import numpy as np

from exobench import atomic, emulator, tables
from exobench.emulator.chain import analysis
from exobench.emulator.recordings import acquire
from exobench.plumbing import provenance, runner


def stage(smk, record):
    manifest = acquire.read_manifest(smk.input.manifest).set_index("trial")
    settings = emulator.analysis_settings(
        {"emulator": {"analysis": smk.params.analysis, "controller": smk.params.controller},
         "seed": smk.params.seed}
    )  # fmt: skip
    duration_s = float(smk.params.duration_s)
    truths = {Path(path).stem: path for path in smk.input.truth}
    out = smk.output
    for trial, brace_path, mocap_path, samples_path, steps_path, qc_path in zip(
        smk.params.trials,
        smk.input.brace,
        smk.input.mocap,
        out.samples,
        out.steps,
        out.qc,
        strict=True,
    ):
        stiffness = float(manifest.loc[trial, "stiffness_Nm_per_rad"])
        brace = acquire.read_brace(brace_path, duration_s, smk.params.columns)
        mocap = acquire.read_mocap(mocap_path, duration_s, smk.params.columns)
        samples, steps, qc = analysis.analyse(trial, brace, mocap, stiffness, settings)
        acquire.check_steps(brace_path, steps)
        used = [smk.input.manifest, brace_path, mocap_path]
        qc["gait_event_accuracy"] = None
        if trial in truths:
            truth = json.loads(Path(truths[trial]).read_text())
            detected = samples["t_s"].to_numpy()[samples["heel_strike"].to_numpy()]
            qc["gait_event_accuracy"] = analysis.event_accuracy(
                detected, np.asarray(truth["heel_strikes_s"]), settings["match_window_s"]
            )
            used.append(truths[trial])
        runner.LOG.info("%s: %s", trial, qc)
        trial_record = provenance.restrict(record, used, smk.config)
        tables.write_table(samples_path, samples, trial_record, analysis.SAMPLE_UNITS)
        tables.write_table(steps_path, steps, trial_record, analysis.STEP_UNITS)
        atomic.write_json(qc_path, {"trial": trial, **qc, "provenance": trial_record})


runner.run(snakemake, stage)
