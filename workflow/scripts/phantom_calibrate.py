"""Rule phantom_calibrate: fit the twin's effect parameters to the medians W.S.B. et al. report;
the fitted twin's simulated strides beside the fit."""

import pandas as pd

from exobench import atomic, tables
from exobench.phantom import reference
from exobench.phantom.rig import Rig
from exobench.phantom.twin import calibrate
from exobench.plumbing import runner


def stage(smk, provenance):
    cfg = runner.settings(smk)
    cycle = reference.read_mean_cycle(smk.input.cycle)["knee_flexion_deg"].to_numpy()
    reported = pd.read_csv(smk.input.reported)
    fitted, summary, table, simulated = calibrate.fit(
        cycle, reported, Rig.from_config(cfg["rig"]), cfg, cfg["calibration"]
    )
    runner.LOG.info("fitted %s (rms scaled residual %.3f)", fitted, summary["rms_scaled_residual"])
    atomic.write_json(smk.output.fit, {**summary, "provenance": provenance})
    atomic.write_text(smk.output.residuals, table.to_csv(index=False, lineterminator="\n"))
    tables.write_table(smk.output.strides, simulated, provenance)


runner.run(snakemake, stage)
