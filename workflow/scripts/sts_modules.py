"""Rule sts_modules: tune the spring–damper modules to minimise the user's joint torque, on the
study's law (the config's choice) and on the corrected laws."""

import pandas as pd

from exobench import atomic, tables
from exobench.plumbing import runner
from exobench.sts import kinematics, tuning


def stage(smk, provenance):
    cfg = smk.params
    table = tables.read_table(smk.input.loads).data
    fits, parts = {}, []
    for law in (cfg["tuning"]["law"], "corrected_study_seat", "corrected"):
        sampled = kinematics.motion_from_table(tables.read_table(smk.input[law]).data)
        rows = table[table["law"] == law]
        required = rows[[f"{j}_dynamic_Nm" for j in tuning.JOINTS]].to_numpy(float)
        fits[law] = tuning.law_fit(sampled, required, cfg["tuning"], cfg["modules"])
        parts.append(tuning.module_table(law, sampled, required, cfg["modules"],
                                         fits[law]["tuned_modules"]))  # fmt: skip
        runner.LOG.info("tuned modules, %s: %s", law, fits[law]["tuned"])
    tables.write_table(smk.output.torques, pd.concat(parts, ignore_index=True), provenance)
    atomic.write_json(
        smk.output.fit,
        {
            "study_law": cfg["tuning"]["law"],
            "objective": "mean square of the user's extensor torque per joint",
            "configured": cfg["modules"],
            "laws": fits,
            "provenance": provenance,
        },
    )


runner.run(snakemake, stage)
