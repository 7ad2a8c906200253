"""Library of correction terms for the phantom recordings: what the engine may propose when its
registry leaves structure unexplained.

Each term is built from what the recording holds, without a physical story behind it:
- per analog channel: a gain on each ankle load cell (each on its own), an offset and a drift in
  trial time of the vertical ankle force (single cells' offsets and drifts add, so a recording
  cannot tell which cell has them), a drift of the spring load cell (its gain and offset are
  registry effects);
- a scale on each nominal rig constant the forward model uses: the spring rate the manifest
  states, the spring's moment arm r·T/t (pulley radius and chain ratio enter only as their
  product, up to the tensioner), the tensioner's stiffness, each segment's mass and inertia (the
  inverse dynamics is linear in them: the moments table carries each segment's part);
- a term quadratic in the spring's stretch (its force-stretch law is not linear);
- rate terms of the phantom's own knee (Coulomb, viscous, quadratic): a moment the inverse
  dynamics adds to the exoskeleton's, in the engaged window and in the swing alike.
A sensor term acts on the recorded (filtered) channels; a knee term is a physical moment and
passes through the chain's filter like the registry's predictions; a scale acts on the chain.
"""

from __future__ import annotations

import numpy as np

from exobench.phantom.model.effects import CELLS, MOMENT_WINDOWS, mechanical, solved, with_recorded
from exobench.selection import Data, Effect, Parameter


def _on_moments(data: Data, contribution) -> dict[str, np.ndarray]:
    """``contribution(prefix)`` for each knee-moment window, keyed by its observable."""
    return {obs: contribution(prefix) for obs, prefix in MOMENT_WINDOWS.items()}


def cell_gain(cell: str, name: str):
    """An ankle load cell reading g × its force: the inverse dynamics then takes
    (1 − 1/g)·F_cell,rec more vertical force, M_rec = M + (∂M/∂F_y)·(1 − 1/g)·F_cell,rec."""

    def transform(state, values, data):
        share = 1.0 - 1.0 / values[name]
        return with_recorded(state, _on_moments(data, lambda w: share * data.arrays[
            f"{w}moment_per_ankle_force_m"] * data.arrays[f"{w}{cell}"]))  # fmt: skip

    return transform


def ankle_offset(state, values, data):
    """The vertical ankle force read o too high: M_rec = M + (∂M/∂F_y)·o."""
    offset = values["ankle_offset_N"]
    return with_recorded(state, _on_moments(
        data, lambda w: offset * data.arrays[f"{w}moment_per_ankle_force_m"]))  # fmt: skip


def ankle_drift(state, values, data):
    """The vertical ankle force drifting by ḃ·t over the trial: M_rec = M + (∂M/∂F_y)·ḃ·t."""
    rate = values["ankle_drift_N_per_s"]
    return with_recorded(state, _on_moments(data, lambda w: rate * data.arrays[
        f"{w}moment_per_ankle_force_m"] * data.arrays[f"{w}time_s"]))  # fmt: skip


def spring_drift(state, values, data):
    """LC_SPRING drifting by ḃ·t over the trial."""
    return with_recorded(state, {"force": values["spring_drift_N_per_s"] * data.arrays["time_s"]})


def segment_scale(segment: str, name: str):
    """A segment whose mass and inertia are s × the rig's: the inverse dynamics, which uses the
    rig's, then misses (s − 1) × that segment's part of the moment, M_rec = M − (s − 1)·P."""

    def transform(state, values, data):
        excess = values[name] - 1.0
        return with_recorded(state, _on_moments(
            data, lambda w: -excess * data.arrays[f"{w}{segment}_part_Nm"]))  # fmt: skip

    return transform


def knee_rate(law, name: str):
    """A moment of the phantom's own knee, law(θ̇)·coefficient, added to the exoskeleton's in
    every window (before the chain's filter, like any physical moment)."""

    def transform(state, values, data):
        state = solved(state, data)
        dt = data.constants["dt_s"]
        out = dict(state)
        for obs, theta in (("moment", state["theta"]), ("swing", data.arrays["swing_phantom_rad"])):
            rate = np.gradient(theta, dt, axis=1)
            out[obs] = state[obs] + values[name] * law(rate)
        return out

    return transform


def _gain(name: str, meaning: str) -> Parameter:
    return Parameter(name, "1", 0.5, 2.0, meaning, start=1.0, neutral=1.0,
                     detectable=(1.03, 1.10), negligible=1.01)  # fmt: skip


def _scale(name: str, meaning: str, negligible: float, low=0.3, high=3.0) -> Parameter:
    return Parameter(name, "1", low, high, meaning, start=1.0, neutral=1.0,
                     detectable=(1.1, 1.4), negligible=negligible)  # fmt: skip


MOMENTS = tuple(MOMENT_WINDOWS)
LIBRARY: dict[str, Effect] = {
    **{
        f"ankle_cell_{i}_gain": Effect(
            f"ankle_cell_{i}_gain",
            f"ankle load cell LC_ANKLE_{i} reads at a gain other than its calibration",
            (_gain(f"gain_cell_{i}", f"LC_ANKLE_{i} recorded over true force"),),
            MOMENTS,
            cell_gain(cell, f"gain_cell_{i}"),
        )
        for i, cell in enumerate(CELLS, start=1)
    },
    "ankle_force_offset": Effect(
        "ankle_force_offset",
        "the ankle load cells read with an offset (on their sum: which cell, the recording "
        "cannot tell)",
        (Parameter("ankle_offset_N", "N", -50.0, 50.0, "offset of the vertical ankle force",
                   log=False, start=0.0, detectable=(1.0, 10.0), negligible=0.5),),
        MOMENTS,
        ankle_offset,
    ),
    "ankle_force_drift": Effect(
        "ankle_force_drift",
        "the ankle load cells drift over the trial (on their sum)",
        (Parameter("ankle_drift_N_per_s", "N/s", -5.0, 5.0, "drift of the vertical ankle force",
                   log=False, start=0.0, detectable=(0.05, 0.5), negligible=0.01),),
        MOMENTS,
        ankle_drift,
    ),
    "spring_cell_drift": Effect(
        "spring_cell_drift",
        "the spring load cell LC_SPRING drifts over the trial",
        (Parameter("spring_drift_N_per_s", "N/s", -5.0, 5.0, "drift of LC_SPRING", log=False,
                   start=0.0, detectable=(0.05, 0.5), negligible=0.01),),
        ("force",),
        spring_drift,
    ),
    "spring_rate_scale": Effect(
        "spring_rate_scale",
        "the spring's rate is not the one the manifest states",
        (_scale("spring_scale", "real over stated spring rate", 1.02),),
        ("moment", "exo", "spring", "force"),
        mechanical(spring_scale=1.0),
        early=True,
    ),
    "moment_arm_scale": Effect(
        "moment_arm_scale",
        "the spring's moment arm r·T/t is not the nominal one (pulley radius or chain ratio: "
        "the recording cannot tell which)",
        (_scale("arm_scale", "real over nominal r·T/t", 1.02, 0.5, 2.0),),
        ("moment", "exo", "spring", "force"),
        mechanical(arm_scale=1.0),
        early=True,
    ),
    # softening is bounded where the spring's tangent rate k·(1 + 2a·x) stays positive over a
    # stretch of up to 6 cm (0.35 rad through r·T/t): beyond, the chain has no unique solution
    "spring_quadratic": Effect(
        "spring_quadratic",
        "the spring's force is not linear in its stretch (it stiffens or softens as it "
        "stretches)",
        (Parameter("spring_quadratic_per_m", "1/m", -8.0, 60.0,
                   "relative change of the spring's rate per metre of stretch, a in "
                   "F = F₀ + k·x·(1 + a·x)", log=False, start=0.0, detectable=(5.0, 20.0),
                   negligible=1.0),),
        ("moment", "exo", "spring", "force"),
        mechanical(spring_quadratic_per_m=0.0),
        early=True,
    ),
    "tensioner_scale": Effect(
        "tensioner_scale",
        "the tensioner spring acts at other than its nominal stiffness",
        (_scale("tensioner_scale", "real over nominal tensioner stiffness", 1.5, 0.01, 100.0),),
        ("moment", "exo", "spring", "force"),
        mechanical(tensioner_scale=1.0),
        early=True,
    ),
    **{
        f"{segment}_inertia_scale": Effect(
            f"{segment}_inertia_scale",
            f"the {segment}'s mass and inertia are not the rig's (the inverse dynamics uses the "
            "rig's)",
            (_scale(f"{segment}_scale", f"real over nominal {segment} mass and inertia", 1.03),),
            MOMENTS,
            segment_scale(segment, f"{segment}_scale"),
        )
        for segment in ("thigh", "shank")
    },
    "knee_coulomb": Effect(
        "knee_coulomb",
        "the phantom's own knee has Coulomb friction",
        (Parameter("knee_coulomb_Nm", "N·m", 1e-4, 5.0, "friction moment of the phantom knee",
                   start=0.05, detectable=(0.05, 0.5), negligible=0.01),),
        MOMENTS,
        knee_rate(np.sign, "knee_coulomb_Nm"),
    ),
    "knee_viscous": Effect(
        "knee_viscous",
        "the phantom's own knee has viscous damping",
        (Parameter("knee_viscous_Nms_per_rad", "N·m·s/rad", 1e-4, 5.0,
                   "damping of the phantom knee", start=0.02, detectable=(0.02, 0.2),
                   negligible=0.005),),
        MOMENTS,
        knee_rate(lambda rate: rate, "knee_viscous_Nms_per_rad"),
    ),
    "knee_quadratic": Effect(
        "knee_quadratic",
        "the phantom's own knee has a loss quadratic in its rate",
        (Parameter("knee_quadratic_Nms2_per_rad2", "N·m·s²/rad²", 1e-5, 1.0,
                   "quadratic damping of the phantom knee", start=0.005,
                   detectable=(0.005, 0.05), negligible=0.001),),
        MOMENTS,
        knee_rate(lambda rate: np.abs(rate) * rate, "knee_quadratic_Nms2_per_rad2"),
    ),
}  # fmt: skip
