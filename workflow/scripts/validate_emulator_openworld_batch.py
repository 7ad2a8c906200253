"""Rule validate_emulator_openworld_batch: a batch of the independent emulator generator's
recordings (a fault of the assumption table beside registry effects, or two to four registry
effects), analysed."""

import pandas as pd

from exobench import tables
from exobench.emulator.validation import openworld
from exobench.plumbing import runner


def stage(smk, provenance):
    block = smk.params.emulator["validation"]["openworld"]
    cases = [("open world", i) for i in range(int(block["cases"]))]
    cases += [("combined", i) for i in range(int(block["combined"]))]
    batch, batches = int(smk.wildcards.batch), int(block["batches"])
    rows = []
    for arm, index in cases[batch::batches]:
        case, report, checks, seed = openworld.run_case(
            arm, index, smk.params.emulator, smk.params.engine, int(smk.params.seed),
            block["durations_s"],
        )  # fmt: skip
        runner.LOG.info("%s case %d (seed %d): fault %s, violations %s; %s", arm, index, seed,
                        case["fault"], case["violations"], report["cause"])  # fmt: skip
        rows.extend(
            openworld.case_rows(arm, index, seed, case, report, checks, smk.params.emulator)
        )
    tables.write_csv(smk.output[0], pd.DataFrame(rows), provenance)


runner.run(snakemake, stage)
