"""Rule sts_kinematics: the study's law (eq. 4) and its minimum-jerk form, the corrected law onto
the chair and onto the study's own seat, their trajectories and their verification."""

from exobench import atomic, tables
from exobench.plumbing import runner
from exobench.sts import body, corrected, kinematics, laws, motion, verification


def stage(smk, provenance):
    cfg = smk.params
    built = corrected.configured_laws(cfg)
    study = built["piecewise"]
    t = laws.time_grid(study, cfg["sample_rate_Hz"])
    report = {"tolerance_m": 1e-9, "laws": {}}
    for name, law in built.items():
        sampled = laws.sample(law, t)
        chain = kinematics.Chain.from_config(cfg["links_mm"], motion.law(name).convention)
        paths = kinematics.closed_loop(chain, sampled)
        tables.write_table(
            smk.output[name], kinematics.trajectory_table(sampled, paths), provenance
        )
        report["laws"][name] = verification.deviations(
            paths, chain.lengths_m, sampled, chain.convention
        )
        runner.LOG.info("%s: %s", name, report["laws"][name])
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
    the_body = body.Body.from_config(cfg["body"], cfg["links_mm"])
    checks = cfg["checks"]
    postures = {
        name: corrected.summary(built[name], the_body, study)
        for name in ("corrected", "corrected_study_seat")
    }
    postures["study_seat_height_mm"] = built["corrected_study_seat"].seat_height_mm
    postures["chair_range_mm"] = list(cfg["corrected"]["chair_range_mm"])
    postures["chair_range_source"] = cfg["corrected"]["chair_range_source"]
    postures["study_loading_at_the_chair"] = corrected.loaded_point_reach(
        study.chain,
        cfg["corrected"]["seat_height_mm"],
        checks["thigh_horizontal_tolerance_deg"],
        checks["slight_lean_max_deg"],
    )
    postures["foot_heel_mm"] = -float(checks["foot"]["ankle_from_heel_mm"])
    postures["foot_toe_mm"] = float(
        checks["foot"]["length_mm"] - checks["foot"]["ankle_from_heel_mm"]
    )
    atomic.write_json(smk.output.postures, {**postures, "provenance": provenance})


runner.run(snakemake, stage)
