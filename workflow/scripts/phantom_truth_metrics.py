"""Rule phantom_truth_metrics: the twin's true per-stride metrics of every trial, from its truth
files through the metrics' definitions (the method check's reference)."""

from pathlib import Path

import pandas as pd

from exobench import tables
from exobench.phantom.recordings import c3d
from exobench.phantom.twin import truth
from exobench.plumbing import runner


def stage(smk, provenance):
    manifest = c3d.read_manifest(Path(smk.input.manifest)).set_index("trial")
    parts = [
        truth.true_metrics(
            trial,
            manifest.loc[trial, "spring_stiffness_N_per_m"],
            tables.read_table(path).data,
            smk.params.protocol,
        )
        for trial, path in zip(smk.params.trials, smk.input.truth, strict=True)
    ]
    tables.write_table(smk.output[0], pd.concat(parts, ignore_index=True), provenance)


runner.run(snakemake, stage)
