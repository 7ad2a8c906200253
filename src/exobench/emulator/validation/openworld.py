"""Validation on emulator recordings the project's twin did not make: the open-world and combined
arms (:mod:`exobench.selection.openworld`).

The recordings come from :mod:`exobench.emulator.validation.labsim`, a generator written from
docs/rig.md §3, the assumption table's law lines (docs/emulator_assumptions.md) and the physics
alone, apart from the twin and the engine. Every relaxation of the emulator's table that is not a
registry effect is violated in turn beside the cuff compliance every real brace has (and, half
the time, one more registry effect); the combined arm draws two to four registry effects. The
files are read back through the analysis chain as a lab's, the direct checks and the engine
report, and each case is scored against the truth.
"""

from __future__ import annotations

import copy
import dataclasses
import tempfile
from collections.abc import Mapping, Sequence
from pathlib import Path

import numpy as np
import pandas as pd

from exobench.emulator.model import assumptions, checks, discrepancy
from exobench.emulator.validation import labsim, twin_arm
from exobench.errors import InputError
from exobench.selection import checks as shared_checks
from exobench.selection import openworld

ARM = openworld.Arm(
    relaxations=assumptions.relaxations(),
    registry=assumptions.registry_terms(),
    kept="cuff.elastic",
    named=lambda table: shared_checks.named(table, assumptions.TABLE),
    violated=shared_checks.violated,
)


# The encoder relaxation every open-world case holds beside its fault: counts lost once.
DROP = "encoder.step"
# The largest lead of a release at a velocity threshold over Table 6.1's, per °/s of threshold:
# 12 ms at 40 °/s over 103 releases of labsim (0.8 and 1.2 m/s, four seeds; 2–3 ms at 10 °/s).
LEAD_S_PER_DEG_PER_S = 3e-4


def draw_case(name: str, index: int, rng: np.random.Generator, durations: Sequence[float],
              arm: Mapping | None = None) -> dict:  # fmt: skip
    """A case of an arm (:func:`exobench.selection.openworld.draw_violations`) and its recording
    length per trial; an open-world case of an ``arm`` block (config emulator.validation.
    openworld) also holds a count drop of ``drop_deg`` and, with ``readings``, a lab's reading
    of the thesis (:func:`labsim.draw_reading`; else the project's own, ``labsim.NOMINAL``)."""
    violations, fault = openworld.draw_violations(ARM, name, index, rng)
    case = {"violations": violations, "fault": fault, "duration_s": float(rng.choice(durations)),
            "reading": labsim.NOMINAL}  # fmt: skip
    if name != "combined" and arm is not None:
        (parameter,) = labsim.VIOLATIONS[DROP]
        violations[DROP] = {parameter: float(rng.uniform(*arm["drop_deg"]))}
        if arm["readings"]:
            case["reading"] = own_rows_nominal(labsim.draw_reading(rng), fault)
    return case


def own_rows_nominal(reading, fault: str | None):
    """The reading with the project's own rule for the row the fault violates (a release or an
    engagement off Table 6.1, or a velocity estimate off the chain's, is the fault alone, its
    truth its drawn size)."""
    nominal = labsim.NOMINAL
    if fault and fault.startswith("clutch_release."):
        return dataclasses.replace(
            reading, release_rule=nominal.release_rule, release_threshold_deg_per_s=0.0,
            release_delay_s=0.0,
        )  # fmt: skip
    if fault and fault.startswith("clutch_engage."):
        return dataclasses.replace(reading, engage_rule=nominal.engage_rule)
    if fault and fault.startswith("velocity_estimate."):
        return dataclasses.replace(reading, velocity_estimate=nominal.velocity_estimate,
                                   velocity_order=nominal.velocity_order)  # fmt: skip
    return reading


def settings(block: Mapping, duration_s: float, lab: Mapping | None = None) -> dict:
    """The emulator block the analysis reads, with the case's recording length and what the lab
    states in its config (``lab``: :meth:`labsim.Reading.lab_config`'s transmission, when it is
    calibrated, controller and sensors, each key replacing the project's)."""
    cfg = copy.deepcopy(dict(block))
    cfg["protocol"] = {**cfg["protocol"], "duration_s": duration_s}
    cfg["transmission_calibrated"] = (lab or {}).get("transmission_calibrated",
                                                     cfg["transmission_calibrated"])  # fmt: skip
    for key in ("transmission", "controller", "sensors"):
        for name, value in (lab or {}).get(key, {}).items():
            # a lab without a filter on its torque says so; one without a velocity cut-off (a
            # plain difference) leaves the analysis its own
            if value is not None or name == "torque_filter_Hz":
                cfg[key][name] = value
    return cfg


def chain_parts(manifest_path: Path, cfg: Mapping, seed: int) -> list[dict]:
    """Read the generator's files back as a lab's (:func:`twin_arm.chain_parts`): per trial its
    stiffness, the analysis chain's samples and the session QC."""
    return [{"trial": n, "stiffness": k, "samples": s, "qc": q}
            for n, k, s, q in twin_arm.chain_parts(manifest_path, cfg, seed)]  # fmt: skip


def check_settings(cfg: Mapping) -> dict:
    """What the direct checks read of the emulator block (as the rule emulator_checks gives it)."""
    controller = cfg["controller"]
    return {"checks": cfg["checks"], "sensors": cfg["sensors"],
            "transmission": cfg["transmission"],
            "velocity_cutoff_Hz": controller["velocity_cutoff_Hz"],
            "direction_blend_deg_per_s": controller["direction_blend_deg_per_s"],
            "torque_filter_Hz": controller["torque_filter_Hz"],
            "activity_tolerance_s": cfg["analysis"]["activity_tolerance_s"]}  # fmt: skip


def analysed(case: Mapping, block: Mapping, engine: Mapping, seed: int,
             directory: Path | None = None) -> tuple[dict, pd.DataFrame]:  # fmt: skip
    """The engine's report and the direct checks on the generator's recordings of a case (or a
    refusal, in the report's shape); the recordings and their truth are kept in ``directory``
    when one is given."""
    reading = case.get("reading", labsim.NOMINAL)
    cfg = settings(block, case["duration_s"], reading.lab_config())
    protocol = cfg["validation"]
    with tempfile.TemporaryDirectory() as tmp:
        manifest = labsim.write_study(
            Path(directory or tmp), speeds_m_per_s=protocol["speeds_m_per_s"],
            stiffnesses_Nm_per_rad=protocol["stiffnesses_Nm_per_rad"],
            duration_s=case["duration_s"], violations=dict(case["violations"]), seed=seed,
            reading=None if reading == labsim.NOMINAL else reading,
        )  # fmt: skip
        parts = chain_parts(manifest, cfg, seed)
    table = checks.checks(parts, check_settings(cfg))
    controller = cfg["controller"]
    try:
        data, scales = discrepancy.observations(
            [(p["trial"], p["stiffness"], p["samples"], p["qc"]) for p in parts],
            controller["equilibrium_deg"], controller["direction_blend_deg_per_s"],
            cfg["transmission"], int(engine["folds"]), controller["torque_filter_Hz"],
        )  # fmt: skip
    except InputError as error:  # too few complete steps: the engine refuses, says why
        return {"effects_found": [], "tentative": [], "unexplained": {"flag": False},
                "discovery": {"named": [], "proposed": []},
                "cause": f"refused: {error}"}, table  # fmt: skip
    report = discrepancy.analyse(data, scales, engine, seed, "open-world validation",
                                 suspects=checks.suspects(table))  # fmt: skip
    return report, table


def run_case(name: str, index: int, block: Mapping, engine: Mapping, seed: int,
             durations: Sequence[float]):  # fmt: skip
    """Draw and analyse one case of an arm: (case, report, direct checks, the case's seed)."""
    case_seed = int(seed) * 100_003 + index + (50_000 if name == "combined" else 0)
    case = draw_case(name, index, np.random.default_rng([case_seed, 31]), durations,
                     block["validation"]["openworld"])  # fmt: skip
    report, table = analysed(case, block, engine, case_seed)
    return case, report, table, case_seed


def case_rows(name: str, index: int, seed: int, case: Mapping, report: Mapping,
              table: pd.DataFrame, block: Mapping) -> list[dict]:  # fmt: skip
    """The case's rows (:func:`exobench.selection.openworld.case_rows`)."""
    drop = ARM.registry[DROP]
    located = "count_drops" in arm_violated(table)
    claimed = {e["effect"]: e for e in report["effects_found"]}.get(drop)
    # labsim drops counts within a trial only: a trial the QC calls faulty before it is sound
    detail = " ".join(table.loc[table["check"] == "count_drops", "detail"].fillna("").astype(str))
    common = {"duration_s": case["duration_s"], **variants(case.get("reading", labsim.NOMINAL)),
              "drop_located": located, "drop_claimed": claimed is not None,
              "sound_trials_called_faulty": detail.count("before the trial")}  # fmt: skip
    sized, unsized = implied(case.get("reading", labsim.NOMINAL), case["violations"],
                             case["fault"], block)  # fmt: skip
    return openworld.case_rows(ARM, name, index, seed, sized, case["fault"], report, table,
                               common, unsized)  # fmt: skip


def implied(reading, violations: Mapping, fault: str | None,
            block: Mapping) -> tuple[dict, tuple[str, ...]]:  # fmt: skip
    """The case's ``violations`` with the rows of the assumption table a lab's reading departs
    from beyond what it states in its config: sized where the reading is a row's own relaxation
    (a release delay after its event, added to a drawn one: ``clutch_release.delay``; a release
    at the impact peak with the analysis's velocity estimate: ``clutch_release.event`` at a share
    of 1; a latched arm with it: ``clutch_engage.event`` at a share of 1; a release at a velocity
    threshold with it and no delay, the lab's or drawn: ``clutch_release.threshold`` at that
    threshold), never the fault's own; and unsized (a release at a velocity threshold with a
    delay after it, which trades against the threshold, and read by ``clutch_release.event``:
    early, a share of its own each step; the delay then late by d less the threshold's lead,
    ``clutch_release.delay`` held where that is at least the smallest visible delay, or where the
    case also draws one, whose size it then changes; any rule through another velocity estimate,
    whose zero crossings come sooner or later than the chain's: its release as either early
    release, the impact peak or a latched arm, and the velocity estimate's own row; a controller
    whose velocity leads by the fault's l, as either early release (one whose l < 0 lags, as a
    late engagement or release); a friction loss as large as the least visible
    calibration zero it reads as, and any friction loss as the cable's friction bias, which it
    is; motion capture re-zeroed per trial, and so its zero off in the trials that share one; a
    calibration redone per trial). A row held, sized or not, is never a wrong name."""
    sized, unsized = dict(violations), []
    threshold = reading.release_rule == "velocity_threshold"
    if reading.release_delay_s > 0.0 and not threshold:
        drawn = violations.get("clutch_release.delay", {}).get("release_delay_s", 0.0)
        sized["clutch_release.delay"] = {"release_delay_s": drawn + reading.release_delay_s}
    analysis = reading.velocity_estimate == "butterworth" and reading.velocity_order == 2
    delayed = reading.release_delay_s > 0.0 or "clutch_release.delay" in violations
    if reading.release_rule == "heel_strike" and analysis:
        sized["clutch_release.event"] = {"heel_strike_share": 1.0}
    elif reading.release_rule != labsim.NOMINAL.release_rule or not analysis:
        unsized.append("clutch_release.event")
    if threshold and analysis and not delayed:
        sized["clutch_release.threshold"] = {
            "threshold_deg_per_s": reading.release_threshold_deg_per_s
        }
    elif threshold or not analysis:
        unsized.append("clutch_release.threshold")
    if threshold and delayed:
        # released d after a crossing that leads Table 6.1's: late by at least the smallest
        # visible delay only past the threshold's largest lead; a drawn delay then has no size
        late = ARM.relaxations["clutch_release.delay"][1].visible[0]
        late += LEAD_S_PER_DEG_PER_S * reading.release_threshold_deg_per_s
        if reading.release_delay_s >= late or "clutch_release.delay" in sized:
            sized.pop("clutch_release.delay", None)
            unsized.append("clutch_release.delay")
    if reading.engage_rule == "latched" and analysis:
        sized["clutch_engage.event"] = {"loading_share": 1.0}
    elif reading.engage_rule != labsim.NOMINAL.engage_rule:
        unsized.append("clutch_engage.event")
    if not analysis:  # its zero crossings lead or lag the chain's, at both events
        unsized.append("velocity_estimate.delay")
    if fault == "velocity_estimate.delay":  # both events moved: a lead reads in part as either
        # early release, a lag (a lead below 0) as a late engagement or release
        lag = violations[fault]["lead_s"] < 0.0
        unsized += (["clutch_engage.delay", "clutch_release.delay"] if lag
                    else ["clutch_release.event", "clutch_release.threshold"])  # fmt: skip
    zero = ARM.relaxations["cable_calibration.offset"][1].visible[0]
    if reading.friction_bias_Nm * block["transmission"]["flexion"]["C"] >= zero:
        unsized.append("cable_calibration.offset")
    if reading.friction_bias_Nm > 0.0:
        unsized.append("cable.bias")  # the generator adds it to the row's own bias
    if reading.mocap_rezeroed:  # each trial's zero off: the trials that share one read it too
        unsized += ["mocap_zero_between.between", "mocap.offset"]
    if reading.calibration == "per_trial":
        unsized.append("cable_tension_between.between")
    if fault in sized and fault in violations:
        sized[fault] = violations[fault]
    return sized, tuple(k for k in unsized if k != fault and k not in sized)


def arm_violated(table: pd.DataFrame) -> set[str]:
    """The direct checks a case's recordings violate, by check name."""
    return set(table.loc[table["decision"] == "violated", "check"])


def variants(reading) -> dict[str, str]:
    """A reading's variant on each axis the open-world arm reports by (the project's reading:
    "nominal")."""
    lab, nominal = reading.lab_config(), labsim.NOMINAL.lab_config()

    def variant(value, default, text) -> str:
        return "nominal" if value == default else text

    return {
        "reading_release": variant((reading.release_rule, reading.release_delay_s > 0.0),
                                   (labsim.NOMINAL.release_rule, False),
                                   reading.release_rule.replace("_", " ")
                                   + (" + delay" if reading.release_delay_s > 0.0 else "")),
        "reading_engage": variant(reading.engage_rule, labsim.NOMINAL.engage_rule,
                                  reading.engage_rule),
        "reading_velocity": variant(
            (reading.velocity_estimate, reading.velocity_order, reading.velocity_cutoff_Hz),
            (labsim.NOMINAL.velocity_estimate, labsim.NOMINAL.velocity_order,
             labsim.NOMINAL.velocity_cutoff_Hz), reading.velocity_estimate),
        "reading_delivery": variant(
            (reading.motor_time_constant_s, reading.friction_bias_Nm),
            (labsim.NOMINAL.motor_time_constant_s, labsim.NOMINAL.friction_bias_Nm),
            "lag or friction bias"),
        "reading_calibration": variant((lab["transmission"], reading.calibration),
                                       (nominal["transmission"], "session"),
                                       f"the lab's, {reading.calibration}"),
        "reading_encoder": variant(reading.encoder_counts_per_turn,
                                   labsim.NOMINAL.encoder_counts_per_turn,
                                   f"{reading.encoder_counts_per_turn} counts"),
        "reading_torque_filter": variant(reading.torque_filter_Hz, labsim.NOMINAL.torque_filter_Hz,
                                         "unfiltered" if reading.torque_filter_Hz is None
                                         else "other cut-off"),
        "reading_noise": variant((reading.load_cell_sd_Nm, reading.mocap_sd_deg),
                                 (labsim.NOMINAL.load_cell_sd_Nm, labsim.NOMINAL.mocap_sd_deg),
                                 "other levels"),
        "reading_mocap": variant(reading.mocap_rezeroed, False, "re-zeroed per trial"),
    }  # fmt: skip


READING_AXES = ("reading_release", "reading_engage", "reading_velocity", "reading_delivery",
                "reading_calibration", "reading_encoder", "reading_torque_filter",
                "reading_noise", "reading_mocap")  # fmt: skip


def by_reading(rows: pd.DataFrame) -> pd.DataFrame:
    """The open-world arm per reading variant (each axis of :func:`variants` and over all):
    cases, the share of each outcome, hypothesis precision, the count drop every case holds (the
    share of cases whose QC located it, of those the share claiming it, and the 95 % coverage of
    the claims) and the cases whose QC called a sound trial an encoder fault before it."""
    arm = rows[rows["arm"] == "open world"]
    faults = arm[arm["kind"] != "registry"].drop_duplicates("case")
    drops = arm[(arm["kind"] == "registry") & (arm["effect"] == ARM.registry[DROP])]
    drops = drops.set_index("case")
    out = []
    groups = [("all", "all", faults)]
    groups += [(axis, value, group) for axis in READING_AXES if axis in faults
               for value, group in faults.groupby(axis)]  # fmt: skip
    for axis, value, group in groups:
        entry = {"axis": axis.removeprefix("reading_"), "variant": value, "cases": len(group)}
        entry.update({o: float((group["outcome"] == o).mean()) for o in openworld.OUTCOMES})
        offered = float(group["hypotheses"].sum())
        entry["precision"] = float(group["hypotheses_right"].sum()) / offered if offered else np.nan
        drop = drops.loc[drops.index.intersection(group["case"])]
        located = drop[drop["drop_located"].astype(bool)]
        entry["drop_located"] = float(drop["drop_located"].astype(bool).mean())
        entry["drop_claimed_when_located"] = float(located["claimed"].mean())
        claimed = located[located["claimed"].astype(bool)]
        entry["drop_coverage_95"] = float(claimed["covered"].mean()) if len(claimed) else np.nan
        entry["cases_calling_a_sound_trial_faulty"] = int((group["sound_trials_called_faulty"]
                                                            > 0).sum())  # fmt: skip
        out.append(entry)
    return pd.DataFrame(out)
