"""Model discrepancy of the phantom recordings: the engaged window and the disengaged swing of
each stride as observations.

The observations of every included stride are its engaged window (``window_pct`` of the stride,
padded by ``margin_s`` on both sides so that delays and clock offsets can be predicted), sampled
every ``step``: the phantom angle (model input), knee moment, exoskeleton-angle and
spring-length change since the window start and spring force; and the knee moment over the
disengaged swing (``noise_pct``), where the clutch is open and the exoskeleton carries no load,
so the net knee moment the inverse dynamics gives must be zero: whatever it holds there is a
sensor or model error seen directly (the ``swing`` observable); and LC_SPRING there must hold
the spring's pretension, whatever the ankle does (``swing_force``). The same swing samples give the
noise: there the moment, the exoskeleton–phantom angle difference, the spring length and force
are constant up to noise; their spread about each stride's mean is the engaged observables'
noise scale and the null of their structure tests, the moment's and the tension's with the
measured angle's noise (which drives the models) passed through each stride's stiffness. The
swing moment's own noise is the
difference of consecutive strides at the same phase (over √2): a moment the phantom or the
sensors add at every stride cancels there, and only what varies from stride to stride remains.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence

import numpy as np
import pandas as pd
from scipy.interpolate import CubicSpline

from exobench import selection
from exobench.errors import InputError
from exobench.phantom.chain.dynamics import SEGMENT_VALUES
from exobench.phantom.chain.filtering import butterworth_zero_phase
from exobench.phantom.model import assumptions, effects, terms
from exobench.phantom.rig import ANALOG_RATE_HZ, POINT_RATE_HZ, Rig
from exobench.selection import assumptions as table
from exobench.selection import summary

CHANNELS = {
    "phantom": "phantom_knee_angle_rad",
    "moment": "knee_moment_Nm",
    "exo": "exo_knee_angle_rad",
    "length": "spring_length_m",
    "force": "spring_force_N",
    "ankle": "ankle_force_y_N",
    "ankle_x": "ankle_force_x_N",
    "arm": "moment_per_ankle_force_m",
    "hip": "moment_per_hip_moment_Nm_per_Nm",
    "thigh_rate": "thigh_rate_rad_per_s",
    "thigh_angle": "thigh_angle_rad",
    **{key: f"moment_per_{key}_scale_Nm" for key in SEGMENT_VALUES},
    **{f"{key}2": f"moment_per_{key}_scale2_Nm" for key in ("thigh_com", "shank_com")},
    "knee_shift": "moment_per_knee_shift_Nm_per_m",
    **{cell: f"LC_ANKLE_{i}_N" for i, cell in enumerate(effects.CELLS, start=1)},
}
# The arrays of both windows (the swing's prefixed swing_) and the channel each holds: what the
# terms read of the recordings.
WINDOW_ARRAYS = {
    "ankle_force_N": "ankle",
    "ankle_force_x_N": "ankle_x",
    "moment_per_ankle_force_m": "arm",
    "moment_per_hip_moment": "hip",
    "thigh_rate_rad_per_s": "thigh_rate",
    "thigh_angle_rad": "thigh_angle",
    "spring_force_N": "force",
    "time_s": "time",
    **{f"moment_per_{key}_scale_Nm": key for key in SEGMENT_VALUES},
    **{f"moment_per_{key}_scale2_Nm": f"{key}2" for key in ("thigh_com", "shank_com")},
    "moment_per_knee_shift_Nm_per_m": "knee_shift",
    **{cell: cell for cell in effects.CELLS},
}
# the columns of a kinetics table the observations read
KINETICS_COLUMNS = ["t_s", *CHANNELS.values()]
RELATIVE = ("exo", "spring")
MEASURED = {
    "moment": "moment_Nm",
    "exo": "exo_change_rad",
    "spring": "spring_change_m",
    "force": "spring_force_N",
    "swing": "swing_moment_Nm",
    "swing_force": "swing_spring_force_N",
}
# the observables of the disengaged swing
SWING = ("swing", "swing_force")
NAMES = {
    "moment": "knee moment",
    "exo": "exoskeleton-angle change",
    "spring": "spring-length change",
    "force": "spring force",
    "swing": "knee moment in the disengaged swing",
    "swing_force": "spring force in the disengaged swing",
}


def problem() -> selection.Problem:
    """The phantom group's problem for the shared engine."""
    return selection.Problem(
        group="phantom",
        registry=effects.REGISTRY,
        baseline=effects.baseline,
        measured=MEASURED,
        units=effects.OBSERVABLES,
        baseline_name="rigid theory (W.S.B. et al. eqs. 2.1–2.2)",
        features=features,
        noise=lambda data: data.constants["noise"],
        recorded=recorded,
        relative=RELATIVE,
        terms=terms.LIBRARY,
        names=NAMES,
        trend=lambda data: np.nanmean(data.arrays["time_s"], axis=1),
        # a structure with the clutch open is a finding about the knee moment or the tension
        sized_by={"swing": "moment", "swing_force": "force"},
        constants=table.constants(assumptions.TABLE, effects.REGISTRY),
    )


def recorded(state: dict, data: selection.Data) -> dict:
    """The analysis chain's view of predicted signals: its zero-phase low-pass (a fixed linear
    map of the window, applied as a matrix), angle and length as changes since the programmed
    engagement instant."""
    state = effects.solved(state, data)
    c = data.constants
    out = {}
    for name in MEASURED:
        analog, markers = c["swing_filter_matrix" if name in SWING else "filter_matrix"]
        smooth = state[name] @ (markers if name in RELATIVE else analog)
        out[name] = smooth - smooth[:, c["zero"], None] if name in RELATIVE else smooth
    for name, extra in state.get("recorded_extra", {}).items():  # terms built from recordings
        out[name] = out[name] + extra
    return out


def filter_matrices(samples: int, step: int, chain: Mapping) -> tuple[np.ndarray, np.ndarray]:
    """Matrices F with x @ F = what the chain makes of a window x sampled every ``step`` ms:
    (analog: its zero-phase Butterworth; markers: sampled at 100 Hz, filtered there, cubic
    spline back), each a fixed linear map of the window."""
    identity = np.eye(samples)
    cutoff, order = float(chain["filter_cutoff_Hz"]), int(chain["filter_order"])
    analog = butterworth_zero_phase(identity, ANALOG_RATE_HZ / step, cutoff, order)
    every = round(ANALOG_RATE_HZ / POINT_RATE_HZ / step)
    frames = np.arange(0, samples, every)
    smooth = butterworth_zero_phase(identity[frames], POINT_RATE_HZ, cutoff, order)
    markers = CubicSpline(frames, smooth, axis=0)(np.arange(samples))
    return analog.T, markers.T  # column j held the response to an impulse at sample j


def model_input(measured: np.ndarray, markers: np.ndarray) -> np.ndarray:
    """The phantom angle that drives the models: the measured one with the chain's marker
    low-pass F undone to second order, θ = θ_f + d + (d − d·F), d = θ_f − θ_f·F (Neumann series
    of F⁻¹), so that predictions, passed once through the chain's filters, compare with
    recordings filtered once."""
    once = measured - measured @ markers
    return measured + once + (once - once @ markers)


def features(data: selection.Data) -> dict[str, dict[str, np.ndarray]]:
    """What residuals are tested against: in the engaged window gait phase, phantom angle and
    rate and the measured moment; in the swing gait phase, phantom angle and rate and the
    vertical ankle force."""
    out = {}
    for window, prefix in (("engaged", ""), ("swing", "swing_")):
        theta = data.arrays[f"{prefix}phantom_measured_rad"]
        force = data.arrays["moment_Nm" if window == "engaged" else "swing_ankle_force_N"]
        out[window] = {
            "phase": np.broadcast_to(data.constants[f"{prefix}t_s"], theta.shape),
            "angle": theta,
            "velocity": np.gradient(theta, data.constants["dt_s"], axis=1),
            "force" if window == "engaged" else "ankle force": force,
        }
    return {obs: out["swing" if obs in SWING else "engaged"] for obs in MEASURED}


def _continuous(kinetics: pd.DataFrame) -> dict[str, np.ndarray]:
    """The kinetics table's channels on one 1000 Hz time line (NaN between analysed strides)."""
    index = np.round(kinetics["t_s"].to_numpy() * ANALOG_RATE_HZ).astype(int)
    length = int(index.max()) + 1 if index.size else 0
    out = {"time": np.arange(length) / ANALOG_RATE_HZ}
    for key, column in CHANNELS.items():
        line = np.full(length, np.nan)
        line[index] = kinetics[column].to_numpy()
        out[key] = line
    return out


def _windows(line: np.ndarray, starts: np.ndarray, first: int, count: int, step: int):
    """(strides, samples) windows of a time line from start+first, every ``step`` samples."""
    offsets = first + np.arange(count) * step
    index = starts[:, None] + offsets[None, :]
    valid = (index >= 0) & (index < line.size)
    return np.where(valid, line[np.clip(index, 0, line.size - 1)], np.nan)


def observations(parts: Sequence[tuple], settings: Mapping, rig: Rig, chain: Mapping):
    """Observations (:class:`selection.Data`) and noise scales from (trial, spring, kinetics,
    strides) of every trial; included strides only, at most ``max_strides_per_trial`` each."""
    step = int(settings["step"])
    if (ANALOG_RATE_HZ / POINT_RATE_HZ) % step:
        raise InputError("config", "phantom.discrepancy.step", "a divisor of 10 (ms)", step)
    start_pct, end_pct = (float(v) for v in settings["window_pct"])
    noise_lo, noise_hi = (float(v) for v in settings["noise_pct"])
    before, after = (round(float(m) * ANALOG_RATE_HZ / step) for m in settings["margin_s"])
    limit = int(settings["max_strides_per_trial"])
    blocks: dict[str, list] = {}
    for trial, spring, kinetics, strides in parts:
        kept = strides[strides["included"]]
        if kept.empty:
            continue
        kept = kept.iloc[
            np.unique(np.linspace(0, len(kept) - 1, min(limit, len(kept))).astype(int))
        ]
        line = _continuous(kinetics)
        begin = np.round(kept["start_s"].to_numpy() * ANALOG_RATE_HZ).astype(int)
        length = np.round((kept["end_s"] - kept["start_s"]).to_numpy() * ANALOG_RATE_HZ)
        samples = int(np.min(length))
        first = round(start_pct / 100 * samples) - before * step
        count = int((end_pct - start_pct) / 100 * samples) // step + before + after
        win = {k: _windows(v, begin, first, count, step) for k, v in line.items()}
        nfirst = round(noise_lo / 100 * samples)
        ncount = int((noise_hi - noise_lo) / 100 * samples) // step
        noise = {k: _windows(v, begin, nfirst, ncount, step) for k, v in line.items()}
        good = np.all([np.isfinite(w).all(1) for w in (*win.values(), *noise.values())], axis=0)
        for key, value in {
            **{f"w_{k}": v[good] for k, v in win.items()},
            **{f"n_{k}": v[good] for k, v in noise.items()},
            "trial": np.full(good.sum(), trial, dtype=object),
            "stride": kept["stride"].to_numpy()[good],
            "k": np.full(good.sum(), float(spring)),
        }.items():
            blocks.setdefault(key, []).append(value)
    needed = 2 * int(settings["engine"]["folds"])
    found = sum(b.size for b in blocks.get("trial", []))
    if found < needed:
        raise InputError(
            "phantom recordings", "included strides",
            f"at least {needed} strides with a complete engaged window for the discrepancy "
            "engine", found,
        )  # fmt: skip
    j = {k: np.concatenate(v) for k, v in blocks.items()}
    dt = step / ANALOG_RATE_HZ
    t = (np.arange(j["w_phantom"].shape[1]) - before) * dt
    zero = before  # the programmed engagement instant
    noise = {
        "moment": j["n_moment"],
        "exo": j["n_exo"] - j["n_phantom"],
        "spring": j["n_length"],
        "force": j["n_force"],
    }
    noise = {k: v - v.mean(axis=1, keepdims=True) for k, v in noise.items()}
    # the models are driven by the measured angle: its noise, through each stride's series
    # stiffness, is noise of the predicted moment and tension too (the stiffer the spring, the
    # more), beside the sensors' own
    stiffness = series_stiffness(j["w_moment"], j["w_phantom"], zero, before, after)
    drive = noise["exo"] / np.sqrt(2.0)  # one angle's share of the two angles' difference
    noise["moment"] = noise["moment"] + stiffness[:, None] * drive
    noise["force"] = noise["force"] + (stiffness / rig.spring_travel_m_per_rad)[:, None] * drive
    noise["swing"] = stride_differences(j["n_moment"], j["trial"])
    noise["swing_force"] = stride_differences(j["n_force"], j["trial"])
    scales = {k: float(np.std(v)) or 1.0 for k, v in noise.items()}
    mask = np.zeros(t.size, bool)
    mask[before : t.size - after] = True
    matrices = filter_matrices(t.size, step, chain)
    swing_matrices = filter_matrices(ncount, step, chain)
    arrays = {
        "moment_Nm": j["w_moment"],
        "exo_change_rad": j["w_exo"] - j["w_exo"][:, zero : zero + 1],
        "spring_change_m": j["w_length"] - j["w_length"][:, zero : zero + 1],
        "spring_force_N": j["w_force"],
        "swing_moment_Nm": j["n_moment"],
        "swing_spring_force_N": j["n_force"],
        "k_spring_N_per_m": j["k"],
        "pretension_N": np.full(j["k"].size, float(settings["pretension_N"])),
    }
    for prefix, w, matrix in (("", "w", matrices), ("swing_", "n", swing_matrices)):
        arrays.update({
            f"{prefix}phantom_rad": model_input(j[f"{w}_phantom"], matrix[1]),
            f"{prefix}phantom_measured_rad": j[f"{w}_phantom"],
            **{f"{prefix}{name}": j[f"{w}_{key}"] for name, key in WINDOW_ARRAYS.items()},
        })  # fmt: skip
    for name in MEASURED:
        if name not in SWING:
            arrays[f"mask_{name}"] = np.broadcast_to(mask, j["w_phantom"].shape)
    constants = {
        "t_s": t,
        "swing_t_s": (nfirst + np.arange(ncount) * step) / ANALOG_RATE_HZ,
        "dt_s": dt,
        "rig": rig,
        "thigh_m": rig.thigh_length_m,
        "shank_m": rig.shank_length_m,
        "noise": {k: v / scales[k] for k, v in noise.items()},
        "zero": zero,
        "filter_matrix": matrices,
        "swing_filter_matrix": swing_matrices,
    }
    data = selection.Data(arrays, j["trial"], j["stride"], constants)
    return data, scales


def series_stiffness(moment: np.ndarray, angle: np.ndarray, zero: int, before: int,
                     after: int) -> np.ndarray:  # fmt: skip
    """Each stride's knee stiffness as its engaged window shows it: the least-squares slope of
    the measured moment on the phantom angle's change since the engagement (N·m/rad)."""
    change = (angle - angle[:, zero : zero + 1])[:, before : angle.shape[1] - after]
    load = moment[:, before : moment.shape[1] - after]
    return np.maximum(np.sum(load * change, axis=1) / np.maximum(np.sum(change**2, axis=1),
                                                                 1e-12), 0.0)  # fmt: skip


def stride_differences(windows: np.ndarray, trial: np.ndarray) -> np.ndarray:
    """Differences of consecutive strides' windows within each trial, over √2: the stride-to-
    stride noise of a signal, free of whatever repeats at every stride."""
    rows = [np.diff(windows[trial == name], axis=0) for name in dict.fromkeys(trial)]
    return np.concatenate(rows) / np.sqrt(2.0)


def analyse(data: selection.Data, scales, settings: Mapping, source: str) -> dict:
    """The discrepancy report of the recordings (shared engine and schema)."""
    engine = selection.Settings.from_config(settings["engine"], settings["seed"])
    return selection.analyse(problem(), data, scales, engine, source)


def reported_model(report: Mapping) -> tuple[list[str], dict[str, float]]:
    """The model a report settles on: its registry effects (found or tentative) and its named
    discovered terms, with every parameter's estimate."""
    fit = summary.as_fit(report)
    return fit["effects"], fit["parameters"]


def prediction_table(data: selection.Data, report: Mapping) -> pd.DataFrame:
    """Measured, baseline and selected-model moment per window sample of the strides in
    ``data`` (the engine's, or every included stride's), the models as the report fitted them
    (for the figure and the verdict)."""
    chosen, values = reported_model(report)
    engine = problem()
    baseline = selection.predict(engine, data, (), {})["moment"]
    extended = selection.predict(engine, data, chosen, values)["moment"]
    keep = data.arrays["mask_moment"][0]
    samples = int(keep.sum())
    return pd.DataFrame(
        {
            "trial": np.repeat(data.trial.astype(str), samples),
            "spring_stiffness_N_per_m": np.repeat(data.arrays["k_spring_N_per_m"], samples),
            "stride": np.repeat(data.order, samples),
            "t_s": np.tile(data.constants["t_s"][keep], data.units),
            "phantom_knee_angle_rad": data.arrays["phantom_measured_rad"][:, keep].ravel(),
            "measured_moment_Nm": data.arrays["moment_Nm"][:, keep].ravel(),
            "baseline_moment_Nm": baseline[:, keep].ravel(),
            "extended_moment_Nm": extended[:, keep].ravel(),
        }
    )


def term_table(data: selection.Data, report: Mapping) -> pd.DataFrame:
    """For every discovered term (named or proposed), per observable it acts on and sample that
    counts: the correction it makes and the residual (measured − predicted) of the report's
    model without it (before) and with it (after), in the observable's unit (the columns of the
    other units are empty)."""
    engine = problem()
    chosen, values = reported_model(report)
    terms = [*report["discovery"]["named"], *report["discovery"]["proposed"]]
    values = {**values, **{k: v for e in terms for k, v in e["parameters"].items()}}
    units = sorted(set(effects.OBSERVABLES.values()))
    columns = ["term", "observable", "trial", "stride"] + [
        f"{kind}_{unit}" for unit in units
        for kind in ("correction", "residual_before", "residual_after")
    ]  # fmt: skip
    rows = [pd.DataFrame({c: pd.Series(dtype=object if c in columns[:3] else float)
                          for c in columns})]  # fmt: skip
    for entry in terms:
        name = entry["term"]
        with_term = selection.predict(engine, data, [*chosen, name], values)
        without = selection.predict(engine, data, [c for c in chosen if c != name], values)
        for obs in entry["observables"]:
            measured = data.arrays[MEASURED[obs]]
            mask = data.arrays.get(f"mask_{obs}", np.ones(measured.shape, bool))
            unit = effects.OBSERVABLES[obs]
            rows.append(pd.DataFrame({
                "term": name,
                "observable": obs,
                "trial": np.broadcast_to(data.trial.astype(str)[:, None], mask.shape)[mask],
                "stride": np.broadcast_to(data.order[:, None], mask.shape)[mask],
                f"correction_{unit}": (with_term[obs] - without[obs])[mask],
                f"residual_before_{unit}": (measured - without[obs])[mask],
                f"residual_after_{unit}": (measured - with_term[obs])[mask],
            }))  # fmt: skip
    return pd.concat(rows, ignore_index=True)[columns]
