"""Rule sts_figures: joint paths, torques, spring–damper modules, thigh loads, with captions."""

import json

from matplotlib import pyplot as plt

from exobench import figures, tables
from exobench.plumbing import runner
from exobench.sts import plots


def stage(smk, provenance):
    trajectories = {law: tables.read_table(smk.input[law]).data for law in ("piecewise", "smooth")}
    drawn = plots.all_figures(
        trajectories,
        tables.read_table(smk.input.loads).data,
        json.loads(open(smk.input.comparison, encoding="utf-8").read()),
        tables.read_table(smk.input.modules).data,
        json.loads(open(smk.input.beam, encoding="utf-8").read()),
    )
    for name, (fig, caption) in drawn.items():
        figures.save(fig, smk.output[f"{name}_png"], smk.output[f"{name}_pdf"])
        figures.write_caption(smk.output[f"{name}_caption"], *caption)
        plt.close(fig)


runner.run(snakemake, stage)
