"""Digital twin of the phantom rig: writes the recordings a lab would (docs/rig.md §1) plus truth.

Physics, in order: programmed knee trajectories (:mod:`trajectory`); the time-domain mechanics
of hexapod drive, phantom, interface, bars, chain and spring (:mod:`twin_mechanics`), which give
the phantom's real knee angle and the knee moment; joint-centre paths of the two-link leg with
the hip fixed and the ankle under it; ankle forces from the leg's Lagrange equations with the
exoskeleton's moment (:func:`ankle_force_N`, derived apart from the analysis's Newton–Euler in
:mod:`dynamics`, so that the analysis is tested against other equations than its own);
markers and analog channels with switchable sensor effects.
"""

from __future__ import annotations

from collections.abc import Iterable, Iterator, Mapping
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import pandas as pd

from exobench import atomic, tables
from exobench.errors import InputError
from exobench.phantom import twin_files, twin_trials
from exobench.phantom.recordings import c3d
from exobench.phantom.rig import (
    ANALOG_RATE_HZ,
    GRAVITY_M_PER_S2,
    MANIFEST_COLUMNS,
    POINT_RATE_HZ,
    REQUIRED_ANALOGS,
    SYNC_HIGH_V,
    SYNC_WIDTH_S,
    Rig,
)
from exobench.phantom.twin import trajectory, twin_mechanics
from exobench.plumbing import stamp

HIP_POSITION_M = np.array([0.0, 0.90])
JOINT_HALF_WIDTH_M = {"HIP": 0.050, "KNEE": 0.045, "ANK": 0.035}
BAR_LATERAL_M = 0.070
SPRING_LATERAL_M = 0.090
BAR_MARKERS_FROM_KNEE_M = {"PROX": 0.20, "DIST": 0.06}
SPRING_ANCHOR_FROM_KNEE_M = 0.26
SPRING_POSTERIOR_OFFSET_M = 0.03
LOAD_CELL_SHARES = np.array([0.36, 0.33, 0.31])
# Effects with the parameter each one carries; a disabled effect is rigid / absent.
MECHANICAL_EFFECTS = {
    "interface_compliance": "k_interface_Nm_per_rad",
    "interface_stiffening": "stiffening_per_rad2",
    "interface_damping": "c_interface_Nms_per_rad",
    "frame_compliance": "k_frame_Nm_per_rad",
    "frame_friction": "friction_Nm",
    "transmission_play": "play_rad",
    "clutch_timing": "delay_s",
    "drive_compliance": "k_drive_N_per_m",
}
SENSOR_EFFECTS = {
    "load_cell_offset": "offset_N",
    "load_cell_gain": "gain",
    "clock_offset": "analog_delay_s",
    "knee_marker_offset": "offset_mm",
}
EFFECT_PARAMETERS = {**MECHANICAL_EFFECTS, **SENSOR_EFFECTS}
# Effects that act only together with another one.
REQUIRES = {
    "interface_stiffening": "interface_compliance",
    "interface_damping": "interface_compliance",
}
# Time-domain states written to truth/<trial>.parquet beside the clutch and the ankle forces.
TRUTH_STATES = (
    "phantom_knee_angle_rad",
    "drive_deflection_rad",
    "exo_knee_angle_rad",
    "knee_moment_Nm",
    "interface_deflection_rad",
    "frame_deflection_rad",
    "chain_slack_rad",
    "spring_side_rotation_rad",
    "spring_force_N",
    "spring_extension_m",
)
CHAIN_PARAMETERS = (
    "k_interface_Nm_per_rad",
    "stiffening_per_rad2",
    "c_interface_Nms_per_rad",
    "k_frame_Nm_per_rad",
    "friction_Nm",
    "play_rad",
)


@dataclass(frozen=True)
class Trial:
    """One trial's recordings and truth, at 100 Hz (markers) and 1000 Hz (everything else)."""

    name: str
    spring_stiffness_N_per_m: float
    markers_mm: dict[str, np.ndarray]  # label -> (frames, 3)
    analogs: dict[str, np.ndarray]  # label -> (samples,)
    truth: pd.DataFrame
    repeat: int = 1


def effect_values(effects: Mapping, calibrated: Mapping[str, float]) -> dict[str, float]:
    """Parameters of the enabled effects; 'calibrated' takes the fitted value."""
    values = {}
    for effect, parameter in EFFECT_PARAMETERS.items():
        block = effects.get(effect, {})
        if not block.get("enabled", False):
            continue
        needed = REQUIRES.get(effect)
        if needed and not effects.get(needed, {}).get("enabled", False):
            raise InputError(
                "config", f"phantom.twin.effects.{effect}", f"'{needed}' enabled as well"
            )
        value = block[parameter]
        values[parameter] = float(calibrated[parameter] if value == "calibrated" else value)
    return values


def chain(
    rig: Rig, springs_N_per_m: np.ndarray, twin: Mapping, values: Mapping
) -> twin_mechanics.Chain:
    """Series-chain parameters for strides with the given spring stiffnesses.

    The spring is pulled r·T/t per radian of knee rotation and the tensioner is felt through the
    chain ratio squared; the taut spring side's knee stiffness k_l·(r·T/t)² − k_t·(T/t)² is
    seed 000 eq. 2.2 (whose sign for the tensioner it takes), summed here by the twin itself.
    """
    springs = np.asarray(springs_N_per_m, float)
    travel = rig.pulley_radius_m * rig.chain_ratio
    tensioner = rig.chain_ratio**2 * rig.tensioner_stiffness_Nm_per_rad
    return twin_mechanics.Chain(
        joint_stiffness_Nm_per_rad=springs * travel**2 - tensioner,
        spring_stiffness_N_per_m=springs,
        travel_m_per_rad=travel,
        pretension_N=float(twin["pretension_N"]),
        tensioner_knee_stiffness_Nm_per_rad=tensioner,
        **{key: values[key] for key in CHAIN_PARAMETERS if key in values},
    )


def clutch_level(
    strides: int, samples: int, settings: Mapping, missed: np.ndarray, delay_s: float = 0.0
) -> np.ndarray:
    """Clutch engagement per sample: 1 from on_pct + delay, smooth release ending at off_pct.

    The release follows the hexapod tilt's smooth step over ``twin.clutch_release_s``; the
    clutch_timing effect engages ``delay_s`` after the programmed instant.
    """
    protocol = settings["protocol"]
    stride_s = float(protocol["stride_time_s"])
    pct = np.arange(samples) / samples * 100.0
    release_pct = float(settings["twin"]["clutch_release_s"]) / stride_s * 100
    off = float(protocol["clutch_off_pct"])
    falling = np.clip((off - pct) / release_pct, 0.0, 1.0) if release_pct > 0 else (pct < off) * 1.0
    start = engagement_sample(samples, settings, delay_s) / samples * 100.0
    level = np.where(pct >= start, trajectory.smoothstep(falling), 0.0)
    return level[None, :] * ~missed[:, None]


def engagement_sample(samples: int, settings: Mapping, delay_s: float = 0.0) -> float:
    """The (fractional) sample of the stride at which the clutch locks: on_pct + delay."""
    protocol = settings["protocol"]
    stride_s = float(protocol["stride_time_s"])
    return (float(protocol["clutch_on_pct"]) / 100.0 + delay_s / stride_s) * samples


def leg_paths(flexion_rad: np.ndarray, rig: Rig) -> dict[str, np.ndarray]:
    """Hip, knee and ankle centres (..., 2) in m for knee flexion with the ankle under the hip."""
    l1, l2 = rig.thigh_length_m, rig.shank_length_m
    thigh = np.arctan2(l2 * np.sin(flexion_rad), l1 + l2 * np.cos(flexion_rad))
    shank = flexion_rad - thigh
    hip = np.broadcast_to(HIP_POSITION_M, (*flexion_rad.shape, 2))
    knee = hip + l1 * np.stack([np.sin(thigh), -np.cos(thigh)], -1)
    ankle = knee + l2 * np.stack([-np.sin(shank), -np.cos(shank)], -1)
    return {"hip": hip, "knee": knee, "ankle": ankle, "thigh": thigh, "shank": shank}


def ankle_force_N(thigh_rad, shank_rad, moment_Nm, dt_s: float, rig: Rig):
    """Horizontal and vertical ankle force from Lagrange's equations of the two-link leg.

    Coordinates: thigh angle α from the downward vertical (anterior +) and shank angle β from it
    (posterior +), knee flexion θ = α + β, hip fixed. With a = m₁c₁² + I₁ + m₂l₁²,
    b = m₂c₂² + I₂, c = m₂l₁c₂ and the extensor moment M doing virtual work −M·δθ:

        a·α̈ − c·cosθ·β̈ + c·sinθ·β̇² + g(m₁c₁ + m₂l₁)·sinα + M = l₁(F_x cosα + F_y sinα)
        b·β̈ − c·cosθ·α̈ + c·sinθ·α̇² + g·m₂c₂·sinβ + M = l₂(−F_x cosβ + F_y sinβ)

    solved for F = (F_x, F_y); angular rates by central differences over the samples axis.
    """
    l1, l2 = rig.thigh_length_m, rig.shank_length_m
    m1, c1, m2, c2 = rig.thigh_mass_kg, rig.thigh_com_m, rig.shank_mass_kg, rig.shank_com_m
    a = m1 * c1**2 + rig.thigh_inertia_kgm2 + m2 * l1**2
    b = m2 * c2**2 + rig.shank_inertia_kgm2
    c = m2 * l1 * c2
    alpha, beta = np.asarray(thigh_rad, float), np.asarray(shank_rad, float)
    rate_a, rate_b = np.gradient(alpha, dt_s, axis=-1), np.gradient(beta, dt_s, axis=-1)
    acc_a, acc_b = np.gradient(rate_a, dt_s, axis=-1), np.gradient(rate_b, dt_s, axis=-1)
    flexion = alpha + beta
    cos_f, sin_f = np.cos(flexion), np.sin(flexion)
    g = GRAVITY_M_PER_S2
    thigh_side = (
        a * acc_a
        - c * cos_f * acc_b
        + c * sin_f * rate_b**2
        + g * (m1 * c1 + m2 * l1) * np.sin(alpha)
        + moment_Nm
    )
    shank_side = (
        b * acc_b
        - c * cos_f * acc_a
        + c * sin_f * rate_a**2
        + g * m2 * c2 * np.sin(beta)
        + moment_Nm
    )
    det = l1 * l2 * sin_f
    horizontal = (thigh_side * l2 * np.sin(beta) - shank_side * l1 * np.sin(alpha)) / det
    vertical = (thigh_side * l2 * np.cos(beta) + shank_side * l1 * np.cos(alpha)) / det
    return horizontal, vertical


def exo_points(paths: Mapping, interface_rad: np.ndarray, extension_m: np.ndarray, twin: Mapping):
    """Sagittal positions (m) of the bar and spring markers, bars hinged at the knee centre."""
    share = float(twin["interface_thigh_share"])
    thigh = paths["thigh"] - share * interface_rad
    shank = paths["shank"] - (1.0 - share) * interface_rad
    up_thigh = np.stack([-np.sin(thigh), np.cos(thigh)], -1)  # knee → hip along the bar
    down_shank = np.stack([-np.sin(shank), -np.cos(shank)], -1)  # knee → ankle along the bar
    posterior = np.stack([-np.cos(thigh), -np.sin(thigh)], -1)
    knee = paths["knee"]
    anchor = knee + SPRING_ANCHOR_FROM_KNEE_M * up_thigh + SPRING_POSTERIOR_OFFSET_M * posterior
    length = float(twin["spring_rest_length_m"]) + extension_m
    return {
        "EX_THIGH_PROX": knee + BAR_MARKERS_FROM_KNEE_M["PROX"] * up_thigh,
        "EX_THIGH_DIST": knee + BAR_MARKERS_FROM_KNEE_M["DIST"] * up_thigh,
        "EX_SHANK_PROX": knee + BAR_MARKERS_FROM_KNEE_M["DIST"] * down_shank,
        "EX_SHANK_DIST": knee + BAR_MARKERS_FROM_KNEE_M["PROX"] * down_shank,
        "EX_SPRING_A": anchor,
        "EX_SPRING_B": anchor - length[..., None] * up_thigh,
    }


def marker_positions_mm(
    paths: Mapping, exo: Mapping, knee_offset_m: float = 0.0
) -> dict[str, np.ndarray]:
    """All twelve docs/rig.md markers in the lab frame (mm), lateral = +Z.

    The knee markers sit ``knee_offset_m`` anterior of the joint along the thigh's anterior
    normal (perpendicular to the hip–knee line in the sagittal plane).
    """
    anterior = np.stack([np.cos(paths["thigh"]), np.sin(paths["thigh"])], -1)
    centres = {
        "HIP": paths["hip"],
        "KNEE": paths["knee"] + knee_offset_m * anterior,
        "ANK": paths["ankle"],
    }
    markers = {}
    for joint, centre in centres.items():
        half = JOINT_HALF_WIDTH_M[joint]
        markers[f"PH_{joint}_MED"] = with_z(centre, -half)
        markers[f"PH_{joint}_LAT"] = with_z(centre, half)
    for label, xy in exo.items():
        markers[label] = with_z(xy, SPRING_LATERAL_M if "SPRING" in label else BAR_LATERAL_M)
    return {label: 1000.0 * xyz for label, xyz in markers.items()}


def with_z(xy: np.ndarray, z: float) -> np.ndarray:
    """Append a constant lateral coordinate to sagittal points."""
    return np.concatenate([xy, np.full((*xy.shape[:-1], 1), z)], -1)


def sync_channel(strides: int, samples: int) -> np.ndarray:
    """5 V pulse of 20 ms at the start of every programmed stride."""
    width = round(SYNC_WIDTH_S * ANALOG_RATE_HZ)
    pulse = np.zeros(samples)
    pulse[:width] = SYNC_HIGH_V
    return np.tile(pulse, strides)


def add_occlusions(markers: dict, block: Mapping, duration_s: float, rng) -> None:
    """Blank random runs of frames (NaN) in every marker: the occlusion effect."""
    if not block.get("enabled", False):
        return
    frames = next(iter(markers.values())).shape[0]
    expected = float(block["gaps_per_marker_per_min"]) * duration_s / 60.0
    for label in sorted(markers):
        for _ in range(rng.poisson(expected)):
            length = rng.integers(1, int(block["max_frames"]) + 1)
            start = rng.integers(0, frames - length)
            markers[label][start : start + length] = np.nan


def programmed_flexion(mean_cycle_deg: np.ndarray, config: Mapping) -> np.ndarray:
    """Programmed knee flexion (rad) of one trial's strides; the same for every spring."""
    protocol, twin = config["protocol"], config["twin"]
    degrees = trajectory.programmed_trials(
        mean_cycle_deg,
        int(protocol["strides"]),
        int(protocol["ramp_strides"]),
        float(twin["flexion_sd_deg"]),
        np.random.default_rng([int(config["seed"]), 0]),
    )
    return np.deg2rad(degrees)


def stride_states(
    programmed_rad, knee_offset, springs_N_per_m, missed, rig: Rig, config: Mapping, values
):
    """Clutch level and time-domain states of strides (rows) with per-stride spring stiffness.

    ``knee_offset`` is x_K of the programmed posture (:func:`twin_mechanics.knee_offset_m`).
    """
    strides, samples = programmed_rad.shape
    level = clutch_level(strides, samples, config, missed, values.get("delay_s", 0.0))
    drive = twin_mechanics.drive_compliance(knee_offset, values.get("k_drive_N_per_m", np.inf))
    state = twin_mechanics.simulate(
        programmed_rad,
        level,
        drive,
        1.0 / ANALOG_RATE_HZ,
        chain(rig, springs_N_per_m, config["twin"], values),
        engagement_sample(samples, config, values.get("delay_s", 0.0)),
    )
    return level, state


def remounted(values: Mapping, twin: Mapping, spread: Mapping, rng) -> tuple[dict, dict]:
    """One mounting: k, c_interface × e^N(0, s), pretension and marker placement + N(0, sd)."""
    out = dict(values)
    for key, sd in (("k_interface_Nm_per_rad", "interface_stiffness_log_sd"),
                    ("c_interface_Nms_per_rad", "interface_damping_log_sd")):  # fmt: skip
        if key in out:
            out[key] = out[key] * float(np.exp(rng.normal(0.0, float(spread[sd]))))
    out["offset_mm"] = out.get("offset_mm", 0.0) + rng.normal(
        0.0, float(spread["marker_placement_sd_mm"])
    )
    pretension = float(twin["pretension_N"]) + rng.normal(0.0, float(spread["pretension_sd_N"]))
    return out, {**twin, "pretension_N": max(pretension, 0.0)}


def simulate_trials(
    mean_cycle_deg: np.ndarray, rig: Rig, config: Mapping, calibrated: Mapping[str, float]
) -> Iterator[Trial]:
    """The protocol's trials in test order, simulated lazily; each repeat a new mounting."""
    protocol, effects = config["protocol"], config["twin"]["effects"]
    strides = int(protocol["strides"])
    programmed = programmed_flexion(mean_cycle_deg, config)
    knee_offset = twin_mechanics.knee_offset_m(programmed, rig)
    miss = effects["clutch_miss"]
    miss_p = float(miss["probability"]) if miss["enabled"] else 0.0
    values = effect_values(effects, calibrated)
    order = twin_trials({"phantom": config, "seed": config["seed"]})
    for index, (name, spring, repeat) in enumerate(order):
        rng = np.random.default_rng([int(config["seed"]), 1, index])
        own, settings = values, config
        if len(order) > len(protocol["test_order_N_per_m"]):
            draws = np.random.default_rng([int(config["seed"]), 3, index])
            own, twin = remounted(values, config["twin"], protocol["trials"]["remount"], draws)
            settings = {**config, "twin": twin}
        missed = rng.random(strides) < miss_p
        engaged, state = stride_states(
            programmed, knee_offset, np.full(strides, spring), missed, rig, settings, own
        )
        yield assemble((name, spring, repeat), programmed, engaged, state, own, settings, rig, rng)
        del engaged, state  # not held while the next trial is simulated


def assemble(trial, programmed, engaged, state, values, config, rig, rng) -> Trial:
    """One trial's simulation (trial = (name, spring, repeat)) as recordings and truth."""
    name, spring, repeat = trial
    strides, samples = programmed.shape
    get = {name: column.ravel() for name, column in state.items()}
    theta = get["phantom_knee_angle_rad"]
    moment = get["knee_moment_Nm"]
    dt = 1.0 / ANALOG_RATE_HZ
    paths = leg_paths(theta, rig)
    ankle_x, ankle_y = ankle_force_N(paths["thigh"], paths["shank"], moment, dt, rig)
    effects = config["twin"]["effects"]
    step = round(ANALOG_RATE_HZ / POINT_RATE_HZ)  # markers only at the camera's frames
    framed = {k: np.ascontiguousarray(v[::step]) for k, v in paths.items()}
    exo = exo_points(
        framed,
        get["interface_deflection_rad"][::step],
        get["spring_extension_m"][::step],
        config["twin"],
    )
    markers = marker_positions_mm(framed, exo, values.get("offset_mm", 0.0) / 1000.0)
    if effects["marker_noise"]["enabled"]:
        sd = float(effects["marker_noise"]["sd_mm"])
        markers = {k: v + rng.normal(0.0, sd, v.shape) for k, v in sorted(markers.items())}
    add_occlusions(markers, effects["occlusion"], theta.size * dt, rng)
    analogs = {f"LC_ANKLE_{i + 1}": share * ankle_y for i, share in enumerate(LOAD_CELL_SHARES)}
    analogs["LC_SPRING"] = values.get("gain", 1.0) * get["spring_force_N"] + values.get(
        "offset_N", 0.0
    )
    analogs["SYNC"] = sync_channel(strides, samples)
    analogs = {k: delayed(v, values.get("analog_delay_s", 0.0), dt) for k, v in analogs.items()}
    if effects["load_cell_noise"]["enabled"]:
        sd = float(effects["load_cell_noise"]["sd_N"])
        for label in REQUIRED_ANALOGS:
            analogs[label] = analogs[label] + rng.normal(0.0, sd, theta.size)
    truth = pd.DataFrame(
        {
            "stride": np.repeat(np.arange(strides), samples),
            "t_s": np.arange(theta.size) * dt,
            "engaged": engaged.ravel() > 0,
            "clutch_level": engaged.ravel(),
            "programmed_knee_angle_rad": programmed.ravel(),
            **{name: get[name] for name in TRUTH_STATES},
            "ankle_force_x_N": ankle_x,
            "ankle_force_y_N": ankle_y,
        }
    )
    return Trial(name, float(spring), markers, analogs, truth, repeat)


def delayed(signal: np.ndarray, delay_s: float, dt_s: float) -> np.ndarray:
    """Signal as stamped by a clock lagging by delay_s: sample t holds the value at t − delay_s."""
    if delay_s == 0.0:
        return signal
    time = np.arange(signal.size) * dt_s
    return np.interp(time - delay_s, time, signal)


def write_recordings(
    trials: Iterable[Trial], folder, provenance: Mapping, ramp_strides: int
) -> list[str]:
    """Write trials as a lab would (``repeat`` column if repeated), truth, stamp; their names."""
    folder = Path(folder)
    rows = []
    for order, trial in enumerate(trials, start=1):
        file = f"{trial.name}.c3d"
        atomic.write_atomic(
            folder / file, lambda tmp, t=trial: c3d.write_trial(tmp, t.markers_mm, t.analogs)
        )
        tables.write_table(folder / "truth" / f"{trial.name}.parquet", trial.truth, provenance)
        rows.append(
            (trial.name, file, trial.spring_stiffness_N_per_m, order, ramp_strides, trial.repeat)
        )
        del trial  # not held while the next trial is simulated
    manifest = pd.DataFrame(rows, columns=[*MANIFEST_COLUMNS, "repeat"])
    if (manifest["repeat"] == 1).all():
        manifest = manifest.drop(columns="repeat")  # the study's design: one trial per spring
    atomic.write_text(folder / "manifest.csv", manifest.to_csv(index=False, lineterminator="\n"))
    names = [name for name, *_ in rows]
    stamp.write_stamp(folder, twin_files(names))
    return names
