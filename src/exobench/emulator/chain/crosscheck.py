"""Brace encoder against motion capture: align the two sensors first, then look for count drops.

1. Clock: the lag δ that maximises the correlation of the two angles' increments, motion capture
   at its stamps s against the encoder at s − δ (1 ms grid over ±``MAX_CLOCK_S``, parabolic peak);
   increments ignore zero and gain. Once drops are found, δ is estimated again without them.
2. Encoder frame and drops: robust (Huber, iteratively reweighted) regression
   θ_enc(s − δ) = a + b·θ_mocap(s) + c·τ(s − δ) + Σ_k d_k·H(s − s_k) + e, whose a and b map
   motion capture onto the encoder.
3. Count drops: forward change-point search on θ_enc − b·θ_mocap, with gait-phase harmonics in
   the design so that a periodic soft-tissue artefact is not taken for drops. For every candidate
   onset the least-squares step size with the other regressors projected out follows from suffix
   sums (vectorised); among the candidates whose size reaches ``drop_threshold_sd`` × the trial's
   own noise (robust SD of the residual's increments / √2, blind to steps), the one that lowers
   the residual sum of squares most is added, until none is left. Candidates need only
   ``MIN_SIDE_S`` of recording on either side (and from other drops), so the first and last
   second are searched. Each drop is then timed and sized on the 1 kHz encoder's own jump, which
   must reach the same threshold (a step of the residual the encoder does not make is not a lost
   count); drops closer than the fit resolves make one step there and are told apart by their
   jumps.
4. Zero, gain, cuff (:func:`alignment`): motion capture regressed on the drop-corrected encoder
   with the gait-locked artefact modelled; a cuff compliance below zero is a misfit
   (:func:`bounded`). Intervals: delete-one-step jackknife (a step: heel strike to heel
   strike), every fit with its own clock — per-block lag correlations and weighted fits — and
   Student's t with K − 1 degrees of freedom (K steps). The encoder's rate term ε·θ'_enc takes
   up what the clock's error leaves locked to the gait; the harmonics (up to
   ``PHASE_HARMONICS``) enter only where Hotelling's T² with the jackknife's covariance rejects
   at ``artefact_alpha`` (with them, zero and gain rest on the steps' variation alone); the
   clock is held at the trial's value in the jackknife (its lag peak is not smooth). Zero and
   gain intervals are the calibrated ones; the clock's and the cuff's are reported as jackknife
   intervals, not calibrated (``intervals_calibrated`` in qc.json).
"""

from __future__ import annotations

from collections.abc import Mapping

import numpy as np
from scipy.special import fdtrc, stdtrit  # F's tail, Student's t quantile (scipy.stats' own)

MAX_CLOCK_S = 0.25  # clock offsets searched: ±250 ms
LAG_STEP_S = 0.001
# half the span of the encoder rate's central difference in the alignment: 5 samples at the
# brace's 1 kHz, a numerical step, not a physical threshold
SLOPE_S = 0.005
MIN_SIDE_S = 0.1  # a count drop needs this much recording on either side
MAX_DROPS = 10
# the encoder increments around a jump whose median is the knee's own motion: five before it,
# three after
JUMP_OFFSETS = np.array([-5, -4, -3, -2, -1, 1, 2, 3])
JUMP_HOLD = 3  # samples after a jump over which a drop's shift must stay
HUBER_K = 1.345  # Huber tuning constant (95 % efficiency under normal errors)
ROBUST_ITERATIONS = 10
PHASE_HARMONICS = 4  # the search models a periodic soft-tissue artefact up to this harmonic


def _interval(estimate: float, left_out: np.ndarray) -> list[float]:
    """95 % delete-one-step jackknife interval: estimate ± t₀.₉₇₅,ₖ₋₁·√((K−1)/K·Σ(θ₍ᵢ₎ − θ̄)²)."""
    k = len(left_out)
    se = np.sqrt((k - 1) / k * np.sum((left_out - left_out.mean()) ** 2))
    half = float(stdtrit(k - 1, 0.975) * se)
    return [estimate - half, estimate + half]


def robust_sd(values: np.ndarray) -> float:
    """Normal-consistent median absolute deviation."""
    return float(1.4826 * np.median(np.abs(values - np.median(values))))


def clock_correlation(stamps, mocap_deg, t, encoder_deg, lags_s, blocks) -> tuple:
    """Per-block sums (lags × blocks) of increment cross-products, encoder and mocap squares."""
    shifted = np.interp(stamps[None, :] - lags_s[:, None], t, encoder_deg)
    d_enc = np.diff(shifted, axis=1)
    d_mocap = np.diff(mocap_deg)
    member = (blocks[1:, None] == np.arange(int(blocks.max()) + 1)[None, :]).astype(float)
    return (d_enc * d_mocap) @ member, d_enc**2 @ member, d_mocap**2 @ member


def _peak_lag(correlation: np.ndarray, lags_s: np.ndarray) -> np.ndarray:
    """Lag of the largest correlation per row, refined by a parabola through its neighbours."""
    k = np.clip(np.argmax(correlation, axis=-1), 1, len(lags_s) - 2)
    rows = np.arange(correlation.shape[0])
    left, mid, right = (correlation[rows, k + j] for j in (-1, 0, 1))
    curvature = left - 2.0 * mid + right
    shift = np.where(curvature < 0, 0.5 * (left - right) / np.where(curvature < 0, curvature, 1), 0)
    return lags_s[k] + np.clip(shift, -1.0, 1.0) * LAG_STEP_S


def _huber_fit(x: np.ndarray, y: np.ndarray) -> tuple[np.ndarray, np.ndarray, float]:
    """Huber regression by iteratively reweighted least squares: coefficients, weights, scale."""
    weights = np.ones(len(y))
    coef = np.linalg.lstsq(x, y, rcond=None)[0]
    scale = 1.0
    for _ in range(ROBUST_ITERATIONS):
        residual = y - x @ coef
        scale = max(robust_sd(residual), 1e-9)
        u = np.abs(residual) / (HUBER_K * scale)
        weights = np.where(u <= 1.0, 1.0, 1.0 / np.maximum(u, 1e-12))
        sw = np.sqrt(weights)
        coef = np.linalg.lstsq(x * sw[:, None], y * sw, rcond=None)[0]
    return coef, weights, scale


def gait_phase(stamps: np.ndarray, heel_strikes_s: np.ndarray) -> np.ndarray:
    """Gait-cycle phase (0–1) at each stamp from heel strikes; edge strides extrapolated."""
    if len(heel_strikes_s) < 2:
        return np.zeros(len(stamps))
    k = np.clip(
        np.searchsorted(heel_strikes_s, stamps, side="right") - 1, 0, len(heel_strikes_s) - 2
    )
    stride = heel_strikes_s[k + 1] - heel_strikes_s[k]
    return np.mod((stamps - heel_strikes_s[k]) / stride, 1.0)


def _harmonics(phase: np.ndarray) -> np.ndarray:
    """sin and cos of the first ``PHASE_HARMONICS`` harmonics of the gait phase."""
    h = 2.0 * np.pi * np.arange(1, PHASE_HARMONICS + 1)[None, :] * phase[:, None]
    return np.column_stack([np.sin(h), np.cos(h)])


def gait_locked(phase: np.ndarray, values: np.ndarray, keep: np.ndarray) -> np.ndarray:
    """Least-squares coefficients of the kept samples of ``values`` on the gait phase: a
    constant, then sin(2πkφ) and cos(2πkφ) for k = 1 … ``PHASE_HARMONICS`` (as
    :func:`locked_design` orders them)."""
    design = locked_design(phase)
    return np.linalg.lstsq(design[keep], values[keep], rcond=None)[0]


def locked_design(phase: np.ndarray) -> np.ndarray:
    """The design of :func:`gait_locked`: 1, sin(2πkφ) (k = 1 … K), cos(2πkφ) (k = 1 … K)."""
    return np.column_stack([np.ones_like(phase), _harmonics(phase)])


def best_step(x: np.ndarray, residual: np.ndarray, s: np.ndarray, threshold: float, taken,
              side: float = MIN_SIDE_S):  # fmt: skip
    """Onset index and size of the step that lowers the RSS most among those ≥ threshold.

    Onsets need ``side`` (s) to the ends of the recording and to the onsets ``taken`` (0: one
    point on either side, and none taken).
    """
    gram_inv = np.linalg.pinv(x.T @ x)
    residual = residual - x @ (gram_inv @ (x.T @ residual))  # least-squares residual
    x_suffix = np.cumsum(x[::-1], axis=0)[::-1]
    r_suffix = np.cumsum(residual[::-1])[::-1]
    count = np.arange(len(s), 0, -1, dtype=float)
    h_norm = count - np.einsum("ni,ij,nj->n", x_suffix, gram_inv, x_suffix)
    valid = (s - s[0] >= side) & (s[-1] - s >= side - 1e-9) & (h_norm > 1e-6)
    for k in taken:
        valid &= np.abs(s - s[k]) >= side
    size = np.where(valid, r_suffix / np.where(valid, h_norm, 1.0), 0.0)
    gain = np.where(valid & (np.abs(size) >= threshold), size * r_suffix, -np.inf)
    k = int(np.argmax(gain))
    return (k, float(size[k])) if np.isfinite(gain[k]) else (None, 0.0)


def _jumps_on_encoder(t, encoder_deg, s_before, s_at, step_deg, threshold_deg) -> list[tuple]:
    """Times and sizes of the encoder's jumps that make one step of the fit near two stamps.

    The controller's reaction to a drop blurs the step in the 100 Hz residual; the 1 kHz encoder
    jumps in one sample, so the jumps are sought within ``MIN_SIDE_S`` of the stamps. A size is
    the jump less the median of the neighbouring increments (the knee's own motion). The largest
    jump of the step's sign is a drop when its size reaches ``threshold_deg`` (a step the encoder
    does not make is no lost count: two clocks drifting apart step the residual at a recording's
    ends while the encoder moves one count); another is one too (two drops the fit cannot
    split) when both its size and the shift it leaves ``JUMP_HOLD`` samples later, the motion
    taken out, reach ``threshold_deg``: a one-sample glitch comes back, a lost count does not.
    """
    window = np.flatnonzero((t >= s_before - MIN_SIDE_S) & (t <= s_at + MIN_SIDE_S))
    at = window[:-1]
    sign = np.sign(step_deg)
    sizes, shifts = jumps(encoder_deg, at, sign)
    largest = int(np.argmax(sign * np.diff(encoder_deg)[at]))
    seen = np.array([largest] if sizes[largest] >= threshold_deg else [], dtype=int)
    drops = np.union1d(seen, np.flatnonzero((sizes >= threshold_deg) & (shifts >= threshold_deg)))
    return [(float(t[at[i] + 1]), float(sign * sizes[i])) for i in drops]


def jumps(encoder_deg: np.ndarray, at: np.ndarray, sign: float) -> tuple[np.ndarray, np.ndarray]:
    """The encoder's jump from each sample ``at`` to the next, in the direction ``sign``, less
    the knee's own motion (median of the neighbouring increments), and the shift it leaves
    ``JUMP_HOLD`` samples later, the motion taken out: a lost count stays, a glitch returns."""
    increments = np.diff(encoder_deg)
    neighbours = np.clip(at[:, None] + JUMP_OFFSETS[None, :], 0, len(increments) - 1)
    motion = np.median(increments[neighbours], axis=1)
    after = np.minimum(at + 1 + JUMP_HOLD, len(encoder_deg) - 1)
    shifts = sign * (encoder_deg[after] - encoder_deg[at] - (after - at) * motion)
    return sign * (increments[at] - motion), shifts


def _clocks(stamps, mocap_deg, t, encoder_deg, blocks, counts) -> np.ndarray:
    """Clock offset of the whole trial, then of every weighting of its blocks (``counts``)."""
    lags = np.arange(-MAX_CLOCK_S, MAX_CLOCK_S + LAG_STEP_S / 2, LAG_STEP_S)
    cross, enc_sq, mocap_sq = clock_correlation(stamps, mocap_deg, t, encoder_deg, lags, blocks)
    weights = np.vstack([np.ones(len(mocap_sq)), counts])
    correlation = (weights @ cross.T) / np.sqrt(
        (weights @ enc_sq.T) * (weights @ mocap_sq)[:, None]
    )
    return _peak_lag(correlation, lags)


def _regression(stamps, mocap_deg, t, encoder_deg, torque_Nm, phase, clock, threshold_sd):
    """Robust regression at the stamps (encoder and torque at s − δ): coefficients, noise scale
    and the drops' onsets."""
    y = np.interp(stamps - clock, t, encoder_deg)
    tau = np.interp(stamps - clock, t, torque_Nm)
    x = np.column_stack([np.ones_like(stamps), mocap_deg, tau])
    # the search runs on y − b·θ_mocap with a periodic artefact (gait-phase harmonics) modelled,
    # so that its residual, and the threshold, are the trial's own noise
    search = np.column_stack([np.ones_like(stamps), tau, _harmonics(phase)])
    onsets: list[int] = []
    while True:
        coef, _, _ = _huber_fit(x, y)
        d = y - coef[1] * mocap_deg
        local, _, _ = _huber_fit(search, d)
        # noise from increments: a drop not yet modelled does not inflate it
        scale = robust_sd(np.diff(d - search @ local)) / np.sqrt(2.0)
        if len(onsets) == MAX_DROPS:
            break
        k, _ = best_step(search, d - search @ local, stamps, threshold_sd * scale, onsets)
        if k is None:
            break
        onsets.append(k)
        step = (np.arange(len(stamps)) >= k).astype(float)
        x, search = np.column_stack([x, step]), np.column_stack([search, step])
    # backward pruning: a step that shrank below the threshold once the others were in is not one
    while onsets and np.min(np.abs(coef[3:])) < threshold_sd * scale:
        weakest = int(np.argmin(np.abs(coef[3:])))
        onsets.pop(weakest)
        x = np.delete(x, 3 + weakest, axis=1)
        coef, _, _ = _huber_fit(x, y)
    return coef, scale, onsets


def fit(
    stamps: np.ndarray,
    mocap_deg: np.ndarray,
    t: np.ndarray,
    encoder_deg: np.ndarray,
    torque_Nm: np.ndarray,
    heel_strikes_s: np.ndarray,
    drop_threshold_sd: float,
    artefact_alpha: float,
) -> dict:
    """Clock δ, count drops, then :func:`alignment` at δ (docs/emulator.md); motion-capture
    frames that are NaN (gaps, masked) are left out."""
    held = np.isfinite(mocap_deg)
    stamps, mocap_deg = stamps[held], mocap_deg[held]
    blocks = np.searchsorted(heel_strikes_s, stamps, side="right")
    n_blocks = int(blocks.max()) + 1
    counts = 1.0 - np.eye(n_blocks)  # the jackknife's weights: every step but one
    phase = gait_phase(stamps, heel_strikes_s)
    clocks = _clocks(stamps, mocap_deg, t, encoder_deg, blocks, counts)
    args = (stamps, mocap_deg, t, encoder_deg, torque_Nm, phase)
    coef, scale, onsets = _regression(*args, float(clocks[0]), drop_threshold_sd)
    threshold = drop_threshold_sd * scale
    drops = _drops(t, encoder_deg, stamps, float(clocks[0]), onsets, coef, threshold)
    if drops:
        corrected = encoder_deg - encoder_error(t, {"count_drops": drops})
        clocks = _clocks(stamps, mocap_deg, t, corrected, blocks, counts)
        coef, scale, onsets = _regression(*args, float(clocks[0]), drop_threshold_sd)
        threshold = drop_threshold_sd * scale
        drops = _drops(t, encoder_deg, stamps, float(clocks[0]), onsets, coef, threshold)
    corrected = encoder_deg - encoder_error(t, {"count_drops": drops})
    found = alignment(
        stamps,
        mocap_deg,
        t,
        corrected,
        torque_Nm,
        phase,
        np.full(len(clocks), clocks[0]),  # the lag's peak is not smooth: held at the trial's
        blocks,
        counts,
        artefact_alpha,
    )
    return {
        "clock_offset_s": float(clocks[0]),
        # the jackknife's t interval of the clock, not calibrated (docs/emulator.md)
        "clock_offset_jackknife_s": _interval(float(clocks[0]), clocks[1:]),
        **found,
        # which intervals are calibrated 95 % intervals (coverage checked, docs/emulator.md)
        "intervals_calibrated": {
            "mocap_zero_ci95_deg": True,
            "mocap_gain_ci95": True,
            "clock_offset_jackknife_s": False,
            "cuff_compliance_jackknife_deg_per_Nm": False,
        },
        "encoder_offset_deg": float(coef[0]),
        "encoder_scale": float(coef[1]),
        "residual_sd_deg": float(scale),
        "drop_threshold_deg": float(threshold),
        "count_drops": drops,
    }


def alignment(
    stamps, mocap_deg, t, encoder_deg, torque_Nm, phase, clocks, blocks, counts, artefact_alpha
) -> dict:
    """θ_mocap = z + g·θ_enc − g·c·τ + ε·θ'_enc [+ harmonics if T² rejects at α]; jackknife CIs."""
    lagged = stamps[None, :] - clocks[:, None]
    # θ_enc, τ and the encoder's rate (central difference over ±SLOPE_S), which takes up what
    # the clock's error leaves locked to the gait: θ(s − δ − ε) ≈ θ(s − δ) − ε·θ'(s − δ)
    rate = (
        np.interp(lagged + SLOPE_S, t, encoder_deg) - np.interp(lagged - SLOPE_S, t, encoder_deg)
    ) / (2.0 * SLOPE_S)
    moving = np.stack(
        [np.interp(lagged, t, encoder_deg), np.interp(lagged, t, torque_Nm), rate], -1
    )
    fixed = np.column_stack([np.ones_like(stamps), _harmonics(phase)])
    weights = np.vstack([np.ones(len(stamps)), counts[:, blocks]])
    # the normal equations by parts, fixed columns F (1, harmonics) and the clock's V (θ_enc, τ)
    wv = np.swapaxes(moving * weights[..., None], 1, 2)
    ff = (weights @ (fixed[:, :, None] * fixed[:, None, :]).reshape(len(stamps), -1)).reshape(
        len(clocks), fixed.shape[1], fixed.shape[1]
    )
    vf = wv @ fixed
    gram = np.block([[ff, np.swapaxes(vf, 1, 2)], [vf, wv @ moving]])
    moment = np.concatenate([weights @ (fixed * mocap_deg[:, None]), wv @ mocap_deg], axis=1)
    k = fixed.shape[1]
    coef = np.linalg.solve(gram, moment[..., None])[..., 0]
    # the artefact's harmonics jointly against zero: Hotelling's T² with the jackknife's
    # covariance (which holds the residuals' correlation within steps), F(q, K − q)
    harmonic, q = coef[:, 1:k], k - 1
    p_artefact = None  # too few steps to test (K − 1 ≤ q): the artefact is not modelled
    if len(harmonic) - 1 > q:
        n = len(harmonic) - 1
        spread = harmonic[1:] - harmonic[1:].mean(axis=0)
        covariance = (n - 1) / n * spread.T @ spread
        t2 = float(harmonic[0] @ np.linalg.solve(covariance, harmonic[0]))
        p_artefact = float(fdtrc(q, n - q, (n - q) / (q * (n - 1)) * t2))
    modelled = p_artefact is not None and p_artefact < artefact_alpha
    if not modelled:  # no artefact found: zero, gain and cuff alone
        keep = np.r_[0, k, k + 1, k + 2]
        reduced = gram[:, keep][:, :, keep]
        coef = np.zeros_like(coef)
        coef[:, keep] = np.linalg.solve(reduced, moment[:, keep, None])[..., 0]
    zero, gain, cuff = coef[:, 0], coef[:, k], -coef[:, k + 1] / coef[:, k]
    return {
        "mocap_zero_deg": float(zero[0]),
        "mocap_zero_ci95_deg": _interval(float(zero[0]), zero[1:]),
        "mocap_gain": float(gain[0]),
        "mocap_gain_ci95": _interval(float(gain[0]), gain[1:]),
        "cuff_compliance_deg_per_Nm": float(cuff[0]),
        # the static term's jackknife interval: not calibrated, the cuffs' lag is not modelled
        "cuff_compliance_jackknife_deg_per_Nm": _interval(float(cuff[0]), cuff[1:]),
        "artefact_p": p_artefact,
        "artefact_modelled": modelled,
    }


def bounded(result: Mapping) -> dict:
    """The cuff compliance as an estimate, or, below zero (the brace cannot lead the limb it is
    strapped to), a model misfit reported with its fit and interval instead of an estimate."""
    value = result["cuff_compliance_deg_per_Nm"]
    if value >= 0.0:
        return {"cuff_compliance_deg_per_Nm": value, "cuff_compliance_misfit": None}
    return {
        "cuff_compliance_deg_per_Nm": None,
        "cuff_compliance_misfit": {
            "fitted_deg_per_Nm": value,
            "jackknife_deg_per_Nm": result["cuff_compliance_jackknife_deg_per_Nm"],
            "reason": (
                "below zero: the brace would lead the limb under the spring's torque; the "
                "static cuff term c·τ does not describe this trial (too little torque to size "
                "it, or the cuffs' dynamics), so it is a misfit, not an estimate"
            ),
        },
    }


def _drops(t, encoder_deg, stamps, clock, onsets, coef, threshold_deg) -> list[dict]:
    """The drops in time order: onset and size from the encoder's jumps, size from the fit (the
    fit's one step, shared by drops it cannot tell apart); a jump seen near two steps belongs
    to the nearer one."""
    found: dict[float, tuple[float, dict]] = {}
    for i, k in enumerate(onsets):
        at = stamps[k] - clock
        jumps = _jumps_on_encoder(
            t, encoder_deg, stamps[k - 1] - clock, at, coef[3 + i], threshold_deg
        )
        for time, size in jumps:
            drop = {"time_s": time, "size_deg": size, "size_from_mocap_deg": float(coef[3 + i])}
            if time not in found or abs(time - at) < found[time][0]:
                found[time] = (abs(time - at), drop)
    return [found[time][1] for time in sorted(found)]


def encoder_frame(t: np.ndarray, stamps: np.ndarray, mocap_deg: np.ndarray, result: Mapping):
    """Motion capture mapped onto the encoder's clock and scale: a + b·θ_mocap(t + δ)."""
    shifted = np.interp(t + result["clock_offset_s"], stamps, mocap_deg)
    return result["encoder_offset_deg"] + result["encoder_scale"] * shifted


def encoder_error(t: np.ndarray, result: Mapping) -> np.ndarray:
    """Encoder error from the count drops found in the trial: Σ d_k·H(t − t_k)."""
    drops = result["count_drops"]
    onsets = np.array([d["time_s"] for d in drops])
    sizes = np.array([d["size_deg"] for d in drops])
    return (t[:, None] >= onsets[None, :]) @ sizes if drops else np.zeros(len(t))


def verdict(result: Mapping) -> dict:
    """Fault if the trial has count drops: the first drop's time."""
    drops = result["count_drops"]
    if drops:
        return {"encoder_fault": True, "fault_time_s": drops[0]["time_s"], "fault_kinds": ["drop"]}
    return {"encoder_fault": False, "fault_time_s": None, "fault_kinds": []}
