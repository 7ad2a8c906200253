"""Rule sts_kinematics: eqs. (1)–(4) trajectories, smooth and corrected laws, verification."""

from exobench import atomic, tables
from exobench.plumbing import runner
from exobench.sts import corrected, kinematics, loads, motion, verification


def stage(smk, provenance):
    cfg = smk.params
    t = motion.time_grid(cfg["sample_rate_Hz"])
    bodies = loads.Bodies.from_config(cfg)
    chains = {c: kinematics.Chain.from_config(cfg["links_mm"], c) for c in ("study", "corrected")}
    heel_m = cfg["foot"]["ankle_from_heel_mm"] / 1000.0
    margin_m = cfg["corrected"]["balance_margin_mm"] / 1000.0
    at_seat, seated = corrected.postures(chains["corrected"], bodies, heel_m, margin_m)
    sampled = {
        "piecewise": motion.piecewise(t),
        "smooth": motion.smooth(t),
        "corrected": motion.min_jerk(t, at_seat, seated),
    }
    report = {"tolerance_m": 1e-9, "laws": {}}
    for law, motion_law in sampled.items():
        chain = chains[motion.law(law).convention]
        paths = kinematics.closed_loop(chain, motion_law)
        tables.write_table(smk.output[law], kinematics.trajectory_table(motion_law, paths),
                           provenance)  # fmt: skip
        report["laws"][law] = verification.deviations(
            paths, chain.lengths_m, motion_law, chain.convention
        )
        runner.LOG.info("%s: %s", law, report["laws"][law])
    report["max_position_deviation_m"] = max(
        v["max_position_deviation_m"] for v in report["laws"].values()
    )
    report["passed"] = report["max_position_deviation_m"] < report["tolerance_m"]
    report["method"] = (
        "serial chain of 3x3 homogeneous transforms; velocities and accelerations from "
        "rigid-body cross products (exobench.sts.verification), against eqs. (1)-(3) and the "
        "corrected chain"
    )
    atomic.write_json(smk.output.verification, {**report, "provenance": provenance})
    atomic.write_json(
        smk.output.postures,
        {**corrected.summary(chains["corrected"], bodies, at_seat, seated),
         "provenance": provenance},
    )  # fmt: skip


runner.run(snakemake, stage)
