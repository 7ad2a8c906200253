"""Model discrepancy against the medians seed 000 reports (no recordings, only numbers).

Units are the reported springs; observables are the stance metrics each spring reports. With
k_θ from eq. (2.2), the series predictions are: exoskeleton stiffness (1/k_θ + 1/k_frame)⁻¹,
phantom stiffness (1/k_exo + 1/k_interface)⁻¹, peak moment = phantom stiffness × phantom stance
flexion, exoskeleton stance flexion = peak moment / exoskeleton stiffness. The rigid theory has
both compliances at zero and a phantom that follows its programme: the same stance flexion
for every spring. Drive compliance lets the hexapod's ankle yield to the load: the knee then
loses M·(D / (l₁·l₂·sin θ))² / k_drive of flexion (virtual work of the two-link leg with the
ankle on the vertical through the hip; D the hip–ankle distance). Metric residuals are relative
(log ratio) over a 5 % scale; the phantom flexion's are absolute over the 0.1° of its rounding.
With two springs nothing can be held out, so the engine selects by AIC and gives Wald intervals.
"""

from __future__ import annotations

from collections.abc import Mapping

import numpy as np
import pandas as pd

from exobench import selection
from exobench.phantom.chain.metrics import STANCE_METRICS
from exobench.phantom.model import effects
from exobench.phantom.rig import Rig

FLEXION = "phantom_stance_flexion_deg"
RELATIVE_SCALE = 0.05
FLEXION_SCALE_DEG = 0.1
UNITS = {**{m: "log" for m in STANCE_METRICS}, FLEXION: "deg"}
NAMES = {
    "peak_moment_Nm": "peak knee moment",
    "phantom_stiffness_Nm_per_rad": "phantom stiffness",
    "exo_stiffness_Nm_per_rad": "exoskeleton stiffness",
    "exo_stance_flexion_deg": "exoskeleton stance flexion",
    FLEXION: "phantom stance flexion",
}


def medians(reported: pd.DataFrame) -> pd.DataFrame:
    """Reported medians per spring (rows) for the phantom flexion and the predicted metrics."""
    rows = reported.dropna(subset=["spring_stiffness_N_per_m"])
    table = rows.pivot(index="spring_stiffness_N_per_m", columns="metric", values="value")
    return table[[FLEXION, *STANCE_METRICS]].dropna()


def drive_compliance_rad_per_Nm(flexion_rad, k_drive_N_per_m: float, rig: Rig):
    """Knee-equivalent compliance of a vertical ankle drive: (D / (l₁·l₂·sin θ))² / k_drive."""
    l1, l2 = rig.thigh_length_m, rig.shank_length_m
    d = np.sqrt(l1**2 + l2**2 + 2 * l1 * l2 * np.cos(flexion_rad))
    return (d / (l1 * l2 * np.sin(flexion_rad))) ** 2 / k_drive_N_per_m


def _series(state: dict, data: selection.Data) -> dict:
    """Series-stiffness predictions of the stance metrics for the state's compliances."""
    k_theta = data.arrays["k_theta_Nm_per_rad"]
    exo = 1.0 / (1.0 / k_theta + 1.0 / state["k_frame_Nm_per_rad"])
    phantom = 1.0 / (1.0 / exo + 1.0 / state["k_interface_Nm_per_rad"])
    flexion = np.deg2rad(data.arrays[FLEXION])
    moment = phantom * flexion
    predicted_flexion = np.full_like(flexion, np.mean(flexion))
    if np.isfinite(state["k_drive_N_per_m"]):
        loss = drive_compliance_rad_per_Nm(flexion, state["k_drive_N_per_m"], data.constants["rig"])
        loss = loss * moment
        programme = np.mean(flexion + loss)  # the same programme for every spring
        predicted_flexion = programme - loss
    return {
        **state,
        "peak_moment_Nm": np.log(moment),
        "phantom_stiffness_Nm_per_rad": np.log(phantom),
        "exo_stiffness_Nm_per_rad": np.log(exo),
        "exo_stance_flexion_deg": np.log(np.rad2deg(moment / exo)),
        FLEXION: np.rad2deg(predicted_flexion),
    }


def baseline(data: selection.Data) -> dict:
    """Rigid theory: rigid interface and frame, a phantom that follows its programme."""
    rigid = {"k_interface_Nm_per_rad": np.inf, "k_frame_Nm_per_rad": np.inf,
             "k_drive_N_per_m": np.inf}  # fmt: skip
    return _series(rigid, data)


def _compliance(name: str):
    def transform(state, values, data):
        return _series({**state, name: values[name]}, data)

    return transform


P = selection.Parameter
REGISTRY = {
    "interface_compliance": selection.Effect(
        "interface_compliance",
        effects.REGISTRY["interface_compliance"].description,
        effects.REGISTRY["interface_compliance"].parameters,
        ("peak_moment_Nm", "phantom_stiffness_Nm_per_rad", "exo_stance_flexion_deg"),
        _compliance("k_interface_Nm_per_rad"),
    ),
    "frame_compliance": selection.Effect(
        "frame_compliance",
        effects.REGISTRY["frame_compliance"].description,
        effects.REGISTRY["frame_compliance"].parameters,
        tuple(STANCE_METRICS),
        _compliance("k_frame_Nm_per_rad"),
    ),
    "drive_compliance": selection.Effect(
        "drive_compliance",
        "a compliant ankle drive (the phantom does not follow its programme under load)",
        (
            P(
                "k_drive_N_per_m",
                "N/m",
                1e3,
                1e9,
                "vertical stiffness of hexapod, fixture and foot",
                start=3e5,
            ),
        ),
        (FLEXION,),
        _compliance("k_drive_N_per_m"),
    ),
}


def problem() -> selection.Problem:
    """The reported-medians problem for the shared engine."""
    return selection.Problem(
        group="phantom_reported",
        registry=REGISTRY,
        baseline=baseline,
        measured={m: f"measured_{m}" for m in UNITS},
        units=UNITS,
        baseline_name="rigid theory (seed 000 eqs. 2.1–2.2)",
        names=NAMES,
    )


def observations(reported: pd.DataFrame, rig: Rig) -> tuple[selection.Data, dict]:
    """Springs as units, the reported medians as measurements, and their scales."""
    table = medians(reported)
    springs = table.index.to_numpy(float)
    arrays = {
        FLEXION: table[FLEXION].to_numpy(float),
        "k_theta_Nm_per_rad": rig.joint_stiffness(springs),
        **{f"measured_{m}": np.log(table[m].to_numpy(float)) for m in STANCE_METRICS},
        f"measured_{FLEXION}": table[FLEXION].to_numpy(float),
    }
    scales = {**{m: RELATIVE_SCALE for m in STANCE_METRICS}, FLEXION: FLEXION_SCALE_DEG}
    data = selection.Data(arrays, np.zeros(springs.size, int), springs, {"rig": rig})
    return data, scales


def analyse(reported: pd.DataFrame, rig: Rig, settings: Mapping, source: str) -> dict:
    """Discrepancy report for the reported medians (shared engine and schema)."""
    data, scales = observations(reported, rig)
    engine = selection.Settings.from_config(settings["engine"], settings["seed"])
    report = selection.analyse(problem(), data, scales, engine, source)
    values = {k: v for e in report["effects_found"] + report["tentative"]
              for k, v in e["parameters"].items()}  # fmt: skip
    predicted = selection.predict(problem(), data, report["selected"], values)
    report["predictions"] = [
        {
            "spring_stiffness_N_per_m": float(spring),
            **{
                m: float(np.exp(predicted[m][i]) if UNITS[m] == "log" else predicted[m][i])
                for m in UNITS
            },
        }
        for i, spring in enumerate(data.order)
    ]
    return report
