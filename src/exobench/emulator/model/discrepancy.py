"""Model discrepancy of the emulator recordings: step windows as observations of the shared engine.

Units are the complete steps of every trial with a spring, in order within the trial (folds are
contiguous step blocks, the bootstrap resamples steps within trials; a count drop the QC located
splits its trial into two segments for both, so a drop late in a trial is still fitted on
training steps). Each step contributes the
``WINDOW`` samples before the heel strike that ends it, every ``SAMPLE_STEP`` brace samples (the
motion capture's frame interval; the spring is active in late swing, at the end of the step),
and the motion-capture angle at 1 kHz with ``MARGIN`` window samples more on either side so
that a clock offset can be predicted. Observables: brace torque, encoder angle and the energy
stored over the window (:mod:`exobench.emulator.model.effects`), and the controller's desired torque
integrated along a row at 1 kHz from the window's start to ``RELEASE_SPAN_S`` after the heel
strike (Table 6.1 releases the clutch at the peak extension just before it; a late release shows
after it).

Noise-only samples (the null of the structure tests and the noise scales), chosen so that no
effect of the registry shows in them:
- torque: the samples where the spring is inactive as recorded, less the little torque the
  calibrated cable delivers at the stretch the recorded motor and encoder angles imply (the QC's
  count drops removed; through the recorded torque's low-pass), each step's mean removed (so an
  offset is not taken for noise): the load cell's noise;
- encoder: the encoder minus the motion capture mapped onto the encoder by the trial's own
  alignment and with the count drops the QC located removed (:mod:`crosscheck`), on the same
  inactive samples (no cuff load), its part locked to the gait phase (harmonics 1–4 of the
  trial's gait cycle) and each step's mean removed: what is left is the two sensors' noise. A
  pattern locked to the gait (a soft-tissue artefact, a hinge off the knee's axis, play) is
  structure a term can explain, not noise; the harmonic the locked part shows most (of 1–3,
  pooled over the trials) and its phase place the library's soft-tissue artefact
  (``constants["artefact"]``), as the QC places a count drop for the registry.
Inactive samples of a trial are strung together into rows of the window's width.
The energy's noise scale follows from the torque noise through the energy sum (measured and
predicted energy share the recorded encoder angle).
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from functools import cache

import numpy as np
import pandas as pd

from exobench import selection, signals, studies
from exobench.emulator.chain import activity, crosscheck, events
from exobench.emulator.chain.controller import direction_weight, pulley_ratio, recorded_torque_Nm
from exobench.emulator.model import assumptions, effects, terms
from exobench.emulator.recordings.acquire import RATE_TOLERANCE
from exobench.emulator.rig import BRACE_RATE_HZ, sample_rate_Hz
from exobench.errors import InputError
from exobench.selection import assumptions as table

SAMPLE_STEP = 10  # brace samples (1 kHz) per window sample: the motion capture's 100 Hz frames
RATE_CUTOFF_HZ = 20.0  # knee rate for the cable's direction: zero phase, sharp at reversals
WINDOW_SHARE = 0.4  # window: this share of the shortest step, ending at heel strike (late swing)
MAX_STEPS_PER_TRIAL = 15  # steps per trial, spread evenly over the trial (keeps the engine fast)
MARGIN = 10  # window samples of motion capture on either side (±0.1 s of clock offset)
DESIRED_PRECISION_NM = 1e-6  # desired torque's scale if the encoder is not quantised (CSV digits)
BRACE_DT_S = 1e-3  # the brace's sample interval (1 kHz)
RELEASE_SPAN_S = 0.3  # desired-torque rows run this long past heel strike (release delay bound)
ROW_AFTER = round(RELEASE_SPAN_S / BRACE_DT_S)  # brace samples of a row after heel strike
# The encoder's residual is compared below this frequency (zero-phase, the same filter on the
# prediction and the recording): the prediction carries motion capture's frame noise, white to
# 50 Hz, and a fit rewards whatever shrinks it (a larger motion-capture gain: regression
# dilution, ~0.4 % on the default twin, and an artefact term that cancels part of the knee's
# own motion at a gain of 1.13 and 3.8°); below 10 Hz a fifth of that noise is left, and the
# knee's motion, the cuff's settling and the clock's shift all stay.
ENCODER_CUTOFF_HZ = 10.0
ARTEFACT_HARMONICS = (1, 2, 3)  # the harmonics of the gait the table's mocap.harmonic law allows
# 1 kHz torque rows start this many samples before the window: the recorded torque's low-pass
# (20 Hz, Heer §5.2) forgets where a row starts within it (its response decays as e^(−t/11 ms))
LEAD = MARGIN * SAMPLE_STEP
DEG = effects.DEG
MEASURED = {"torque": "torque_Nm", "encoder": "encoder_low_deg", "energy": "energy_J",
            "desired_impulse": "desired_impulse_Nm_s"}  # fmt: skip


LOCATED = ("encoder_count_drop",)


def problem(located: bool = True) -> selection.Problem:
    """The emulator group's problem for the shared engine (``located``: the QC located a count
    drop; without one the count-drop effect, which only sizes a located drop, changes nothing
    and is no candidate)."""
    registry = {n: e for n, e in effects.REGISTRY.items() if located or n not in LOCATED}
    return selection.Problem(
        group="emulator",
        registry=registry,
        baseline=effects.baseline,
        measured=MEASURED,
        units=effects.OBSERVABLES,
        baseline_name=(
            "cable model calibrated per trial (the brace angle from the recorded motor angle, "
            "the knee angle taken as the encoder's)"
        ),
        names={
            "torque": "brace torque",
            "encoder": "knee angle, encoder against motion capture",
            "energy": "energy stored per step",
            "desired_impulse": "desired-torque impulse",
        },
        features=features,
        noise=lambda data: data.constants["noise"],
        recorded=recorded,
        exact=("desired_impulse",),
        terms=terms.LIBRARY,
        located=LOCATED if located else (),
        constants=table.constants(assumptions.TABLE, registry),
        trials=session_trials,
        per_unit=("zero_deg", "torque_offset_Nm"),
    )


def session_trials(data: selection.Data) -> np.ndarray:
    """Each step's trial: its segment (``trial/k`` after the k-th count drop) without the
    drop."""
    return np.array([str(name).split("/")[0] for name in data.trial], dtype=object)


def recorded(state: dict, data: selection.Data) -> dict:
    """The observables of the state's model (:func:`effects.recorded`), the encoder through
    :func:`low_pass` as the recording's."""
    out = effects.recorded(state, data)
    return {**out, "encoder": low_pass(out["encoder"])}


def low_pass(rows: np.ndarray) -> np.ndarray:
    """Zero-phase 2nd-order (forward and backward) Butterworth low-pass at
    ``ENCODER_CUTOFF_HZ`` along each row of window samples (a linear map of a row, applied as
    its matrix)."""
    return rows @ _low_pass_matrix(rows.shape[1]).T


@cache
def _low_pass_matrix(width: int) -> np.ndarray:
    """The matrix of :func:`low_pass` on rows of ``width`` samples: the filter of each unit
    sample."""
    sos = signals.butterworth(2, ENCODER_CUTOFF_HZ, 1000.0 / SAMPLE_STEP)
    return signals.zero_phase(sos, np.eye(width))


def features(data: selection.Data) -> dict[str, dict[str, np.ndarray]]:
    """What the torque and encoder residuals are tested against: phase in the window, encoder
    angle, knee velocity and the controller's recorded desired torque (noise-free: binning on
    the measured torque would sort its own noise)."""
    angle = data.arrays["encoder_deg"]
    shared = {
        "phase": np.broadcast_to(np.arange(angle.shape[1], dtype=float), angle.shape),
        "angle": angle,
        "velocity": data.arrays["velocity_deg_per_s"],
        "force": data.arrays["desired_Nm"],
    }
    return {"torque": shared, "encoder": shared}


def smooth(line_1kHz: np.ndarray, cutoff_Hz: float) -> np.ndarray:
    """Zero-phase 4th-order (2nd-order forward and backward) Butterworth low-pass of a 1 kHz
    series."""
    return signals.zero_phase(signals.butterworth(2, cutoff_Hz, 1000.0), line_1kHz)


def mocap_1kHz(samples: pd.DataFrame) -> np.ndarray:
    """Motion capture on the brace clock: a cubic spline through its recorded frames, unfiltered.

    A low-pass (12 Hz, zero phase) or linear interpolation between the 100 Hz frames flattens
    the swing peaks by ~0.1 %: the engine read that as a motion-capture gain off by 0.0008 and a
    clock off by 0.1 ms, outside its intervals. The frames' noise stays, and widens them."""
    from scipy.interpolate import CubicSpline  # here: the verdict's job imports this module

    frames = np.flatnonzero(samples["mocap_frame"].to_numpy())
    t = samples["t_s"].to_numpy()
    spline = CubicSpline(t[frames], samples["mocap_angle_deg"].to_numpy()[frames])
    return spline(np.clip(t, t[frames[0]], t[frames[-1]]))


def trial_windows(
    samples: pd.DataFrame,
    in_trial: np.ndarray,
    before: bool,
    width: int,
    transmission: Mapping,
    blend_deg_per_s: float,
    torque_filter_Hz: float | None,
    excluded: tuple[int, ...] = (),
) -> dict:
    """(steps, samples) windows of one trial's per-sample table: the ``width`` window samples
    before each step's closing heel strike (motion capture with ``MARGIN`` more each side; the
    torque's inputs at 1 kHz from ``LEAD`` samples before the window), none reaching into a step
    the QC ``excluded`` (a brace gap, bridged in the table)."""
    hs = np.flatnonzero(samples["heel_strike"].to_numpy())
    n = len(samples)
    after = max(MARGIN * SAMPLE_STEP, ROW_AFTER)
    ends = hs[1:]
    ends = ends[(ends - (width + MARGIN) * SAMPLE_STEP >= 0) & (ends + after < n)]
    first = max((width + MARGIN) * SAMPLE_STEP, width * SAMPLE_STEP + LEAD)
    # every window's steps, from its first sample's to its last's, clear of the excluded ones
    spans = (
        np.searchsorted(hs, np.stack([np.maximum(ends - first, 0), ends + after - 1]), side="right")
        - 1
    )
    clear = ~np.any(
        (spans[0][:, None] <= np.asarray(excluded, int))
        & (np.asarray(excluded, int) <= spans[1][:, None]),
        axis=1,
    )
    ends = ends[clear]
    ends = ends[
        np.unique(np.linspace(0, ends.size - 1, min(MAX_STEPS_PER_TRIAL, ends.size)).astype(int))
    ]
    offsets = (np.arange(width) - width) * SAMPLE_STEP
    index = ends[:, None] + offsets[None, :]
    # motion capture at the brace's 1 kHz (a clock offset shifts it by fractions of a window
    # sample; interpolating between 10 ms samples would average their noise and favour one)
    wide = ends[:, None] + np.arange(-(width + MARGIN) * SAMPLE_STEP, MARGIN * SAMPLE_STEP)[None, :]
    rows = ends[:, None] + np.arange(-width * SAMPLE_STEP, ROW_AFTER)[None, :]
    fine = ends[:, None] + np.arange(-width * SAMPLE_STEP - LEAD, 0)[None, :]

    encoder = samples["brace_angle_deg"].to_numpy()
    rate = np.gradient(smooth(encoder, RATE_CUTOFF_HZ), 1e-3)
    t = samples["t_s"].to_numpy()
    phase = crosscheck.gait_phase(t, t[hs])
    inactive = ~samples["active"].to_numpy().astype(bool)
    # the excluded steps' samples are bridged: no noise floor from them either
    inactive &= ~np.isin(np.searchsorted(hs, np.arange(n), side="right") - 1, excluded)
    # encoder against the aligned motion capture, and its part locked to the gait
    apart = (samples["brace_angle_deg"] - samples["anatomical_angle_deg"]
             - samples["encoder_error_deg"]).to_numpy()  # fmt: skip
    counted = inactive & (np.arange(n) >= hs[0]) & (np.arange(n) < hs[-1])
    locked = crosscheck.gait_locked(phase, apart, counted)
    # the count drops the QC located split the trial into segments of constant encoder error
    changes = np.flatnonzero(np.diff(samples["encoder_error_deg"].to_numpy()) != 0.0) + 1

    def take(column, at=index):
        return samples[column].to_numpy()[at]

    # the clutch an arm latched once the knee passed 40° would hold (on the chain's velocity),
    # armed from the recording's first pass of 40°: a controller latched before the recording
    # began engages at loading peaks before it too, which the first step's window may hold;
    # what it adds to Table 6.1's are the runs it alone engages (at a loading peak)
    omega = samples["velocity_deg_per_s"].to_numpy()
    latched = events.clutch(encoder, omega, latched=True)
    loading = latched & ~samples["engaged"].to_numpy().astype(bool)
    closing = np.searchsorted(hs, ends)  # each window's closing heel strike, among hs

    return {
        "step": closing - 1,
        "segment": np.searchsorted(changes, ends, side="right"),
        "mocap_deg": mocap_1kHz(samples)[wide],
        "encoder_deg": take("brace_angle_deg"),
        "torque_Nm": take("brace_torque_Nm"),
        "desired_Nm": take("desired_torque_Nm"),
        "motor_fine_deg": take("motor_angle_deg", fine),
        "encoder_fine_deg": take("brace_angle_deg", fine),
        "rate_fine_deg_per_s": rate[fine],
        "dropped_fine": (in_trial | before)[fine].astype(float),
        "encoder_rows_deg": take("brace_angle_deg", rows),
        "desired_rows_Nm": take("desired_torque_Nm", rows),
        "velocity_rows_deg_per_s": take("velocity_deg_per_s", rows),
        "engaged_rows": take("engaged", rows),
        "loading_rows": loading[rows],
        "carried_at": carried_release(loading, hs, closing, rows[:, 0]),
        "stride_after": stride_after(hs, closing),
        "active": take("active").astype(float),
        "velocity_deg_per_s": take("velocity_deg_per_s"),
        "rate_deg_per_s": rate[index],
        "time_s": (t - t[0])[index],
        "phase": phase[index],
        "dropped": (in_trial | before)[index].astype(float),
        "in_trial": in_trial[index].astype(float),
        # noise-only samples of the trial: inactive, encoder against the aligned motion capture
        "noise_torque": samples["brace_torque_Nm"].to_numpy()
        - recorded_torque_Nm(
            transmission_Nm(samples, rate, transmission, blend_deg_per_s), torque_filter_Hz, 1e3
        ),
        "noise_encoder": apart - crosscheck.locked_design(phase) @ locked,
        "inactive": inactive,
        "hs": hs,
        "locked": locked,
    }


def transmission_Nm(
    samples: pd.DataFrame, rate_deg_per_s, transmission: Mapping, blend
) -> np.ndarray:
    """Cable torque the recorded motor angle and the brace angle imply (the encoder with the
    QC's count drops removed, plus half a count): what the load cell reads but its noise."""
    brace = samples["corrected_angle_deg"].to_numpy() + 0.5 * encoder_count_deg(
        samples["brace_angle_deg"].to_numpy()
    )
    stretch = samples["motor_angle_deg"].to_numpy() - pulley_ratio(transmission) * brace
    return effects.cable_Nm(stretch, direction_weight(rate_deg_per_s, blend), transmission)


def _noise_rows(line: np.ndarray, inactive: np.ndarray, hs: np.ndarray, width: int):
    """Inactive samples (every ``SAMPLE_STEP``-th, each step's mean removed) in rows of width."""
    keep = np.zeros(line.size, bool)
    keep[hs[0] : hs[-1] : SAMPLE_STEP] = True
    keep &= inactive
    step = np.searchsorted(hs, np.arange(line.size), side="right")
    values, which = line[keep], step[keep]
    means = np.bincount(which, values) / np.maximum(np.bincount(which), 1)
    centred = values - means[which]
    rows = centred.size // width
    return centred[: rows * width].reshape(rows, width)


def require_1kHz(trial: str, samples: pd.DataFrame) -> None:
    """Refuse a trial whose per-sample table (``t_s``) is not at the brace's 1000 Hz, the rate
    the engine's windows, strides and filters count in (docs/rig.md §3)."""
    rate = sample_rate_Hz(samples["t_s"])
    if abs(rate / BRACE_RATE_HZ - 1.0) > RATE_TOLERANCE:
        raise InputError(
            f"per-sample table of trial '{trial}' (its brace file)",
            "t_s",
            f"brace samples at {BRACE_RATE_HZ:g} Hz: the discrepancy engine and the direct checks "
            "count 1 kHz samples (its per-trial steps, energy and alignment hold at the file's "
            "own rate); resample the brace to 1000 Hz (every channel, e.g. "
            "scipy.signal.resample_poly, time_s on a 1 ms grid) and run again",
            f"{rate:g} Hz",
        )


def observations(parts, equilibrium_deg, blend_deg_per_s, transmission: Mapping, folds: int,
                 torque_filter_Hz: float | None):  # fmt: skip
    """Observations (:class:`selection.Data`) and noise scales from (trial, stiffness, per-sample
    table, QC record) of every trial with a spring, each at the brace's 1000 Hz
    (:func:`require_1kHz`); the recorded torque passed the real-time model's low-pass at
    ``torque_filter_Hz`` (None: unfiltered)."""
    parts = [p for p in parts if p[1] > 0.0]
    for trial, _, samples, _ in parts:
        require_1kHz(trial, samples)
    lengths = [np.diff(np.flatnonzero(s["heel_strike"].to_numpy())) for _, _, s, _ in parts]
    lengths = np.concatenate(lengths) if lengths else np.zeros(0)
    if lengths.size < 2 * folds:
        raise InputError("emulator recordings", "heel_strike",
                         f"at least {2 * folds} complete steps in trials with a spring",
                         lengths.size)  # fmt: skip
    width = round(WINDOW_SHARE * int(lengths.min()) / SAMPLE_STEP)
    blocks: dict[str, list] = {}
    noise: dict[str, list] = {"torque": [], "encoder": []}
    locked, located = [], []
    for trial, stiffness, samples, qc in parts:
        error = samples["encoder_error_deg"].to_numpy()
        before = "drop_before_trial" in qc.get("fault_kinds", [])
        excluded = tuple(e["step"] for e in qc.get("excluded_steps", []))
        win = trial_windows(samples, error != 0.0, before, width, transmission, blend_deg_per_s,
                            torque_filter_Hz, excluded)  # fmt: skip
        for kind in noise:
            noise[kind].append(_noise_rows(win[f"noise_{kind}"], win["inactive"], win["hs"], width))
        locked.append(win["locked"])
        count = win["step"].size
        keys = ("mocap_deg", "encoder_deg", "torque_Nm", "active", "velocity_deg_per_s",
                "dropped", "in_trial", "step", "rate_deg_per_s", "desired_Nm", "time_s",
                "phase", "encoder_rows_deg", "desired_rows_Nm", "engaged_rows", "loading_rows",
                "carried_at", "stride_after", "motor_fine_deg",
                "velocity_rows_deg_per_s",
                "encoder_fine_deg", "rate_fine_deg_per_s", "dropped_fine")  # fmt: skip
        for key in keys:
            blocks.setdefault(key, []).append(win[key])
        count_deg = encoder_count_deg(samples["brace_angle_deg"].to_numpy())
        blocks.setdefault("count_deg", []).append(np.full(count, count_deg))
        if count_deg > 0.0:  # a drop within the trial, sized on the encoder's own jump
            located += [(-d["size_deg"], count_deg) for d in qc.get("count_drops", [])]
        # folds and bootstrap stratify on the segments between count drops: every fold holds
        # steps on both sides of a drop, so its size is fitted on training steps wherever it is
        segment = np.array([f"{trial}" if k == 0 else f"{trial}/{k}" for k in win["segment"]],
                           dtype=object)  # fmt: skip
        blocks.setdefault("trial", []).append(segment)
        blocks.setdefault("stiffness_Nm_per_rad", []).append(np.full(count, float(stiffness)))
    j = {k: np.concatenate(v) for k, v in blocks.items()}
    noise = {k: np.concatenate(v) for k, v in noise.items()}
    noise["encoder"] = low_pass(noise["encoder"])
    scales = {k: float(np.std(v)) or 1.0 for k, v in noise.items()}
    dt = SAMPLE_STEP / 1000.0
    arrays = {
        **{k: j[k] for k in ("mocap_deg", "encoder_deg", "torque_Nm", "active", "desired_Nm",
                             "velocity_deg_per_s", "dropped", "in_trial", "count_deg",
                             "stiffness_Nm_per_rad", "rate_deg_per_s", "time_s", "phase",
                             "encoder_rows_deg", "velocity_rows_deg_per_s", "motor_fine_deg",
                             "encoder_fine_deg", "rate_fine_deg_per_s", "dropped_fine")},
        "engaged_rows": j["engaged_rows"].astype(float),
        "loading_rows": j["loading_rows"].astype(float),
        "carried_at": j["carried_at"],
        "weight_fine": direction_weight(j["rate_fine_deg_per_s"], blend_deg_per_s),
        "energy_J": effects.window_energy_J(j["torque_Nm"], j["encoder_deg"], j["active"]),
        "encoder_low_deg": low_pass(j["encoder_deg"]),
    }  # fmt: skip
    scales["energy"] = energy_noise_J(arrays, scales)
    spring = effects.spring_Nm(j["stiffness_Nm_per_rad"], equilibrium_deg, j["encoder_rows_deg"])
    table61 = activity.table61(j["engaged_rows"], spring, flag_recorded=False)
    release_at = release_samples(table61)
    impact_at = impact_samples(j["velocity_rows_deg_per_s"], release_at)
    # the runs only an arm latched once the knee passed 40° engages (at a loading peak): where
    # the row's last fall of them releases one, the sample that run began and the heel strike
    # after it (the row's own for a run begun before it, else the next step's)
    loading = j["loading_rows"].astype(bool)
    loading_release_at = release_samples(loading)
    loading_began = effects.last_runs(loading.astype(float), loading_release_at)
    closing = loading.shape[1] - ROW_AFTER  # the row's heel strike
    after = impact_at + j["stride_after"]
    arrays.update(
        release_at=release_at,
        impact_at=impact_at,
        loading_release_at=loading_release_at,
        loading_began=loading_began,
        loading_impact_at=np.where(loading_began < closing, impact_at, after),
        spring_rows_Nm=spring,
        table61_rows=table61.astype(float),
        table61_impulse_Nm_s=effects.impulse_Nm_s(spring * table61, BRACE_DT_S, SAMPLE_STEP),
        desired_impulse_Nm_s=effects.impulse_Nm_s(j["desired_rows_Nm"], BRACE_DT_S, SAMPLE_STEP),
    )
    # the controller's desired torque moves in steps of one encoder count of the spring law:
    # the impulse's resolution is one such step held for one sample
    step_Nm = float((j["stiffness_Nm_per_rad"] * j["count_deg"]).max()) * DEG
    scales["desired_impulse"] = (step_Nm or DESIRED_PRECISION_NM) * BRACE_DT_S
    constants = {
        "dt_s": dt,
        "brace_dt_s": BRACE_DT_S,
        "margin": MARGIN * SAMPLE_STEP,
        "lead": LEAD,
        "torque_filter_Hz": torque_filter_Hz,
        "mocap_dt_s": 1e-3,
        "stride": SAMPLE_STEP,
        "equilibrium_deg": float(equilibrium_deg),
        "transmission": transmission,
        "noise": {k: v / scales[k] for k, v in noise.items()},
        "artefact": artefact(np.array(locked)),
        # the counts lost at each drop the QC located within a trial, and one count
        "located": {"encoder_count_drop": {"drop_deg": {
            "values": [size for size, _ in located],
            "resolution": max((step for _, step in located), default=0.0)}}} if located else {},
    }  # fmt: skip
    arrays.update(effects.delivered_torques(arrays, constants))
    return selection.Data(arrays, j["trial"], j["step"], constants), scales


def carried_release(loading: np.ndarray, hs: np.ndarray, closing: np.ndarray,
                    start: np.ndarray) -> np.ndarray:  # fmt: skip
    """Where the run a latched arm alone engaged in each window's step (``loading``: on at a
    loading peak, the trial's samples; ``closing``: the index in ``hs`` of the heel strike that
    ends the step) released before the row began, in the row's samples from its ``start`` (≤ 0;
    NaN where none did since the step's first heel strike, or where a run is on at the row's
    start, which the row holds): a rule that releases later carries it into the row."""
    falls = np.flatnonzero(loading[:-1] & ~loading[1:]) + 1
    began = np.where(closing > 0, hs[np.maximum(closing - 1, 0)], -1)
    last = np.searchsorted(falls, start, side="right") - 1
    fall = falls[np.maximum(last, 0)] if falls.size else np.zeros(start.size, int)
    kept = (last >= 0) & (fall > began) & ~loading[start]
    return np.where(kept, fall - start, np.nan).astype(float)


def stride_after(hs: np.ndarray, closing: np.ndarray) -> np.ndarray:
    """Samples from each window's closing heel strike (``hs[closing]``) to the next one (the
    median step where none follows)."""
    median = float(np.median(np.diff(hs))) if hs.size > 1 else 0.0
    after = np.where(closing + 1 < hs.size,
                     hs[np.minimum(closing + 1, hs.size - 1)] - hs[closing], median)  # fmt: skip
    return after.astype(float)


def artefact(locked: np.ndarray) -> dict[str, float]:
    """Where the library's soft-tissue artefact sits: of the harmonics its law allows, the one
    the trials' gait-locked encoder-against-motion-capture coefficients (trials × design of
    :func:`crosscheck.gait_locked`) show with the largest mean amplitude, and the phase ψ of
    their sum as an artefact a·sin(2πkφ + ψ) of motion capture (which the encoder, reading
    the knee, lacks: the coefficients' opposite)."""
    harmonics = crosscheck.PHASE_HARMONICS
    sines, cosines = locked[:, 1 : 1 + harmonics], locked[:, 1 + harmonics :]
    amplitude = np.hypot(sines, cosines).mean(axis=0)
    k = max(ARTEFACT_HARMONICS, key=lambda h: amplitude[h - 1])
    phase = np.arctan2(-cosines[:, k - 1].sum(), -sines[:, k - 1].sum())
    return {"harmonic": int(k), "phase_rad": float(phase)}


def impact_samples(velocity: np.ndarray, release_at: np.ndarray) -> np.ndarray:
    """Sample of each row at which the velocity (the chain's rebuilt causal estimate of the
    controller's) first falls after Table 6.1's release (ω_k < ω_k−1, k > the release): the
    impact peak Table 5.1's text takes for the heel strike (the row's width if none)."""
    k = np.arange(1, velocity.shape[1])[None, :]
    falls = (np.diff(velocity, axis=1) < 0.0) & (k > release_at[:, None])
    return np.where(falls.any(axis=1), np.argmax(falls, axis=1) + 1, velocity.shape[1]).astype(
        float
    )


def release_samples(active: np.ndarray) -> np.ndarray:
    """Sample of each row at which its last run of activity ends (the row's width if none)."""
    falls = np.diff(active.astype(int), axis=1) == -1
    last = falls.shape[1] - np.argmax(falls[:, ::-1], axis=1)
    return np.where(falls.any(axis=1), last, active.shape[1]).astype(float)


def encoder_count_deg(angle_deg: np.ndarray) -> float:
    """The encoder's count, read off the recording: the smallest step of the brace angle when
    every step is a whole number of it; else, where the file's rounding (10^−d for d decimals)
    blurs a count it does not write exactly (360°/4096 at 3 decimals), the mean of the
    single-count steps (up to 1.5 × the smallest), every step a whole number of counts to within
    that rounding; 0 if the angle is not quantised (a file written at a coarser precision than
    the count)."""
    steps = np.abs(np.diff(angle_deg))
    steps = steps[steps > 1e-6]
    if steps.size == 0:
        return 0.0
    count = float(steps.min())
    if np.mean(np.abs(steps / count - np.round(steps / count)) < 1e-3) > 0.99:
        return count
    count = float(np.mean(steps[steps < 1.5 * count]))
    rounding = 2.0 * 10.0 ** -decimals(angle_deg)  # each end of a step rounded
    whole = np.abs(steps - count * np.round(steps / count)) <= rounding + 1e-3 * count
    return count if whole.mean() > 0.99 else 0.0


def decimals(values: np.ndarray, most: int = 9) -> int:
    """The fewest decimals that write every finite value exactly (``most`` at most)."""
    values = np.asarray(values, float)
    values = values[np.isfinite(values)]
    for d in range(most + 1):
        scaled = values * 10.0**d
        if np.all(np.abs(scaled - np.round(scaled)) < 1e-6):
            return d
    return most


def energy_noise_J(arrays: Mapping, scales: Mapping) -> float:
    """Noise of the window energy −Σ τ̄·Δθ (median over steps): the measured and the predicted
    energy integrate over the same recorded encoder angle, so only the torque noise enters,
    σ² = σ_τ²·Σ Δθ² over active intervals (θ in rad)."""
    active = arrays["active"][:, :-1]
    dtheta = np.diff(arrays["encoder_deg"], axis=1) * DEG * active
    var = scales["torque"] ** 2 * np.sum(dtheta**2, 1)
    return float(np.sqrt(np.median(var))) or 1.0


def analyse(data: selection.Data, scales, engine: Mapping, seed: int, source: str,
            suspects: Sequence[str] = ()) -> dict:  # fmt: skip
    """The discrepancy report of the recordings (shared engine and schema; ``suspects``: the
    library terms a violated direct check sees)."""
    settings = selection.Settings.from_config(engine, seed)
    return selection.analyse(problem(drop_located(data)), data, scales, settings, source,
                             suspects)  # fmt: skip


def drop_located(data: selection.Data) -> bool:
    """Whether the QC located a count drop in any step the observations hold."""
    return bool(np.any(data.arrays["dropped_fine"]))


def reported_condition_12(reported: pd.DataFrame, equilibrium_deg: float, transmission: Mapping):
    """Why Heer's condition 12 stored more than condition 6, from the closed form ½κΔθ²."""
    rows = reported[reported["metric"] == "mean_energy_per_step_J"].set_index("condition")
    six, twelve = rows.loc[6], rows.loc[12]
    kappa = float(six["stiffness_Nm_per_rad"])
    deflection = {
        c: float(np.degrees(np.sqrt(2.0 * float(r["value"]) / float(r["stiffness_Nm_per_rad"]))))
        for c, r in ((6, six), (12, twelve))
    }
    extra = deflection[12] - deflection[6]
    ratio = transmission["brace_pulley_radius_m"] / transmission["motor_pulley_radius_m"]
    desired_per_deg = kappa * DEG
    set_point_per_deg = ratio / transmission["extension"]["C"]
    return {
        "deflection_deg": {"condition_6": deflection[6], "condition_12": deflection[12]},
        "implied_extra_deflection_deg": extra,
        "peak_extension_deg_if_no_fault": {
            "condition_6": equilibrium_deg - deflection[6],
            "condition_12": equilibrium_deg - deflection[12],
        },
        "desired_torque_change_Nm_per_deg_of_drop": desired_per_deg,
        "set_point_torque_change_Nm_per_deg_of_drop": -set_point_per_deg,
        "explanation": (
            f"With τ = κ·max(0, θ_eq − θ) the energy per step is ½κΔθ²: {float(six['value']):.3f} "
            f"J and {float(twelve['value']):.3f} J need "
            f"Δθ = {deflection[6]:.1f}° and {deflection[12]:.1f}°, i.e. the encoder read the knee "
            f"{extra:.1f}° further extended at 1.2 m/s. A count drop of that size raises the "
            f"desired torque by {desired_per_deg:.3f} N·m per degree. Had it happened during the "
            "trial, the position-based set point (eq. 5.6, A·θ_b) would also have let out cable, "
            f"lowering the delivered torque by {set_point_per_deg:.3f} N·m per degree, so the "
            "energy would have fallen; the increase fits a drop that predates the trial's "
            "transmission calibration (which re-fits D and absorbs it) while the spring's "
            "static-trial zero did not."
        ),
    }


def condition_12_note(reading: Mapping) -> list[str]:
    """The closed-form reading of condition 12 for the summary, with what it rests on."""
    return [
        f"{reading['explanation']} This reading rests on two reported numbers, the mean energies "
        f"per step of conditions 6 and 12 ({studies.EMULATOR.key}, Table 6.3), and on the "
        "spring law; the other cells of that table are not in the text."
    ]
