"""Rule phantom_compare: every number W.S.B. et al. report against the reproduced one."""

import pandas as pd

from exobench import tables
from exobench.phantom.study import comparison
from exobench.plumbing import runner


def stage(smk, provenance):
    table = comparison.compare(
        pd.read_csv(smk.input.reported), tables.read_table(smk.input.metrics).data
    )
    worst = table.sort_values("rel_error", ascending=False).head(3)
    runner.LOG.info("largest relative errors:\n%s", worst.to_string(index=False))
    tables.write_csv(smk.output[0], table, provenance)


runner.run(snakemake, stage)
