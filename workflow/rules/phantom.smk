# Phantom + passive knee exoskeleton (W.S.B. et al.): the group's locations, trials and settings, its
# four stages (recordings and chain; engine and checks; report and figures; W.S.B. et al.'s
# numbers and significance statements reproduced, and the twin against the chain) and its
# targets.
# Scheduling: the phantom chain (calibrate → twin → acquire → filter → angles → strides →
# dynamics → kinetics, then the engine and its figure) is the workflow's longest path. Every rule's
# `priority` is its remaining critical path in 5 s levels (`python -m exobench.plumbing.bench
# priorities`, docs/running.md): a free core takes the ready job with the longest road ahead.

import re

from exobench import phantom as phantom_pkg
from exobench.phantom.chain.metrics import METRIC_COLUMNS as PHANTOM_METRICS
from exobench.phantom.recordings import c3d as phantom_c3d

PHANTOM_RAW = RAW / "phantom"
PHANTOM = RESULTS / "phantom"
PHANTOM_FIGURES = RESULTS / "figures" / "phantom"
# The rig's constants without the lab's label map (renaming a label changes no mechanics: only
# the acquisition reads the map, and only it reruns).
PHANTOM_RIG = {k: v for k, v in config["phantom"]["rig"].items() if k != "labels"}
# W.S.B. et al.'s steps (calibration, reproduction table, their medians in the discrepancy figure):
# with the twin by default (auto), with a lab's files only when the config asks for them (true).
SEED000_CHOICE = config["phantom"]["compare_seed000"]
PHANTOM_SEED000 = SYNTHETIC if SEED000_CHOICE == "auto" else bool(SEED000_CHOICE)
# TWIN_GUARD: the twins refuse to overwrite recordings they did not write, checked when the main
# run builds its DAG. A job process (each cluster or group job parses this file too) only runs
# what the main run planned, and may start while a twin job is still writing its files and has
# not yet written its stamp: it does not check again (the cluster run failed on that race).


def phantom_trials():
    """Trials to analyse: the twin's (synthetic) or the manifest's (files)."""
    if SYNTHETIC:
        names = phantom_pkg.twin_trial_names(config)
        if workflow.is_main_process:  # the main run only: see TWIN_GUARD
            stamp.check_writable(PHANTOM_RAW, phantom_pkg.twin_files(names))
        return names
    manifest = PHANTOM_RAW / "manifest.csv"
    return (
        list(phantom_c3d.read_manifest(manifest)["trial"]) if manifest.exists() else []
    )


# Every trial of the run (the twin writes them all) and those analysed: phantom.exclude_trials
# leaves trials out, and the verdict names them with their reasons.
PHANTOM_ALL_TRIALS = runner.at_dag_build(phantom_trials)
PHANTOM_TRIALS = runner.at_dag_build(
    config_checks.kept_trials, config, "phantom", PHANTOM_ALL_TRIALS
)


def phantom_recording(wildcards):
    """The C3D file of one trial: the twin's name for it, or the manifest's ``file``."""
    if SYNTHETIC:
        return PHANTOM_RAW / f"{wildcards.trial}.c3d"
    rows = phantom_c3d.read_manifest(PHANTOM_RAW / "manifest.csv").set_index("trial")
    return PHANTOM_RAW / rows.loc[wildcards.trial, "file"]


# The trial wildcard matches the run's trials only (a name is never read as another's prefix).
PHANTOM_TRIAL_PATTERN = "|".join(map(re.escape, PHANTOM_TRIALS)) or "(?!)"


def phantom_trial_files(folder, suffix=""):
    """One Parquet file per trial under ``PHANTOM/folder``."""
    return phantom_trial_files_in(PHANTOM / folder, suffix)


def phantom_trial_files_in(folder, suffix=""):
    """One Parquet file per trial under ``folder``."""
    return expand(folder / f"{{trial}}{suffix}.parquet", trial=PHANTOM_TRIALS)


def reported_trial(folder, caption):
    """A trial's Parquet file under ``PHANTOM/folder``, in the report (its table and trial as
    labels)."""
    section = "Strides and quality control"
    labels = {"table": folder, "trial": "{trial}"}
    return in_report(
        PHANTOM / folder / "{trial}.parquet", "phantom", caption, section, **labels
    )


# Every trial's files of each output of the per-trial chain (rule phantom_chain), by output.
PHANTOM_CHAIN = {
    "markers": phantom_trial_files("acquired", "_markers"),
    "analog": phantom_trial_files("acquired", "_analog"),
    "events": phantom_trial_files("acquired", "_events"),
    "filtered_markers": phantom_trial_files("filtered", "_markers"),
    "filtered_analog": phantom_trial_files("filtered", "_analog"),
    "angles": phantom_trial_files("angles"),
    "strides": phantom_trial_files("strides"),
    "qc": phantom_trial_files("qc"),
    "moments": phantom_trial_files("moments"),
    "kinetics": phantom_trial_files("kinetics"),
}
# What a reader of the kinetics contract table takes (exobench.phantom.chain.kinetics.read): the
# power stage's own file and the earlier stages' it joins.
PHANTOM_KINETICS = {
    "kinetics": PHANTOM_CHAIN["kinetics"],
    "angles": PHANTOM_CHAIN["angles"],
    "moments": PHANTOM_CHAIN["moments"],
    "filtered": PHANTOM_CHAIN["filtered_analog"],
}


# The protocol keys the calibration's metrics read (the strides it simulates are its own block's,
# so the recordings' length does not rerun it).
CALIBRATION_PROTOCOL = (
    "stride_time_s",
    "clutch_on_pct",
    "clutch_off_pct",
    "work_window_s",
    "min_spring_force_N",
)


# W.S.B. et al.'s figures 5–11, in order (the phantom_figures rule draws each from
# exobench.phantom.report.plots.FIGURES).
PHANTOM_PAPER_FIGURES = [
    "fig05_kinematics",
    "fig06_kinetics",
    "fig07_assistance",
    "fig08_power_by_spring",
    "fig09_power_by_component",
    "fig10_work",
    "fig11_relative_work",
]


include: "phantom_chain.smk"
include: "phantom_engine.smk"
include: "phantom_report.smk"
include: "phantom_reproduction.smk"
include: "phantom_targets.smk"
