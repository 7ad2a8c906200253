"""Rule emulator_compare: every number of Heer's thesis the group computes beside the project's,
with its role by the one rule (exobench.roles) and the reason for every miss."""

import functools
import json
from pathlib import Path

import pandas as pd

from exobench import tables
from exobench.emulator.study import comparison, heer_numbers
from exobench.plumbing import runner


def stage(smk, provenance):
    samples = dict(zip(smk.params.trials, smk.input.samples, strict=True))
    config = {
        "acquisition": smk.params.acquisition,
        "budget": smk.params.budget,
        "effects": smk.params.effects,
        "equilibrium_deg": smk.params.equilibrium_deg,
        "comparison": smk.params.comparison,
        "controller": {
            "torque_filter_Hz": smk.params.torque_filter_Hz,
            "velocity_cutoff_Hz": smk.params.velocity_cutoff_Hz,
        },
        "match_window_s": smk.params.match_window_s,
    }
    context = heer_numbers.Context(
        summary=pd.read_csv(smk.input.summary),
        qc=json.loads(Path(smk.input.qc).read_text(encoding="utf-8"))["trials"],
        budget=json.loads(Path(smk.input.budget).read_text(encoding="utf-8")),
        config=config,
        reported=pd.read_csv(smk.input.reported, dtype={"value": str}),
        # every row reads the same trials: each file once
        samples=functools.cache(lambda trial: tables.read_table(samples[trial]).data),
        steps=tables.read_table(smk.input.steps).data,
    )
    table = comparison.compare(context)
    runner.LOG.info(
        "Heer's numbers:\n%s",
        table[["metric", "heer_value", "project_value", "role", "within_tolerance"]].to_string(),
    )
    tables.write_csv(smk.output[0], table, provenance)


runner.run(snakemake, stage)
