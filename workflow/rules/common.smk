# Paths shared by every rule group. Locations come from the config so that
# --config raw_dir=... results_dir=... moves recordings and results anywhere.
from pathlib import Path

RAW = Path(config["raw_dir"])
RESULTS = Path(config["results_dir"])
REFERENCE = Path(config["reference_dir"])


def logfile(rule_name):
    return RESULTS / "logs" / f"{rule_name}.log"


def benchfile(rule_name):
    return RESULTS / "benchmarks" / f"{rule_name}.tsv"
