"""The recordings of a validation case: a workflow config for the twin with exactly the hidden
effects, the twin's files, and the tables the workflow's own analysis stages make of any
recordings (the twin's or the independent generator's)."""

from __future__ import annotations

import copy
from collections.abc import Mapping
from pathlib import Path

import numpy as np

from exobench import phantom
from exobench.phantom.chain import metrics, trial
from exobench.phantom.model import effects
from exobench.phantom.recordings import c3d
from exobench.phantom.rig import ANALOG_RATE_HZ, Rig
from exobench.phantom.twin import twin

SPRINGS_N_PER_M = (3400.0, 9200.0, 21700.0)


def twin_config(base: Mapping, hidden: Mapping, strides: int, seed: int) -> dict:
    """Workflow config whose phantom twin has exactly the hidden effects (plus sensor noise)."""
    config = copy.deepcopy(dict(base))
    config["seed"] = int(seed)
    block = config["phantom"]
    block["protocol"].update(
        strides=int(strides) + 2,
        ramp_strides=1,
        springs_N_per_m=list(SPRINGS_N_PER_M),
        test_order_N_per_m=list(SPRINGS_N_PER_M),
    )
    for name, entry in block["twin"]["effects"].items():
        if name in effects.REGISTRY or name in ("drive_compliance", "clutch_miss"):
            entry["enabled"] = False
    for name, values in hidden.items():
        block["twin"]["effects"][name] = {"enabled": True, **values}
    return config


def write(folder: Path, config: Mapping, mean_cycle_deg: np.ndarray, rig: Rig) -> Path:
    """Write the twin's recordings of a config (RIG.md files only) and return the manifest."""
    settings = phantom.settings(config)
    trials = twin.simulate_trials(mean_cycle_deg, rig, settings, {})
    twin.write_recordings(
        trials, folder, {"rule": "validation"}, int(settings["protocol"]["ramp_strides"])
    )
    return folder / "manifest.csv"


def chain_tables(manifest_path: Path, config: Mapping, swing_fraction: float, rig: Rig,
                 labels: Mapping[str, str] | None = None):  # fmt: skip
    """Per trial, the tables the workflow's own analysis stages make of its recordings (the
    recordings screened for glitches as the acquisition rule screens them; ``labels``: the
    lab's label map): trial, spring, kinetics, strides, angles, metrics and the glitch events."""
    settings = phantom.settings(config)
    protocol = settings["protocol"]
    chain = {"chain": settings["chain"], "stride_time_s": protocol["stride_time_s"],
             "min_spring_force_N": protocol["min_spring_force_N"]}  # fmt: skip
    parts = []
    for _, row in c3d.read_manifest(manifest_path).iterrows():
        path = manifest_path.parent / row["file"]
        out = trial.run(path, row, chain, swing_fraction, rig, labels)
        spring = float(row["spring_stiffness_N_per_m"])
        parts.append({
            "trial": row["trial"], "spring": spring, "kinetics": out.kinetics,
            "strides": out.strides, "angles": out.angles, "events": out.events,
            "metrics": metrics.metrics_table(row["trial"], spring, out.strides, out.kinetics,
                                             1.0 / ANALOG_RATE_HZ, protocol,
                                             settings["statistics"]["slope_validity"]),
        })  # fmt: skip
    return parts


def engine_parts(parts) -> list[tuple]:
    """(trial, spring, kinetics, strides) of every trial: what the discrepancy engine reads."""
    return [(p["trial"], p["spring"], p["kinetics"], p["strides"]) for p in parts]
