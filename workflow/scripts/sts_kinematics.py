"""Rule sts_kinematics: eqs. (1)–(4) trajectories, smooth laws, independent verification."""

from exobench import atomic, tables
from exobench.plumbing import runner
from exobench.sts import kinematics, motion, verification


def stage(smk, provenance):
    cfg = smk.params
    chain = kinematics.Chain.from_config(cfg["links_mm"])
    t = motion.time_grid(cfg["sample_rate_Hz"])
    report = {"tolerance_m": 1e-9, "laws": {}}
    for law, output in (("piecewise", smk.output.piecewise), ("smooth", smk.output.smooth)):
        sampled = motion.LAWS[law](t)
        paths = kinematics.closed_loop(chain, sampled)
        tables.write_table(output, kinematics.trajectory_table(sampled, paths), provenance)
        report["laws"][law] = verification.deviations(paths, chain.lengths_m, sampled)
        runner.LOG.info("%s: %s", law, report["laws"][law])
    report["max_position_deviation_m"] = max(
        v["max_position_deviation_m"] for v in report["laws"].values()
    )
    report["passed"] = report["max_position_deviation_m"] < report["tolerance_m"]
    report["method"] = (
        "serial chain of 3x3 homogeneous transforms; velocities and accelerations from "
        "rigid-body cross products (exobench.sts.verification), against eqs. (1)-(3)"
    )
    atomic.write_json(smk.output.verification, {**report, "provenance": provenance})


runner.run(snakemake, stage)
