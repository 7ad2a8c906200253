"""Rule phantom_discrepancy: what the rigid theory gets wrong, its cause and the gain."""

import os

# The rule's threads go to the engine's worker processes; linear algebra stays on one thread in
# each (Snakemake sets these to the rule's threads; two levels would oversubscribe the cores).
for variable in ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ[variable] = "1"

from pathlib import Path

import pandas as pd

from exobench import atomic, tables
from exobench.phantom.chain import kinetics
from exobench.phantom.model import discrepancy
from exobench.phantom.recordings import c3d
from exobench.phantom.rig import Rig
from exobench.plumbing import runner


def stage(smk, provenance):
    rig = Rig.from_config(smk.params.rig)
    manifest = c3d.read_manifest(Path(smk.input.manifest)).set_index("trial")
    parts = [
        (
            trial,
            manifest.loc[trial, "spring_stiffness_N_per_m"],
            kinetics.read(files, discrepancy.KINETICS_COLUMNS),
            tables.read_table(strides).data,
        )
        for trial, files, strides in zip(
            smk.params.trials, kinetics.trial_files(smk.input), smk.input.strides, strict=True
        )
    ]
    engine = {**smk.params.engine, "workers": smk.threads}  # independent fits share the cores
    settings = {**smk.params.discrepancy, "engine": engine, "seed": smk.params.seed}
    data, scales = discrepancy.observations(parts, settings, rig, smk.params.chain)
    report = discrepancy.analyse(data, scales, settings, source="recordings (manifest.csv)")
    runner.LOG.info("recordings: %s", report["cause"])
    atomic.write_json(smk.output.recordings, {**report, "provenance": provenance})
    # every included stride's window, predicted by the model fitted to the engine's sample
    every = {**settings, "max_strides_per_trial": sum(len(part[3]) for part in parts)}
    table = discrepancy.prediction_table(
        discrepancy.observations(parts, every, rig, smk.params.chain)[0], report
    )
    sample = pd.MultiIndex.from_arrays([data.trial.astype(str), data.order])
    table["fitted"] = pd.MultiIndex.from_frame(table[["trial", "stride"]]).isin(sample)
    tables.write_table(smk.output.predictions, table, provenance)
    tables.write_table(smk.output.terms, discrepancy.term_table(data, report), provenance)


runner.run(snakemake, stage)
