"""Rule emulator_budget: motor thermal check (eqs. 4.1-4.2) and torque budget (section 4.4)."""

import numpy as np
import pandas as pd

from exobench import atomic, tables
from exobench.emulator.study import budget
from exobench.plumbing import runner


def stage(smk, provenance):
    torque = np.concatenate(
        [tables.read_table(p).data["brace_torque_Nm"].to_numpy() for p in smk.input.samples]
    )
    result = budget.check(smk.params.budget, smk.params.transmission, torque)
    result["reported"] = budget.compare_reported(result, pd.read_csv(smk.input.reported))
    runner.LOG.info("budget: %s", result["margins"])
    atomic.write_json(smk.output[0], {**result, "provenance": provenance})


runner.run(snakemake, stage)
