"""Rule phantom_calibrate: fit the twin's effect parameters to the medians W.S.B. et al. report."""

import pandas as pd

from exobench import atomic
from exobench.phantom import reference
from exobench.phantom.rig import Rig
from exobench.phantom.twin import calibrate
from exobench.plumbing import runner


def stage(smk, provenance):
    cfg = dict(smk.params.items())
    cycle = reference.read_mean_cycle(smk.input.cycle)["knee_flexion_deg"].to_numpy()
    reported = pd.read_csv(smk.input.reported)
    fitted, summary, table = calibrate.fit(
        cycle, reported, Rig.from_config(cfg["rig"]), cfg, cfg["calibration"]
    )
    runner.LOG.info("fitted %s (rms scaled residual %.3f)", fitted, summary["rms_scaled_residual"])
    atomic.write_json(smk.output.fit, {**summary, "provenance": provenance})
    atomic.write_text(smk.output.residuals, table.to_csv(index=False, lineterminator="\n"))


runner.run(snakemake, stage)
