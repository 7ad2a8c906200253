"""Rule phantom_curves: mean ± SD curves over the gait cycle per spring (included strides)."""

import pandas as pd

from exobench import tables
from exobench.phantom.chain import kinetics
from exobench.phantom.study import curves
from exobench.plumbing import runner


def stage(smk, provenance):
    metrics = tables.read_table(smk.input.metrics).data
    parts = []
    for trial, files in zip(smk.params.trials, kinetics.trial_files(smk.input), strict=True):
        rows = metrics[(metrics["trial"] == trial) & metrics["included"]]
        spring = float(metrics.loc[metrics["trial"] == trial, "spring_stiffness_N_per_m"].iloc[0])
        table = kinetics.read(files)
        parts.append(curves.mean_curves(table, rows["stride"], spring, smk.params.points))
    table = pd.concat(parts).sort_values(["spring_stiffness_N_per_m", "gait_cycle_pct"])
    tables.write_table(smk.output[0], table.reset_index(drop=True), provenance)


runner.run(snakemake, stage)
