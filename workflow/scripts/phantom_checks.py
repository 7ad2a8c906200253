"""Rule phantom_checks: the direct checks of the rig's assumptions (no model) on every trial."""

from pathlib import Path

import pandas as pd

from exobench import tables
from exobench.phantom.chain import angles, kinetics
from exobench.phantom.model import checks
from exobench.phantom.recordings import c3d
from exobench.phantom.rig import Rig
from exobench.plumbing import runner


def stage(smk, provenance):
    manifest = c3d.read_manifest(Path(smk.input.manifest)).set_index("trial")
    metrics = tables.read_table(smk.input.metrics).data
    parts = []
    for trial, files, strides, markers in zip(
        smk.params.trials, kinetics.trial_files(smk.input), smk.input.strides,
        smk.input.markers, strict=True,
    ):  # fmt: skip
        read = kinetics.read_parts(files)  # each file once: the join and the joint centres
        parts.append({
            "trial": trial,
            "spring": manifest.loc[trial, "spring_stiffness_N_per_m"],
            "kinetics": kinetics.joined(read, checks.KINETICS_COLUMNS),
            "strides": tables.read_table(strides).data,
            "angles": angles.with_centres(read["angles"], tables.read_table(markers).data),
            "metrics": metrics[metrics["trial"] == trial],
        })  # fmt: skip
    settings = {**smk.params.checks, "window_pct": smk.params.window_pct,
                "swing_pct": smk.params.swing_pct}  # fmt: skip
    table = checks.checks(parts, Rig.from_config(smk.params.rig), settings)
    for _, row in table[table["decision"] != "holds"].iterrows():
        runner.LOG.info("%s: %s %s (%s)", row["assumption"], row["quantity"], row["decision"],
                        row["detail"] or f"{row['measured']:.3g} {row['unit']}")  # fmt: skip
    tables.write_csv(smk.output[0], pd.DataFrame(table), provenance)


runner.run(snakemake, stage)
