"""Rule sts_figures: joint paths, torques, spring–damper modules, thigh loads and the thigh link
by finite elements, with captions."""

import json

from matplotlib import pyplot as plt

from exobench import figures, runner, tables
from exobench.sts import motion, plots


def stage(smk, provenance):
    trajectories = {law: tables.read_table(smk.input[law]).data for law in motion.LAWS}
    fe = (
        json.loads(open(smk.input.fe, encoding="utf-8").read()),
        tables.read_table(smk.input.field).data,
        tables.read_table(smk.input.mesh).data,
    )
    drawn = plots.all_figures(
        trajectories,
        tables.read_table(smk.input.loads).data,
        json.loads(open(smk.input.comparison, encoding="utf-8").read()),
        tables.read_table(smk.input.modules).data,
        json.loads(open(smk.input.beam, encoding="utf-8").read()),
        fe,
    )
    for name, (fig, caption) in drawn.items():
        figures.save(fig, smk.output[f"{name}_png"], smk.output[f"{name}_pdf"])
        figures.write_caption(smk.output[f"{name}_caption"], *caption)
        plt.close(fig)


runner.run(snakemake, stage)
