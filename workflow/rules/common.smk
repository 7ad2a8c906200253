# Paths shared by every rule group. Locations come from the config so that
# --config raw_dir=... results_dir=... moves recordings and results anywhere.
from pathlib import Path

# no heavy imports here (scipy, the twins): every Snakemake call (each dry run, each cluster
# job) parses this file
from exobench import emulator as emulator_pkg
from exobench import phantom as phantom_pkg
from exobench.plumbing import codedeps, runner, stamp
from exobench.emulator.recordings import acquire as emulator_acquire
from exobench.phantom.recordings import c3d as phantom_c3d
from exobench.phantom.chain.metrics import METRIC_COLUMNS as PHANTOM_METRICS

RAW = Path(config["raw_dir"])
RESULTS = Path(config["results_dir"])
REFERENCE = Path(config["reference_dir"])


SCRIPTS = Path(workflow.basedir) / "workflow" / "scripts"


def logfile(rule_name, job="job"):
    """The rule's log: one folder per rule, one file per job."""
    return RESULTS / "logs" / rule_name / f"{job}.log"


def benchfile(rule_name, job="job"):
    """The rule's Snakemake benchmark file: one folder per rule, one file per job."""
    return RESULTS / "benchmarks" / rule_name / f"{job}.tsv"


def code(script):
    """The package modules a rule's script imports, transitively (its code inputs): editing one
    reruns exactly the rules that run it; computed at DAG build, so new modules are covered.
    """
    return codedeps.code_files(SCRIPTS / script)


def source_spec(group, twin_blocks, calibration=None):
    """Where a group's recordings come from, for the first line of its summary: the twin with
    its settings (and calibration file, relative to the summary) or the lab's manifest.
    """
    return {
        "acquisition": config["acquisition"],
        "group": group,
        "twin_blocks": twin_blocks,
        "manifest": f"<raw_dir>/{group}/manifest.csv",
        "calibration": calibration if SYNTHETIC else None,
        "engine": "discrepancy.json",
    }


# Phantom (W.S.B. et al.) locations and trials.

PHANTOM_RAW = RAW / "phantom"
PHANTOM = RESULTS / "phantom"
PHANTOM_FIGURES = RESULTS / "figures" / "phantom"
SYNTHETIC = config["acquisition"] == "synthetic"
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


PHANTOM_TRIALS = runner.at_dag_build(phantom_trials)


def phantom_recordings():
    """The C3D file of every trial: the twin's name for it, or the manifest's ``file``."""
    if SYNTHETIC:
        return [PHANTOM_RAW / f"{trial}.c3d" for trial in PHANTOM_TRIALS]
    manifest = PHANTOM_RAW / "manifest.csv"
    if not manifest.exists():
        return []
    rows = phantom_c3d.read_manifest(manifest).set_index("trial")
    return [PHANTOM_RAW / rows.loc[trial, "file"] for trial in PHANTOM_TRIALS]


PHANTOM_C3D = runner.at_dag_build(phantom_recordings)


def phantom_trial_files(folder, suffix=""):
    """One Parquet file per trial under ``PHANTOM/folder``."""
    return expand(PHANTOM / folder / f"{{trial}}{suffix}.parquet", trial=PHANTOM_TRIALS)


def reported_trials(folder, caption):
    """One Parquet file per trial under ``PHANTOM/folder``, each in the report (its table and
    trial as labels)."""
    paths = zip(PHANTOM_TRIALS, phantom_trial_files(folder))
    return [flag_for_report(path, caption, folder, trial) for trial, path in paths]


def flag_for_report(path, caption, table, trial):
    """One per-trial table flagged for the report (snakefmt reads a line opening with the
    report flag as a directive)."""
    labels = {"table": table, "trial": trial}
    flagged = report(
        path,
        caption=caption,
        category="Phantom",
        subcategory="Strides and quality control",
        labels=labels,
    )
    return flagged


# Emulator (Heer) locations and trials.

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
