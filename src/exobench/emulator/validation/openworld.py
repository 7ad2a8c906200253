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


def draw_case(name: str, index: int, rng: np.random.Generator, durations: Sequence[float]) -> dict:
    """A case of an arm (:func:`exobench.selection.openworld.draw_violations`) and its recording
    length per trial."""
    violations, fault = openworld.draw_violations(ARM, name, index, rng)
    return {"violations": violations, "fault": fault, "duration_s": float(rng.choice(durations))}


def settings(block: Mapping, duration_s: float) -> dict:
    """The emulator block the analysis reads, with the case's recording length."""
    cfg = copy.deepcopy(dict(block))
    cfg["protocol"] = {**cfg["protocol"], "duration_s": duration_s}
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


def analysed(case: Mapping, block: Mapping, engine: Mapping,
             seed: int) -> tuple[dict, pd.DataFrame]:  # fmt: skip
    """The engine's report and the direct checks on the generator's recordings of a case (or a
    refusal, in the report's shape)."""
    cfg = settings(block, case["duration_s"])
    protocol = cfg["validation"]
    with tempfile.TemporaryDirectory() as tmp:
        manifest = labsim.write_study(
            Path(tmp), speeds_m_per_s=protocol["speeds_m_per_s"],
            stiffnesses_Nm_per_rad=protocol["stiffnesses_Nm_per_rad"],
            duration_s=case["duration_s"], violations=dict(case["violations"]), seed=seed,
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
    case = draw_case(name, index, np.random.default_rng([case_seed, 31]), durations)
    report, table = analysed(case, block, engine, case_seed)
    return case, report, table, case_seed


def case_rows(name: str, index: int, seed: int, case: Mapping, report: Mapping,
              table: pd.DataFrame) -> list[dict]:  # fmt: skip
    """The case's rows (:func:`exobench.selection.openworld.case_rows`)."""
    return openworld.case_rows(ARM, name, index, seed, case["violations"], case["fault"],
                               report, table, {"duration_s": case["duration_s"]})  # fmt: skip
