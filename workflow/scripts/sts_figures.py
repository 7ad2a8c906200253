"""Rule sts_figures: joint paths, torques, spring–damper modules, thigh loads and the thigh link
by finite elements, with captions."""

import json

from exobench import figures, tables
from exobench.plumbing import runner
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
    figures.publish(smk.output, smk.params.figures, drawn)


runner.run(snakemake, stage)
