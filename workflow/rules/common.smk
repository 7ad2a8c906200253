# Paths shared by every rule group. Locations come from the config so that
# --config raw_dir=... results_dir=... moves recordings and results anywhere.
from pathlib import Path

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


PHANTOM_TRIALS = phantom_trials()
