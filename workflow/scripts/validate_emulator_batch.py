"""Rule validate_emulator_batch: a batch of emulator recordings with hidden effects, analysed."""

import pandas as pd

from exobench import tables
from exobench.emulator.validation import twin_arm as validation
from exobench.plumbing import runner


def stage(smk, provenance):
    base = validation.base_config(smk.params.emulator)
    block = smk.params.emulator["validation"]
    per_batch = -(-int(block["cases"]) // int(block["batches"]))
    first = int(smk.wildcards.batch) * per_batch
    rows = []
    for index in range(first, min(first + per_batch, int(block["cases"]))):
        truth, report = validation.run_case(index, base, smk.params.engine, int(smk.params.seed))
        runner.LOG.info("case %d (seed %d): hidden %s; %s", index, truth["seed"],
                        truth["hidden"], report["cause"])  # fmt: skip
        rows.extend(validation.case_rows(truth, report))
    tables.write_csv(smk.output[0], pd.DataFrame(rows), provenance)


runner.run(snakemake, stage)
