"""Rule validate_openworld_batch: a batch of the independent generator's recordings (a fault of
the assumption table beside registry effects, or two to four registry effects), analysed."""

import pandas as pd

from exobench import tables
from exobench.phantom import reference
from exobench.phantom.rig import Rig
from exobench.phantom.validation import openworld
from exobench.plumbing import runner


def stage(smk, provenance):
    block = smk.params.validation["openworld"]
    base = {"phantom": smk.params.phantom, "discrepancy": smk.params.engine,
            "seed": int(smk.params.seed)}  # fmt: skip
    cycle = reference.read_mean_cycle(smk.input.cycle)
    swing = reference.swing_fraction(cycle)
    rig = Rig()  # the generator writes the nominal rig, whatever phantom.rig says
    cases = [("open world", i) for i in range(int(block["cases"]))]
    cases += [("combined", i) for i in range(int(block["combined"]))]
    batch, batches = int(smk.wildcards.batch), int(block["batches"])
    rows = []
    for arm, index in cases[batch::batches]:
        case, report, checks, seed = openworld.run_case(
            arm,
            index,
            base,
            smk.input.cycle,
            swing,
            rig,
            smk.params.validation["strides_per_trial"],
        )
        runner.LOG.info("%s case %d (seed %d): fault %s, violations %s; %s", arm, index, seed,
                        case["fault"], case["violations"], report["cause"])  # fmt: skip
        rows.extend(openworld.case_rows(arm, index, seed, case, report, checks))
    tables.write_csv(smk.output[0], pd.DataFrame(rows), provenance)


runner.run(snakemake, stage)
