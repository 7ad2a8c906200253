"""What the phantom's summary says beside its pooled numbers: the knee moment's error per
spring, and what the drive stiffness of the twin's calibration rests on."""

from __future__ import annotations

from collections.abc import Mapping

import numpy as np
import pandas as pd

from exobench import studies
from exobench.selection.summary import interval_text, number

DIFFERENCE = "phantom_stance_flexion_median_difference_deg"
SPRING = "spring_stiffness_N_per_m"


def _per_spring_rms(predictions: pd.DataFrame) -> pd.DataFrame:
    """Each model's RMS knee-moment error per spring (rows, ascending) over the engine's
    sample (the strides it fitted: ``fitted``, where the table has it)."""
    if "fitted" in predictions:
        predictions = predictions[predictions["fitted"]]
    error = predictions.assign(
        rigid=(predictions["baseline_moment_Nm"] - predictions["measured_moment_Nm"]) ** 2,
        extended=(predictions["extended_moment_Nm"] - predictions["measured_moment_Nm"]) ** 2,
    )
    return np.sqrt(error.groupby(SPRING)[["rigid", "extended"]].mean())


def pooled_range(predictions: pd.DataFrame) -> str:
    """One sentence beside the verdict: the rigid theory's pooled error is a mean over springs
    whose own errors span a range."""
    rms = _per_spring_rms(predictions)
    return (
        f"(The rigid theory's knee-moment error is pooled over {rms.shape[0]} springs; per "
        f"spring it runs from {number(rms['rigid'].iloc[0])} N·m at "
        f"{rms.index.min() / 1e3:g} kN/m to {number(rms['rigid'].iloc[-1])} N·m at "
        f"{rms.index.max() / 1e3:g} kN/m.)"
    )


def peaks(predictions: pd.DataFrame) -> pd.DataFrame:
    """Each stride's peak measured knee moment in the engine's window, median and quartiles per
    spring (rows, ascending), over every stride in the table."""
    per = predictions.groupby([SPRING, "trial", "stride"])["measured_moment_Nm"].max()
    grouped = per.groupby(level=SPRING)
    return pd.DataFrame({"q1": grouped.quantile(0.25), "median": grouped.median(),
                         "q3": grouped.quantile(0.75), "n": grouped.size()})  # fmt: skip


def per_spring(predictions: pd.DataFrame) -> str:
    """The knee moment's pooled error in proportion: each model's RMS error per spring (from
    the engine's window samples of the strides it fitted, discrepancy_predictions.parquet) and
    the measured moment's per-stride peak, median [quartiles], over every included stride."""
    rms = _per_spring_rms(predictions)
    sample = predictions[predictions["fitted"]] if "fitted" in predictions else predictions
    peak = peaks(predictions)
    strides = sample.groupby(["trial", "stride"]).ngroups
    low, high = rms.index.min() / 1e3, rms.index.max() / 1e3
    ends = [peak.iloc[0], peak.iloc[-1]]
    quoted = [f"{number(p['median'])} [{number(p['q1'])}, {number(p['q3'])}] N·m" for p in ends]
    return (
        f"The knee moment's errors are pooled over {rms.shape[0]} springs ({strides} strides of "
        f"the engine's window). Per spring the rigid theory's error runs from "
        f"{number(rms['rigid'].iloc[0])} N·m ({low:g} kN/m) to {number(rms['rigid'].iloc[-1])} "
        f"N·m ({high:g} kN/m), while each stride's measured moment peaks in that window at a "
        f"median [quartiles] of {quoted[0]} ({low:g} kN/m, {int(ends[0]['n'])} strides) to "
        f"{quoted[1]} ({high:g} kN/m, {int(ends[1]['n'])} strides); the extended model's error, "
        f"fitted to the engine's strides, runs from {number(rms['extended'].min())} to "
        f"{number(rms['extended'].max())} N·m (discrepancy_predictions.parquet)."
    )


def drive_note(reported: Mapping, calibrated: Mapping[str, float], residuals: pd.DataFrame
               ) -> list[str]:  # fmt: skip
    """Why the twin's drive stiffness and the medians' model disagree: two models read the one
    flexion difference the study calls not significant (none when either is absent)."""
    refused = {e["effect"]: e for e in reported.get("not_claimed", [])}
    if "drive_compliance" not in refused or "k_drive_N_per_m" not in calibrated:
        return []
    entry = refused["drive_compliance"]
    row = residuals[residuals["metric"] == DIFFERENCE]
    if row.empty:
        return []
    twin, target = float(row["twin"].iloc[0]), float(row["reported"].iloc[0])
    medians = interval_text(entry["fitted_anyway"]["k_drive_N_per_m"], None, "N/m")
    set_to = interval_text(calibrated["k_drive_N_per_m"], None, "N/m")
    return [
        f"The twin's drive stiffness ({set_to}) is its calibration's fit to {len(residuals)} "
        f"reported numbers, among them the same {target:g}° difference, inside the twin's "
        "time-domain model: there the hexapod follows a fixed programme, so a softer drive also "
        "lowers every spring's flexion and moment, and the interface's damping and the frame's "
        f"friction change the flexion too; the calibrated twin shows {twin:.2f}° rather than "
        f"{target:g}°. The medians' quasi-static model, in which the measured flexion already "
        "carries the drive's loss and only the flexion difference speaks of the drive, reads "
        f"{medians} from that difference. Two models give two readings; neither is a measured "
        "property of the hexapod, and the one number that speaks of the drive directly is one "
        f"{studies.PHANTOM.key} report as not significant."
    ]
