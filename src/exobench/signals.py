"""Butterworth low-passes, causal and zero-phase, for both groups' per-trial chains.

Designed from the analog prototype's poles by the prewarped bilinear transform, as second-order
sections; each section runs as a banded lower-triangular solve (LAPACK ``tbtrs``), so the chains
need not import ``scipy.signal`` (SciPy 1.17 builds every one of its docstrings at import: about
1.4 s of each per-trial job's start). Tests hold every function to ``scipy.signal``'s.
"""

from __future__ import annotations

import numpy as np


def butterworth(order: int, cutoff_Hz: float, rate_Hz: float) -> np.ndarray:
    """Second-order sections [b₀ b₁ b₂ 1 a₁ a₂] of the digital Butterworth low-pass: analog
    poles ω·e^{iπ(2k+n+1)/(2n)}, ω = 2f_s·tan(πf_c/f_s), mapped by z = (2f_s + p)/(2f_s − p),
    zeros at z = −1, unit gain at DC."""
    if not 0.0 < cutoff_Hz < rate_Hz / 2.0:
        raise ValueError(f"low-pass cut-off {cutoff_Hz} Hz: expected in (0, {rate_Hz / 2} Hz)")
    two_fs = 2.0 * rate_Hz
    omega = two_fs * np.tan(np.pi * cutoff_Hz / rate_Hz)
    k = np.arange(order)
    analog = omega * np.exp(1j * np.pi * (2 * k + order + 1) / (2 * order))
    poles = (two_fs + analog) / (two_fs - analog)
    # k < n/2: the upper pole of each conjugate pair; k = (n − 1)/2 of an odd order: −ω, real
    rows = [[1.0, 2.0, 1.0, 1.0, -2.0 * p.real, abs(p) ** 2] for p in poles[: order // 2]]
    if order % 2:
        rows.append([1.0, 1.0, 0.0, 1.0, -(two_fs - omega) / (two_fs + omega), 0.0])
    sos = np.array(rows, dtype=float)
    sos[:, :3] *= (sos[:, 3:].sum(axis=1) / sos[:, :3].sum(axis=1))[:, None]
    return sos


def settled_state(section: np.ndarray) -> np.ndarray:
    """State (z₁, z₂) of a section [b₀ b₁ b₂ 1 a₁ a₂] (transposed direct form II) settled on a
    unit input: with G = Σb/(1 + a₁ + a₂), z₂ = b₂ − a₂G and z₁ = b₁ − a₁G + z₂."""
    b0, b1, b2, _, a1, a2 = section
    gain = (b0 + b1 + b2) / (1.0 + a1 + a2)
    z2 = b2 - a2 * gain
    return np.array([b1 - a1 * gain + z2, z2])


def causal(section: np.ndarray, x: np.ndarray, state: np.ndarray | None = None) -> np.ndarray:
    """One section [b₀ b₁ b₂ 1 a₁ a₂] along axis 0, from state (z₁, z₂) stacked on axis 0
    (zero when None):
    y_n + a₁y_(n−1) + a₂y_(n−2) = b₀x_n + b₁x_(n−1) + b₂x_(n−2), solved as one banded system."""
    from scipy.linalg.lapack import dtbtrs  # here: every DAG build imports the readers

    b0, b1, b2, _, a1, a2 = section
    x = np.asarray(x, dtype=float)
    drive = b0 * x
    drive[1:] += b1 * x[:-1]
    drive[2:] += b2 * x[:-2]
    if state is not None:
        drive[0] += state[0]
        drive[1:2] += state[1]
    n = x.shape[0]
    band = np.zeros((3, n))
    band[0], band[1, :-1], band[2, :-2] = 1.0, a1, a2
    flat = drive.reshape(n, -1)
    y, info = dtbtrs(band, flat, uplo="L")
    if info != 0:
        raise np.linalg.LinAlgError(f"tbtrs failed (info {info})")
    return y.reshape(x.shape)


def cascade(sos: np.ndarray, x: np.ndarray, settle_on: np.ndarray | None = None) -> np.ndarray:
    """Sections in turn along axis 0; ``settle_on``: each starts settled on that value per column
    (the input's DC level carried through the sections before it), else at rest."""
    level = None if settle_on is None else np.asarray(settle_on, dtype=float)
    for section in sos:
        state = None if level is None else np.multiply.outer(settled_state(section), level)
        x = causal(section, x, state)
        if level is not None:
            level = level * section[:3].sum() / (1.0 + section[4] + section[5])
    return x


def zero_phase(sos: np.ndarray, x: np.ndarray) -> np.ndarray:
    """Forward–backward filter along axis 0, as ``scipy.signal.sosfiltfilt``: odd extension by
    3·(2·sections + 1 − trivial orders) samples each end, each pass settled on its first value."""
    x = np.asarray(x, dtype=float)
    taps = 2 * len(sos) + 1 - min(int((sos[:, 2] == 0).sum()), int((sos[:, 5] == 0).sum()))
    pad = 3 * taps
    if x.shape[0] <= pad:
        raise ValueError(f"{x.shape[0]} samples: a zero-phase pass needs more than {pad}")
    head = 2.0 * x[0] - x[pad:0:-1]
    tail = 2.0 * x[-1] - x[-2 : -pad - 2 : -1]
    extended = np.concatenate([head, x, tail])
    forward = cascade(sos, extended, extended[0])
    backward = cascade(sos, forward[::-1], forward[-1])
    return backward[::-1][pad:-pad]
