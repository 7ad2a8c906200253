"""Rule sts_checks: every motion law against the study's words and against balance."""

from exobench import tables
from exobench.plumbing import runner
from exobench.sts import checks, kinematics, loads, motion


def stage(smk, provenance):
    cfg = smk.params
    trajectories = {law: tables.read_table(smk.input[law]).data for law in motion.LAWS}
    chains = {c: kinematics.Chain.from_config(cfg["links_mm"], c) for c in ("study", "corrected")}
    table = checks.checks(
        trajectories,
        tables.read_table(smk.input.loads).data,
        chains,
        loads.Bodies.from_config(cfg),
        checks.Settings.from_config(cfg["checks"]),
    )
    for _, r in table[table["decision"] == "violated"].iterrows():
        runner.LOG.info("%s: %s %.4g %s violated (%s)", r["law"], r["quantity"], r["value"],
                        r["unit"], r["cause"] or "cause not named")  # fmt: skip
    tables.write_csv(smk.output[0], table, provenance)


runner.run(snakemake, stage)
