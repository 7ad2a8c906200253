"""Rule sts_loads: joint torques of both motion laws and the gain of the smooth laws."""

import pandas as pd

from exobench import atomic, tables
from exobench.plumbing import runner
from exobench.sts import kinematics, loads, smoothing


def stage(smk, provenance):
    cfg = smk.params
    chain = kinematics.Chain.from_config(cfg["links_mm"])
    bodies = loads.Bodies.from_config(cfg)
    trajectories = {
        law: tables.read_table(path).data
        for law, path in (("piecewise", smk.input.piecewise), ("smooth", smk.input.smooth))
    }
    table = pd.concat(
        [
            loads.load_table(
                law, chain, bodies, kinematics.motion_from_table(frame), cfg["modules"]
            )
            for law, frame in trajectories.items()
        ],
        ignore_index=True,
    )
    tables.write_table(smk.output.loads, table, provenance)
    comparison = smoothing.compare(trajectories, table)
    runner.LOG.info("gain of the smooth laws: %s", comparison["gain"])
    atomic.write_json(smk.output.comparison, {**comparison, "provenance": provenance})


runner.run(snakemake, stage)
