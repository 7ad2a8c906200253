"""Rule validate_discrepancy_batch: a batch of twin recordings with hidden effects, analysed."""

import pandas as pd

from exobench import tables
from exobench.phantom import reference
from exobench.phantom.rig import Rig
from exobench.phantom.validation import twin_arm
from exobench.plumbing import runner


def stage(smk, provenance):
    block = smk.params.validation
    base = {"phantom": smk.params.phantom, "discrepancy": smk.params.engine,
            "seed": int(smk.params.seed)}  # fmt: skip
    cycle = reference.read_mean_cycle(smk.input.cycle)
    swing = reference.swing_fraction(cycle)
    rig = Rig.from_config(smk.params.phantom["rig"])
    per_batch = -(-int(block["cases"]) // int(block["batches"]))
    first = int(smk.wildcards.batch) * per_batch
    rows = []
    for index in range(first, min(first + per_batch, int(block["cases"]))):
        truth, report = twin_arm.run_case(
            index, base, cycle["knee_flexion_deg"].to_numpy(), swing, rig,
            block["strides_per_trial"],
        )  # fmt: skip
        runner.LOG.info("case %d (seed %d): hidden %s; %s", index, truth["seed"],
                        truth["hidden"], report["cause"])  # fmt: skip
        rows.extend(twin_arm.case_rows(truth, report))
    tables.write_csv(smk.output[0], pd.DataFrame(rows), provenance)


runner.run(snakemake, stage)
