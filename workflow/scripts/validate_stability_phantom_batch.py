"""Rule validate_stability_phantom_batch: a batch of the phantom twin's recordings with a rig
constant changed in one trial, or in none, and the parameter stability's outcome."""

import pandas as pd

from exobench import tables
from exobench.phantom import reference
from exobench.phantom.validation import stability
from exobench.plumbing import runner


def stage(smk, provenance):
    block = smk.params.stability
    per_batch = -(-int(block["cases"]) // int(block["batches"]))
    first = int(smk.wildcards.batch) * per_batch
    seed = int(smk.params.seed)
    cycle = reference.read_mean_cycle(smk.input.cycle)
    base = {"phantom": smk.params.group, "discrepancy": smk.params.engine, "seed": seed}
    rows = []
    for index in range(first, min(first + per_batch, int(block["cases"]))):
        case = stability.run_case(
            index,
            base,
            cycle["knee_flexion_deg"].to_numpy(),
            reference.swing_fraction(cycle),
            block["strides_per_trial"],
        )
        runner.LOG.info("case %d: %s", index, "; ".join(
            f"{r['constant']} p {r['p']:.3g} flag {r['flag']}" for r in case))  # fmt: skip
        rows.extend(case)
    tables.write_csv(smk.output[0], pd.DataFrame(rows), provenance)


runner.run(snakemake, stage)
