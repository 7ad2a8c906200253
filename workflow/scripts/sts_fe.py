"""Rule sts_fe: the thigh link by finite elements (plane stress, quadratic triangles) under the
study's load cases, its mesh convergence, the load-introduction hypotheses and the beam formulas
against the field."""

import pandas as pd

from exobench import atomic, tables
from exobench.plumbing import runner
from exobench.sts import fea, strength


def stage(smk, provenance):
    cfg = smk.params
    reported = strength.read_reported(smk.input.reported)
    link = fea.link_from_config(cfg["thigh_link"], float(cfg["l_BC_mm"]), cfg["design_load_N"])
    report, (nodes, triangles) = fea.analyse(link, cfg["fe"], reported)
    runner.LOG.info("finest mesh: %s", report["finest"])
    tables.write_table(smk.output.field, pd.DataFrame(nodes), provenance)
    tables.write_table(smk.output.mesh, pd.DataFrame(triangles), provenance,
                       dict.fromkeys(triangles, "1"))  # fmt: skip
    atomic.write_json(smk.output.report, {**report, "seed_fea": reported,
                                          "provenance": provenance})  # fmt: skip


runner.run(snakemake, stage)
