"""Rule sts_modules: tune the spring–damper modules to minimise the user's joint torque."""

from exobench import atomic, tables
from exobench.plumbing import runner
from exobench.sts import kinematics, tuning


def stage(smk, provenance):
    cfg = smk.params
    law = cfg["tuning"]["law"]
    sampled = kinematics.motion_from_table(tables.read_table(smk.input[law]).data)
    table = tables.read_table(smk.input.loads).data
    required = table.loc[table["law"] == law, [f"{j}_dynamic_Nm" for j in tuning.JOINTS]].to_numpy(
        float
    )
    fit = tuning.tune(sampled, required, cfg["tuning"])
    tuned = {j: {p: fit[j][p] for p in tuning.PARAMETERS} for j in tuning.JOINTS}
    torques = tuning.module_table(sampled, required, cfg["modules"], tuned)
    configured = {j: tuning.rms(torques[f"{j}_user_configured_Nm"]) for j in tuning.JOINTS}
    runner.LOG.info("tuned modules: %s", fit)
    tables.write_table(smk.output.torques, torques, provenance)
    atomic.write_json(
        smk.output.fit,
        {
            "law": law,
            "objective": "mean square of the user's extensor torque per joint",
            "tuned": fit,
            "configured": cfg["modules"],
            "user_rms_configured_Nm": configured,
            "provenance": provenance,
        },
    )


runner.run(snakemake, stage)
