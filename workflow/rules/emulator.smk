# Knee exoskeleton emulator: energy stored per step in an emulated clutched spring (Heer,
# docs/rig.md §3). Recordings come from the twin (acquisition: synthetic) or any lab (files).
# This file: the group's locations, trials and figures; its stages: recordings and chain
# (emulator_chain.smk), engine and verdict (emulator_engine.smk), report and figures
# (emulator_report.smk).

import re

from exobench import emulator as emulator_pkg
from exobench.emulator.recordings import acquire as emulator_acquire

EMULATOR_RAW = RAW / "emulator"
EMULATOR = RESULTS / "emulator"
EMULATOR_FIGURES = RESULTS / "figures" / "emulator"


def emulator_manifest():
    """The emulator manifest of recordings (files), or None before the twin wrote one."""
    path = EMULATOR_RAW / "manifest.csv"
    return emulator_acquire.read_manifest(path) if path.exists() else None


def emulator_trials():
    """Trials to analyse: the twin's (synthetic) or the manifest's (files)."""
    if SYNTHETIC:
        names = emulator_pkg.twin_trial_names(config)
        if workflow.is_main_process:  # the main run only: see TWIN_GUARD
            stamp.check_writable(EMULATOR_RAW, emulator_pkg.twin_files(names))
        return names
    manifest = emulator_manifest()
    return [] if manifest is None else list(manifest["trial"])


# Every trial of the run (the twin writes them all) and those analysed: emulator.exclude_trials
# leaves trials out, and the verdict names them with their reasons.
EMULATOR_ALL_TRIALS = runner.at_dag_build(emulator_trials)
EMULATOR_TRIALS = runner.at_dag_build(
    config_checks.kept_trials, config, "emulator", EMULATOR_ALL_TRIALS
)


def emulator_trial_files(kind, suffix="parquet"):
    """One file per trial under ``EMULATOR/kind``."""
    return expand(EMULATOR / kind / f"{{trial}}.{suffix}", trial=EMULATOR_TRIALS)


# Every trial's files of each output of the per-trial rule emulator_trial, by output.
EMULATOR_CHAIN = {
    "samples": emulator_trial_files("samples"),
    "steps": emulator_trial_files("steps"),
    "qc": emulator_trial_files("qc", "json"),
}
# The trial wildcard matches the run's trials only (a name is never read as another's prefix).
EMULATOR_TRIAL_PATTERN = "|".join(map(re.escape, EMULATOR_TRIALS)) or "(?!)"


def emulator_recording(wildcards):
    """Brace, motion-capture and (when present) truth file of one trial, as the manifest (or
    the twin) names them; the twin's truth file is an input so that the heel-strike check
    reruns when it changes."""
    trial = wildcards.trial
    if SYNTHETIC:
        brace, mocap = f"{trial}_brace.csv", f"{trial}_mocap.csv"
    else:
        row = emulator_manifest().set_index("trial").loc[trial]
        brace, mocap = row["file"], row["mocap_file"]
    truth = EMULATOR_RAW / "truth" / f"{trial}.json"
    return {
        "brace": EMULATOR_RAW / brace,
        "mocap": EMULATOR_RAW / mocap,
        "truth": [truth] if SYNTHETIC or truth.is_file() else [],
    }


# The group's figures (the emulator_figures rule draws each, a caption beside it).
EMULATOR_FIGURE_NAMES = [
    "energy_per_step",
    "angle_torque",
    "encoder_vs_mocap",
    "activity_vs_table61",
]


include: "emulator_chain.smk"
include: "emulator_engine.smk"
include: "emulator_report.smk"
