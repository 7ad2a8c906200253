# Knee exoskeleton emulator: energy stored per step in an emulated clutched spring (Heer,
# docs/rig.md §3). Recordings come from the twin (acquisition: synthetic) or any lab (files).
# This file: the group's locations, trials and figures; its stages: recordings and chain
# (emulator_chain.smk), engine and verdict (emulator_engine.smk), report and figures
# (emulator_report.smk).

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


EMULATOR_TRIALS = runner.at_dag_build(emulator_trials)


def emulator_trial_files(kind, suffix="parquet"):
    """One file per trial under ``EMULATOR/kind``."""
    return expand(EMULATOR / kind / f"{{trial}}.{suffix}", trial=EMULATOR_TRIALS)


def emulator_recordings(wildcards):
    """Brace, motion-capture and (when present) truth files of every trial, as the manifest (or
    the twin) names them; the twin's truth files are inputs so that the heel-strike check
    reruns when they change."""
    if SYNTHETIC:
        names = {t: (f"{t}_brace.csv", f"{t}_mocap.csv") for t in EMULATOR_TRIALS}
    else:
        rows = emulator_manifest().set_index("trial")
        names = {
            t: (rows.loc[t, "file"], rows.loc[t, "mocap_file"]) for t in EMULATOR_TRIALS
        }
    truth = [EMULATOR_RAW / "truth" / f"{t}.json" for t in EMULATOR_TRIALS]
    return {
        "brace": [EMULATOR_RAW / brace for brace, _ in names.values()],
        "mocap": [EMULATOR_RAW / mocap for _, mocap in names.values()],
        "truth": [p for p in truth if SYNTHETIC or p.is_file()],
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
