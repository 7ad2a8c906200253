"""Rule sts_figures: joint paths, torques, spring–damper modules, thigh loads."""

import json

from exobench import runner, tables
from exobench.sts import plots


def stage(smk, provenance):
    trajectories = {law: tables.read_table(smk.input[law]).data for law in ("piecewise", "smooth")}
    loads = tables.read_table(smk.input.loads).data
    comparison = json.loads(open(smk.input.comparison, encoding="utf-8").read())
    check = json.loads(open(smk.input.beam, encoding="utf-8").read())
    out = smk.output
    plots.paths(trajectories, out.paths_png, out.paths_pdf)
    plots.torques(loads, comparison, out.torques_png, out.torques_pdf)
    plots.modules(tables.read_table(smk.input.modules).data, out.modules_png, out.modules_pdf)
    plots.thigh(loads, check, out.thigh_png, out.thigh_pdf)


runner.run(snakemake, stage)
