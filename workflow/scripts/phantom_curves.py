"""Rule phantom_curves: mean ± SD curves over the gait cycle per spring (included strides)."""

import pandas as pd

from exobench import tables
from exobench.phantom.study import curves
from exobench.plumbing import runner


def stage(smk, provenance):
    metrics = tables.read_table(smk.input.metrics).data
    parts = []
    for trial, path in zip(smk.params.trials, smk.input.kinetics, strict=True):
        rows = metrics[(metrics["trial"] == trial) & metrics["included"]]
        spring = float(metrics.loc[metrics["trial"] == trial, "spring_stiffness_N_per_m"].iloc[0])
        kinetics = tables.read_table(path).data
        parts.append(curves.mean_curves(kinetics, rows["stride"], spring, smk.params.points))
    table = pd.concat(parts).sort_values(["spring_stiffness_N_per_m", "gait_cycle_pct"])
    tables.write_table(smk.output[0], table.reset_index(drop=True), provenance)


runner.run(snakemake, stage)
