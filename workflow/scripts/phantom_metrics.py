"""Rule phantom_metrics: per-stride metrics of every trial (contract table), each stride's
outlying metrics named with the reason (and listed in outliers.csv)."""

from pathlib import Path

import pandas as pd

from exobench import tables
from exobench.phantom.chain import kinetics, metrics
from exobench.phantom.recordings import c3d
from exobench.phantom.rig import ANALOG_RATE_HZ
from exobench.phantom.study import outliers
from exobench.plumbing import runner


def stage(smk, provenance):
    protocol = smk.params.protocol
    manifest = c3d.read_manifest(Path(smk.input.manifest)).set_index("trial")
    parts = []
    for trial, strides, files in zip(
        smk.params.trials, smk.input.strides, kinetics.trial_files(smk.input), strict=True
    ):
        table = metrics.metrics_table(
            trial,
            manifest.loc[trial, "spring_stiffness_N_per_m"],
            tables.read_table(strides).data,
            kinetics.read(files),
            1.0 / ANALOG_RATE_HZ,
            protocol,
            smk.params.slope_validity,
        )
        runner.LOG.info(
            "%s: %d programmed, %d analysed, %d included",
            trial,
            len(table),
            table["peak_moment_Nm"].notna().sum(),
            table["included"].sum(),
        )
        parts.append(table)
    table = pd.concat(parts, ignore_index=True)
    invalid = metrics.invalid_counts(table, smk.params.slope_validity)
    runner.LOG.info(
        "slope validity (loading excursion >= %.3g deg): %d slope values left out",
        metrics.min_excursion_deg(smk.params.slope_validity),
        int(invalid["invalid"].sum()),
    )
    found = outliers.find(table, metrics.METRIC_COLUMNS, smk.params.robust_z)
    runner.LOG.info(
        "%d outlying values in %d strides (robust z beyond %g)",
        len(found),
        found.groupby(["trial", "stride"]).ngroups,
        smk.params.robust_z,
    )
    tables.write_table(smk.output.metrics, outliers.annotate(table, found), provenance)
    tables.write_csv(smk.output.outliers, found, provenance)


runner.run(snakemake, stage)
