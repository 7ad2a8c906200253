# Paths shared by every rule group. Locations come from the config so that
# --config raw_dir=... results_dir=... moves recordings and results anywhere.
from pathlib import Path

from exobench import emulator as emulator_pkg
from exobench import runner
from exobench.emulator import acquire as emulator_acquire
from exobench.emulator import twin as emulator_twin
from exobench.phantom import c3d as phantom_c3d
from exobench.phantom import twin as phantom_twin
from exobench.phantom import twin_trial_names
from exobench.phantom.metrics import METRIC_COLUMNS as PHANTOM_METRICS

RAW = Path(config["raw_dir"])
RESULTS = Path(config["results_dir"])
REFERENCE = Path(config["reference_dir"])


def logfile(rule_name):
    return RESULTS / "logs" / f"{rule_name}.log"


def benchfile(rule_name):
    return RESULTS / "benchmarks" / f"{rule_name}.tsv"


# Phantom (seed 000) locations and trials.

PHANTOM_RAW = RAW / "phantom"
PHANTOM = RESULTS / "phantom"
PHANTOM_FIGURES = RESULTS / "figures" / "phantom"
SYNTHETIC = config["acquisition"] == "synthetic"


def phantom_trials():
    """Trials to analyse: the twin's (synthetic) or the manifest's (files)."""
    if SYNTHETIC:
        names = twin_trial_names(config)
        phantom_twin.check_writable(PHANTOM_RAW, names)
        return names
    manifest = PHANTOM_RAW / "manifest.csv"
    return (
        list(phantom_c3d.read_manifest(manifest)["trial"]) if manifest.exists() else []
    )


PHANTOM_TRIALS = runner.at_dag_build(phantom_trials)


# Emulator (seed 002) locations and trials.

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
        emulator_twin.check_writable(EMULATOR_RAW, names)
        return names
    manifest = emulator_manifest()
    return [] if manifest is None else list(manifest["trial"])


EMULATOR_TRIALS = runner.at_dag_build(emulator_trials)


def emulator_recording(wildcards):
    """Brace and motion-capture files of one trial, as the manifest (or the twin) names them."""
    if SYNTHETIC:
        return {
            "brace": EMULATOR_RAW / f"{wildcards.trial}_brace.csv",
            "mocap": EMULATOR_RAW / f"{wildcards.trial}_mocap.csv",
        }
    row = emulator_manifest().set_index("trial").loc[wildcards.trial]
    return {
        "brace": EMULATOR_RAW / row["file"],
        "mocap": EMULATOR_RAW / row["mocap_file"],
    }
