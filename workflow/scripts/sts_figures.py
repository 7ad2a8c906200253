"""Rule sts_figures: joint paths, torques, spring–damper modules, thigh loads, with captions."""

import json

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
    figures.publish(smk.output, smk.params.figures, drawn)


runner.run(snakemake, stage)
