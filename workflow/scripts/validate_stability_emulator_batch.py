"""Rule validate_stability_emulator_batch: a batch of the emulator twin's recordings with a rig
constant changed in one trial, or in none, and the parameter stability's outcome."""

import pandas as pd

from exobench import tables
from exobench.emulator.validation import stability
from exobench.plumbing import runner


def stage(smk, provenance):
    block = smk.params.stability
    per_batch = -(-int(block["cases"]) // int(block["batches"]))
    first = int(smk.wildcards.batch) * per_batch
    seed = int(smk.params.seed)
    rows = []
    for index in range(first, min(first + per_batch, int(block["cases"]))):
        case = stability.run_case(index, smk.params.group, smk.params.engine, seed)
        runner.LOG.info("case %d: %s", index, "; ".join(
            f"{r['constant']} p {r['p']:.3g} flag {r['flag']}" for r in case))  # fmt: skip
        rows.extend(case)
    tables.write_csv(smk.output[0], pd.DataFrame(rows), provenance)


runner.run(snakemake, stage)
