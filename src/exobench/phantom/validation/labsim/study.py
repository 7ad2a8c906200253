"""Simulated trials (one per spring) and the files a lab would write: C3D files and manifest.csv."""

from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import NamedTuple

import numpy as np
import pandas as pd

from .c3d import write_c3d
from .cells import load_cell_signals, sync_signal
from .chain import exoskeleton_response
from .leg import (
    ankle_forces,
    cycle_extrema,
    knee_motion,
    marker_positions,
    phantom_knee_moment,
    read_mean_cycle,
    real_leg,
)
from .rig import (
    BETWEEN,
    FS_ANALOG,
    FS_POINT,
    LOAD_CELLS,
    MANIFEST_COLUMNS,
    SHIFT_SD_DEG,
    STRIDE_S,
    VIOLATIONS,
    Z_MAX,
    check_duration,
    checked_violations,
    value_of,
)


class Trial(NamedTuple):
    """A trial: markers (3, 12, frames) in mm, analogs (5, samples), between-trial draws by key."""

    name: str
    spring_N_per_m: float
    points_mm: np.ndarray
    analogs: np.ndarray
    between: dict


def between_draws(
    violations: Mapping[str, Mapping[str, float]],
    trials: int,
    seed: int,
    fixed: Mapping[str, Sequence[float]] | None = None,
) -> dict[str, list[float]]:
    """z_i ~ N(0, 1) truncated at ±Z_MAX per trial and present between-trial key (or `fixed`)."""
    draws = np.random.default_rng(np.random.SeedSequence(seed).spawn(1)[0])
    out = {}
    for key in BETWEEN:
        if key not in violations:
            continue
        if fixed is not None and key in fixed:
            z = np.asarray(fixed[key], dtype=float)
            if z.shape != (trials,) or not np.all(np.abs(z) <= Z_MAX):
                raise ValueError(f"{key}: give one z per trial, |z| ≤ {Z_MAX}, got {z}")
        else:
            z = np.array([_truncated_normal(draws) for _ in range(trials)])
        out[key] = z.tolist()
    return out


def _truncated_normal(rng: np.random.Generator) -> float:
    """One standard normal draw, redrawn until |z| ≤ Z_MAX."""
    while abs(z := float(rng.standard_normal())) > Z_MAX:
        pass
    return z


def trial_violations(
    violations: Mapping[str, Mapping[str, float]], z: Mapping[str, float]
) -> tuple[dict, dict]:
    """Trial i's violations and draws: k_interface·(1 + s·z_i), LC_SPRING's zero s·z_i (N)."""
    out, drawn = dict(violations), {}
    straps, zero = "straps_between.between", "cells_zero_between.between"
    if straps in z:
        (name,) = VIOLATIONS["interface.elastic"]
        k = violations["interface.elastic"][name] * (
            1.0 + value_of(violations, straps, 0.0) * z[straps]
        )
        out["interface.elastic"] = {name: k}
        drawn[straps] = {"z": z[straps], name: k}
    if zero in z:
        drawn[zero] = {"z": z[zero], "offset_N": value_of(violations, zero, 0.0) * z[zero]}
    return out, drawn


def simulate_study(
    *,
    cycle_csv: Path,
    springs_N_per_m: Sequence[float],
    strides: int,
    ramp_strides: int,
    violations: Mapping[str, Mapping[str, float]],
    seed: int,
    marker_noise_mm: float = 0.15,
    cell_noise_N: float = 0.5,
    occlusions_per_marker: float = 0.0,
    cell_shares: Sequence[float] = (0.30, 0.33, 0.37),
    substeps: int = 4,
    release_s: float = 0.1,
    between_z: Mapping[str, Sequence[float]] | None = None,
) -> list[Trial]:
    """The trials write_study writes (one per spring, in test order), as arrays.

    A between-trial violation draws z_i per trial (between_z fixes them), reported on each Trial.
    """
    violations = checked_violations(violations)
    if strides <= 2 * ramp_strides or ramp_strides < 0:
        raise ValueError("strides must exceed twice ramp_strides (≥ 0)")
    if len(cell_shares) != 3 or not np.isclose(sum(cell_shares), 1.0):
        raise ValueError("cell_shares must be three shares summing to 1")
    if substeps < 1 or (FS_ANALOG * substeps) % FS_POINT:
        raise ValueError("substeps must be a whole number ≥ 1")
    names = [f"k{k:.0f}" for k in springs_N_per_m]
    if len(set(names)) != len(names):
        raise ValueError(f"springs give duplicate trial names: {names}")
    check_duration(violations, strides * STRIDE_S)
    rng = np.random.default_rng(seed)
    cycle = read_mean_cycle(cycle_csv)
    shifts = np.deg2rad(rng.normal(0.0, SHIFT_SD_DEG, (strides, cycle_extrema(cycle).size)))
    n = strides * round(STRIDE_S * FS_ANALOG)
    t = np.arange(n) / FS_ANALOG
    fine = knee_motion(
        cycle, shifts, ramp_strides, np.arange(n * substeps) / (FS_ANALOG * substeps)
    )
    leg = real_leg(violations)
    hinge = phantom_knee_moment(fine, violations)
    hip = tuple(value_of(violations, f"hip.{f}", 0.0) for f in ("viscous", "coulomb", "elastic"))
    sync = sync_signal(
        n,
        value_of(violations, "clocks.delay", 0.0) * FS_ANALOG,
        value_of(violations, "clocks.drift", 0.0),
    )
    frames = slice(None, None, substeps * FS_ANALOG // FS_POINT)
    draws = between_draws(violations, len(names), seed, between_z)
    trials = []
    for i, (name, k) in enumerate(zip(names, springs_N_per_m, strict=True)):
        real, drawn = trial_violations(violations, {key: z[i] for key, z in draws.items()})
        exo = exoskeleton_response(fine.theta, FS_ANALOG * substeps, k, real, release_s)
        fx, fy = ankle_forces(fine, exo.moment + hinge, leg, *hip)
        cells = load_cell_signals(fx, fy, exo.tension, violations, cell_shares, substeps)
        cells[:3] += rng.normal(0.0, cell_noise_N, (3, n))
        cells[3] += rng.normal(0.0, cell_noise_N, n)
        for c, cell in enumerate(LOAD_CELLS):
            cells[c] += value_of(violations, f"{cell}.offset", 0.0)
            cells[c] += value_of(violations, f"{cell}.drift", 0.0) * t
        if "cells_zero_between.between" in drawn:
            cells[LOAD_CELLS.index("LC_SPRING")] += drawn["cells_zero_between.between"]["offset_N"]
        points = marker_positions(
            fine.theta[frames],
            exo.interface[frames],
            exo.spring_length[frames],
            leg,
            value_of(violations, "bars.offset", 0.0),
            value_of(violations, "knee_markers.offset", 0.0),
        )
        points += rng.normal(0.0, marker_noise_mm, points.shape)
        _occlude(points, occlusions_per_marker, rng)
        trials.append(Trial(name, float(k), points, np.vstack([cells, sync]), drawn))
    return trials


def _occlude(points: np.ndarray, per_marker: float, rng: np.random.Generator) -> None:
    """Blank Poisson(per_marker) gaps of 3–15 frames per marker with NaN, in place."""
    n_frames = points.shape[2]
    counts = rng.poisson(per_marker, size=points.shape[1])
    starts = rng.integers(0, n_frames, size=counts.sum())
    lengths = rng.integers(3, 16, size=counts.sum())
    markers = np.repeat(np.arange(points.shape[1]), counts)
    frames = np.arange(n_frames)
    for mk, st, ln in zip(markers, starts, lengths, strict=True):
        points[:, mk, (frames >= st) & (frames < st + ln)] = np.nan


def write_study(folder: Path, **study) -> Path:
    """Write one C3D per spring and manifest.csv into folder; return the manifest's path
    (``study``: the keywords of :func:`simulate_study`)."""
    trials = simulate_study(**study)
    folder = Path(folder)
    folder.mkdir(parents=True, exist_ok=True)
    rows = []
    for order, trial in enumerate(trials, start=1):
        write_c3d(folder / f"{trial.name}.c3d", trial.points_mm, trial.analogs)
        rows.append(
            (trial.name, f"{trial.name}.c3d", trial.spring_N_per_m, order, study["ramp_strides"])
        )
    manifest = folder / "manifest.csv"
    pd.DataFrame(rows, columns=list(MANIFEST_COLUMNS)).to_csv(manifest, index=False)
    return manifest
