"""Brace encoder against motion capture: offset, drift, cuff lag and a step (count drop).

The difference d = θ_encoder − θ_mocap at the motion-capture samples is modelled as
d = offset + drift·t + compliance·τ_brace + step·H(t − t₀): the brace lags the limb in proportion
to its torque through the cuffs, and a count drop is a step. For every candidate t₀ the step's
least-squares size follows from suffix sums once the other regressors are projected out, so the
whole search is vectorised; t₀ is where the residual sum of squares falls most.
"""

from __future__ import annotations

import numpy as np

MIN_SIDE_S = 1.0  # a step needs this much recording on either side


def _design(t: np.ndarray, torque: np.ndarray) -> np.ndarray:
    return np.column_stack([np.ones_like(t), t - t[0], torque])


def fit(t: np.ndarray, difference_deg: np.ndarray, torque_Nm: np.ndarray) -> dict:
    """Offset, drift, compliance and the best single step of ``difference_deg`` (module doc)."""
    x = _design(t, torque_Nm)
    gram_inv = np.linalg.inv(x.T @ x)
    residual = difference_deg - x @ (gram_inv @ (x.T @ difference_deg))
    # ⟨X, H_t0⟩ and ⟨r, H_t0⟩ for a step starting at each sample: suffix sums
    x_suffix = np.cumsum(x[::-1], axis=0)[::-1]
    r_suffix = np.cumsum(residual[::-1])[::-1]
    count = np.arange(len(t), 0, -1, dtype=float)
    h_norm = count - np.einsum("ni,ij,nj->n", x_suffix, gram_inv, x_suffix)
    valid = (t - t[0] >= MIN_SIDE_S) & (t[-1] - t >= MIN_SIDE_S) & (h_norm > 1e-9)
    gain = np.where(valid, r_suffix**2 / np.where(valid, h_norm, 1.0), -np.inf)
    k = int(np.argmax(gain))
    full = np.column_stack([x, (np.arange(len(t)) >= k).astype(float)])
    coef, *_ = np.linalg.lstsq(full, difference_deg, rcond=None)
    rest = difference_deg - full @ coef
    return {
        "offset_deg": float(coef[0]),
        "drift_deg_per_min": float(60.0 * coef[1]),
        "compliance_deg_per_Nm": float(coef[2]),
        "step_deg": float(coef[3]),
        "step_time_s": float(t[k]),
        "time_origin_s": float(t[0]),
        "residual_sd_deg": float(np.std(rest)),
    }


def encoder_error(t: np.ndarray, result: dict) -> np.ndarray:
    """Encoder error against motion capture without the torque term: offset, drift, step."""
    return (
        result["offset_deg"]
        + result["drift_deg_per_min"] / 60.0 * (t - result["time_origin_s"])
        + result["step_deg"] * (t >= result["step_time_s"])
    )


def verdict(result: dict, threshold_deg: float, start_s: float) -> dict:
    """Fault if the step or the offset reaches the threshold; the fault's time and size."""
    if abs(result["step_deg"]) >= threshold_deg:
        return {"encoder_fault": True, "fault_time_s": result["step_time_s"], "fault_kind": "step"}
    if abs(result["offset_deg"]) >= threshold_deg:
        return {"encoder_fault": True, "fault_time_s": start_s, "fault_kind": "offset"}
    return {"encoder_fault": False, "fault_time_s": None, "fault_kind": None}


def corrected_angle(t: np.ndarray, angle_deg: np.ndarray, result: dict, fault: dict):
    """Encoder angle with the detected fault removed (the step, or the offset from the start)."""
    if fault["fault_kind"] == "step":
        return angle_deg - result["step_deg"] * (t >= result["step_time_s"])
    if fault["fault_kind"] == "offset":
        return angle_deg - result["offset_deg"]
    return angle_deg
