"""Validation on recordings the project's twin did not make: the open-world and combined arms
(:mod:`exobench.selection.openworld`, the scoring both groups share).

The recordings come from :mod:`exobench.phantom.validation.labsim`, a generator written from the rig
contract, the assumption table's law lines (docs/assumptions.md) and the physics alone, apart from
the twin and the engine. Every relaxation of the phantom's table that is not a registry effect
(a term of the engine's library, or a row only a direct check sees) is violated in turn beside
the interface compliance every real rig has (the arm's kept effect) and, half the time, one more
registry effect; the combined arm draws two to four registry effects. The files are read back
through the analysis chain as a lab's, the direct checks and the engine report (the rows that
must hold between trials are checked by the report's parameter stability, its rows joined to the
direct checks'), and each case is scored against the truth.
"""

from __future__ import annotations

import tempfile
from collections.abc import Mapping, Sequence
from pathlib import Path

import numpy as np
import pandas as pd

from exobench import phantom
from exobench.errors import InputError
from exobench.phantom.model import assumptions, checks, discrepancy
from exobench.phantom.rig import Rig
from exobench.phantom.validation import labsim, recordings
from exobench.selection import checks as direct_checks
from exobench.selection import openworld

ARM = openworld.Arm(
    relaxations=assumptions.relaxations(),
    registry=assumptions.registry_terms(),
    kept="interface.elastic",
    named=checks.named,
    violated=direct_checks.violated,
)


def draw_case(arm: str, index: int, rng: np.random.Generator, strides_choices) -> dict:
    """A case of an arm (:func:`exobench.selection.openworld.draw_violations`) and its strides
    per trial."""
    strides = int(rng.choice(strides_choices))
    violations, fault = openworld.draw_violations(ARM, arm, index, rng)
    return {"violations": violations, "fault": fault, "strides": strides}


def analysed(case: Mapping, base: Mapping, seed: int, cycle_csv: Path, swing_fraction: float,
             rig: Rig) -> tuple[dict, pd.DataFrame]:  # fmt: skip
    """The engine's report and the direct checks on the generator's recordings of a case (or a
    refusal, in the report's shape); the generator drives the phantom along the mean cycle in
    ``cycle_csv``."""
    config = recordings.twin_config(base, {}, case["strides"], seed)
    with tempfile.TemporaryDirectory() as tmp:
        manifest = labsim.write_study(
            Path(tmp), cycle_csv=Path(cycle_csv), springs_N_per_m=recordings.SPRINGS_N_PER_M,
            strides=case["strides"] + 2, ramp_strides=1, violations=dict(case["violations"]),
            seed=seed,
        )  # fmt: skip
        parts = recordings.chain_tables(manifest, config, swing_fraction, rig)
    block = phantom.settings(config)
    settings = {**block["discrepancy"], "engine": config["discrepancy"], "seed": seed}
    table = checks.checks(parts, rig, {**block["checks"], "swing_pct": settings["noise_pct"],
                                       "window_pct": settings["window_pct"]})  # fmt: skip
    try:
        data, scales = discrepancy.observations(recordings.engine_parts(parts), settings, rig,
                                                block["chain"])  # fmt: skip
    except InputError as error:
        return {"effects_found": [], "tentative": [], "unexplained": {"flag": False},
                "discovery": {"named": [], "proposed": []},
                "cause": f"refused: {error}"}, table  # fmt: skip
    report = discrepancy.analyse(data, scales, settings, source="open-world validation")
    # the rows that must hold between trials are checked by the report's parameter stability
    return report, direct_checks.with_stability(table, report)


def run_case(arm: str, index: int, base: Mapping, cycle_csv: Path, swing_fraction: float,
             rig: Rig, strides_choices: Sequence[int]):  # fmt: skip
    """Draw and analyse one case of an arm: (case, report, direct checks, seed)."""
    seed = int(base["seed"]) * 100_003 + index + (50_000 if arm == "combined" else 0)
    case = draw_case(arm, index, np.random.default_rng([seed, 29]), strides_choices)
    report, table = analysed(case, base, seed, cycle_csv, swing_fraction, rig)
    return case, report, table, seed


def case_rows(arm: str, index: int, seed: int, case: Mapping, report: Mapping,
              table: pd.DataFrame) -> list[dict]:  # fmt: skip
    """The case's rows (:func:`exobench.selection.openworld.case_rows`)."""
    return openworld.case_rows(ARM, arm, index, seed, case["violations"], case["fault"], report,
                               table, {"strides_per_trial": case["strides"]})  # fmt: skip
