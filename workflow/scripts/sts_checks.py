"""Rule sts_checks: every reading of the study's law, the corrected laws and the users' law files
(each beside its mirror) through the same checks, and the readings' verdicts."""

from dataclasses import replace

import pandas as pd

from exobench import atomic, tables
from exobench.plumbing import runner
from exobench.sts import body, checks, corrected, laws, readings


def stage(smk, provenance):
    cfg = smk.params
    the_body = body.Body.from_config(cfg["body"], cfg["links_mm"])
    settings = checks.Settings.from_config(cfg["checks"])
    study_readings = laws.readings(cfg)
    built = corrected.configured_laws(cfg)
    users = {}
    for path in smk.input.user_laws:
        law = laws.load(path)
        mirror = replace(law, name=f"{law.name}, mirrored", facing=-law.facing)
        users[law.name] = {
            law.name: (law, f"the law file {path}", True),
            mirror.name: (mirror, "its mirror image (the other facing)", False),
        }
    every = [law for law, _, _ in study_readings.values()]
    every += [built["corrected"], built["corrected_study_seat"]]
    every += list(corrected.chair_laws(cfg).values())
    every += [law for user in users.values() for law, _, _ in user.values()]
    table = pd.concat(
        [
            checks.law_checks(
                law,
                laws.sample(law, laws.time_grid(law, cfg["sample_rate_Hz"])),
                the_body,
                settings,
            )[0]
            for law in every
        ],
        ignore_index=True,
    )
    verdict = readings.verdict(table, study_readings)
    verdict["users"] = {name: readings.verdict(table, user) for name, user in users.items()}
    runner.LOG.info("readings: survivors %s, cause %s", verdict["survivors"], verdict["cause"])
    tables.write_csv(smk.output.checks, table, provenance)
    atomic.write_json(smk.output.readings, {**verdict, "provenance": provenance})


runner.run(snakemake, stage)
