"""Rule sts_loads: joint torques of every motion law and the gain of the smooth laws."""

import pandas as pd

from exobench import atomic, tables
from exobench.plumbing import runner
from exobench.sts import kinematics, loads, motion, smoothing


def stage(smk, provenance):
    cfg = smk.params
    bodies = loads.Bodies.from_config(cfg)
    trajectories = {law: tables.read_table(smk.input[law]).data for law in motion.LAWS}
    parts = []
    for law, frame in trajectories.items():
        chain = kinematics.Chain.from_config(cfg["links_mm"], motion.law(law).convention)
        sampled = kinematics.motion_from_table(frame)
        parts.append(loads.load_table(law, chain, bodies, sampled, cfg["modules"]))
    table = pd.concat(parts, ignore_index=True)
    tables.write_table(smk.output.loads, table, provenance)
    comparison = smoothing.compare(trajectories, table)
    runner.LOG.info("gain of the smooth laws: %s", comparison["gain"])
    atomic.write_json(smk.output.comparison, {**comparison, "provenance": provenance})


runner.run(snakemake, stage)
