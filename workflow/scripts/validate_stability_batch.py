"""Rule validate_stability_batch: a batch of one group's twin recordings with a rig constant
changed in one trial, or in none, and the parameter stability's outcome."""

import pandas as pd

from exobench import tables
from exobench.emulator.validation import stability as emulator
from exobench.phantom import reference
from exobench.phantom.validation import stability as phantom
from exobench.plumbing import runner


def stage(smk, provenance):
    block, group, seed = smk.params.stability, smk.wildcards.group, int(smk.params.seed)
    per_batch = -(-int(block["cases"]) // int(block["batches"]))
    first = int(smk.wildcards.batch) * per_batch
    cycle = reference.read_mean_cycle(smk.input.cycle)
    base = {"phantom": smk.params.phantom, "discrepancy": smk.params.engine, "seed": seed}
    rows = []
    for index in range(first, min(first + per_batch, int(block["cases"]))):
        if group == "phantom":
            case = phantom.run_case(index, base, cycle["knee_flexion_deg"].to_numpy(),
                                    reference.swing_fraction(cycle),
                                    block["strides_per_trial"])  # fmt: skip
        else:
            case = emulator.run_case(index, smk.params.emulator, smk.params.engine, seed)
        runner.LOG.info("%s case %d: %s", group, index, "; ".join(
            f"{r['constant']} p {r['p']:.3g} flag {r['flag']}" for r in case))  # fmt: skip
        rows.extend(case)
    tables.write_csv(smk.output[0], pd.DataFrame(rows), provenance)


runner.run(snakemake, stage)
