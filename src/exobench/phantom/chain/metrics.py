"""Per-stride metrics of seed 000 §2.4 and §3, vectorised over strides (rows) and samples."""

from __future__ import annotations

from collections.abc import Mapping

import numpy as np
import pandas as pd

COMPONENTS = ("knee", "exoskeleton", "interface", "spring", "frame")
WORK_KINDS = ("positive", "negative", "net")
WORK_COLUMNS = tuple(f"work_{c}_{k}_J" for c in COMPONENTS for k in WORK_KINDS)
# Stance metrics shaped by the compliances in series with the spring (fitted and predicted).
STANCE_METRICS = (
    "peak_moment_Nm",
    "phantom_stiffness_Nm_per_rad",
    "exo_stiffness_Nm_per_rad",
    "exo_stance_flexion_deg",
)
# Slope metrics (a moment over an angle's loading excursion) and the excursion each rests on.
SLOPES = {
    "phantom_stiffness_Nm_per_rad": "phantom_loading_excursion_deg",
    "exo_stiffness_Nm_per_rad": "exo_loading_excursion_deg",
}
# The measured signals the power partition takes, in its argument order (then spring length).
SIGNALS = ("knee_moment_Nm", "phantom_knee_angle_rad", "exo_knee_angle_rad", "spring_force_N")


def rate(values: np.ndarray, dt_s: float) -> np.ndarray:
    """Time derivative along the samples axis (second-order central differences)."""
    return np.gradient(values, dt_s, axis=-1)


def power_partition(moment, phantom_rad, exo_rad, force, length, dt_s) -> dict[str, np.ndarray]:
    """Knee, exoskeleton, interface, spring and frame power (W), seed 000 eqs. (2.3)–(2.4).

    Sign convention of seed 000 §3.5: power is what a component delivers to the knee, so the
    extensor moment M multiplies the extension rate −θ̇ (θ = flexion) and the spring power is
    −F·l̇. Negative work = energy absorbed (or dissipated) by the component, positive = returned.
    P_interface = P_knee − P_exoskeleton and P_frame = P_exoskeleton − P_spring close the partition.
    """
    knee = -moment * rate(phantom_rad, dt_s)
    exo = -moment * rate(exo_rad, dt_s)
    spring = -force * rate(length, dt_s)
    return {
        "knee": knee,
        "exoskeleton": exo,
        "interface": knee - exo,
        "spring": spring,
        "frame": exo - spring,
    }


def work(power: np.ndarray, window: np.ndarray, dt_s: float) -> dict[str, np.ndarray]:
    """Positive, negative and net work (J) of each stride over the samples in ``window``."""
    inside = power[..., window]
    return {
        "positive": np.maximum(inside, 0.0).sum(-1) * dt_s,
        "negative": np.minimum(inside, 0.0).sum(-1) * dt_s,
        "net": inside.sum(-1) * dt_s,
    }


def masked_slope(x: np.ndarray, y: np.ndarray, mask: np.ndarray) -> np.ndarray:
    """Least-squares slope of y on x per row over the samples in ``mask`` (NaN if < 3 samples)."""
    count = mask.sum(-1)
    with np.errstate(invalid="ignore", divide="ignore"):
        x_mean = np.where(mask, x, 0.0).sum(-1) / count
        y_mean = np.where(mask, y, 0.0).sum(-1) / count
        dx = np.where(mask, x - x_mean[:, None], 0.0)
        dy = np.where(mask, y - y_mean[:, None], 0.0)
        slope = (dx * dy).sum(-1) / (dx * dx).sum(-1)
    return np.where(count >= 3, slope, np.nan)


def stride_metrics(signals: Mapping, powers: Mapping, dt_s: float, protocol: Mapping):
    """Stance flexion, peak moment, stiffnesses and the 15 work values of every stride.

    ``signals`` holds (strides, samples) arrays from the first sample of each stride:
    phantom_knee_angle_rad, exo_knee_angle_rad, knee_moment_Nm, spring_force_N; ``powers``
    the five component powers of :func:`power_partition` on the same grid.
    Stance flexion = peak minus initial angle in the clutch window (midstance); stiffness =
    slope of moment on angle from clutch engagement to the peak moment (spring loading).
    """
    phantom = signals["phantom_knee_angle_rad"]
    exo = signals["exo_knee_angle_rad"]
    moment = signals["knee_moment_Nm"]
    samples = phantom.shape[-1]
    pct = np.arange(samples) / samples * 100.0
    time = np.arange(samples) * dt_s
    clutch = (pct >= protocol["clutch_on_pct"]) & (pct < protocol["clutch_off_pct"])
    work_window = time < protocol["work_window_s"]
    engaged = {name: signals[name][:, clutch] for name in SIGNALS}  # the clutch window
    held = engaged["knee_moment_Nm"]
    loading = np.arange(held.shape[-1])[None, :] <= held.argmax(-1)[:, None]
    out = {
        "phantom_stance_flexion_deg": np.rad2deg(
            stance_flexion(engaged["phantom_knee_angle_rad"], phantom[:, 0])
        ),
        "exo_stance_flexion_deg": np.rad2deg(
            stance_flexion(engaged["exo_knee_angle_rad"], exo[:, 0])
        ),
        "peak_moment_Nm": moment[:, work_window].max(-1),
        "phantom_stiffness_Nm_per_rad": masked_slope(
            engaged["phantom_knee_angle_rad"], held, loading
        ),
        "exo_stiffness_Nm_per_rad": masked_slope(engaged["exo_knee_angle_rad"], held, loading),
        "phantom_loading_excursion_deg": np.rad2deg(
            excursion(engaged["phantom_knee_angle_rad"], loading)
        ),
        "exo_loading_excursion_deg": np.rad2deg(excursion(engaged["exo_knee_angle_rad"], loading)),
        "exo_phantom_peak_angle_difference_deg": np.rad2deg(
            (engaged["phantom_knee_angle_rad"] - engaged["exo_knee_angle_rad"]).max(-1)
        ),
        "peak_spring_force_N": engaged["spring_force_N"].max(-1),
    }
    for component in COMPONENTS:
        for kind, value in work(powers[component], work_window, dt_s).items():
            out[f"work_{component}_{kind}_J"] = value
    return out


def excursion(angle: np.ndarray, mask: np.ndarray) -> np.ndarray:
    """Range (max − min) of each row's angle over the samples in ``mask``."""
    inside = np.where(mask, angle, np.nan)
    with np.errstate(invalid="ignore"):
        return np.nanmax(inside, -1) - np.nanmin(inside, -1)


def min_excursion_deg(validity: Mapping) -> float:
    """Smallest valid loading excursion Δθ = √2·σ_θ/r, σ_θ = 2σ_m/L·√s (config: the derivation)."""
    sigma = 2.0 * float(validity["marker_noise_sd_mm"]) / float(validity["marker_spacing_mm"])
    sigma *= np.sqrt(float(validity["noise_bandwidth_share"]))
    return float(np.rad2deg(np.sqrt(2.0) * sigma / float(validity["max_relative_error"])))


def validate_slopes(table: pd.DataFrame, validity: Mapping) -> pd.DataFrame:
    """Slopes whose loading excursion is not ≥ Δθ (:func:`min_excursion_deg`) left out (NaN)."""
    threshold = min_excursion_deg(validity)
    out = table.copy()
    for slope, angle in SLOPES.items():
        out.loc[~(out[angle] >= threshold), slope] = np.nan
    return out


def invalid_counts(table: pd.DataFrame, validity: Mapping) -> pd.DataFrame:
    """Per slope metric and spring, included strides left out: excursion not ≥ Δθ (as validated)."""
    threshold = min_excursion_deg(validity)
    kept = table[table["included"].astype(bool)]
    rows = []
    for slope, angle in SLOPES.items():
        below = ~(kept[angle] >= threshold)
        for spring, count in below.groupby(kept["spring_stiffness_N_per_m"]).sum().items():
            rows.append({"metric": slope, "spring_stiffness_N_per_m": spring,
                         "invalid": int(count)})  # fmt: skip
    return pd.DataFrame(rows, columns=["metric", "spring_stiffness_N_per_m", "invalid"])


def stance_flexion(window_rad: np.ndarray, initial_rad: np.ndarray) -> np.ndarray:
    """Peak angle in the clutch (midstance) window minus the stride's initial angle."""
    return window_rad.max(-1) - initial_rad


METRIC_COLUMNS = (
    "phantom_stance_flexion_deg",
    "exo_stance_flexion_deg",
    "peak_moment_Nm",
    "phantom_stiffness_Nm_per_rad",
    "exo_stiffness_Nm_per_rad",
    "exo_phantom_peak_angle_difference_deg",
    *WORK_COLUMNS,
)
EXCURSION_COLUMNS = tuple(SLOPES.values())


def metrics_table(
    trial: str,
    spring: float,
    strides: pd.DataFrame,
    kinetics: pd.DataFrame,
    dt_s: float,
    protocol: Mapping,
    validity: Mapping,
) -> pd.DataFrame:
    """One row per stride: inclusion, reason, metrics (slopes validated) and loading excursions."""
    numbers = kinetics["stride"].unique()
    arrays = {c: kinetics[c].to_numpy().reshape(numbers.size, -1) for c in kinetics.columns}
    powers = {c: arrays[f"power_{c}_W"] for c in COMPONENTS}
    per = stride_metrics(arrays, powers, dt_s, protocol)
    table = pd.DataFrame(
        {
            "trial": trial,
            "spring_stiffness_N_per_m": float(spring),
            "stride": strides["stride"].to_numpy(),
            "included": strides["included"].to_numpy(),
            "exclusion_reason": strides["exclusion_reason"].to_numpy(),
        }
    )
    position = pd.Index(numbers).get_indexer(table["stride"])
    found = position >= 0
    for column in (*METRIC_COLUMNS, *EXCURSION_COLUMNS):
        values = np.full(len(table), np.nan)
        values[found] = per[column][position[found]]
        table[column] = values
    return validate_slopes(table, validity)
