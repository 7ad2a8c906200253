"""Reference data shipped with the project (see raw/reference/README.md)."""

from __future__ import annotations

from decimal import Decimal
from pathlib import Path

import numpy as np
import pandas as pd

from exobench.errors import InputError

MEAN_CYCLE_COLUMNS = ("gait_cycle_pct", "knee_flexion_deg")
STRIDE_TIME_S = 2.0
SIGNIFICANCE_COLUMNS = ("statement", "metric", "section", "different", "not_different",
                        "stated_test", "claim")  # fmt: skip


def read_reported(path: str | Path) -> pd.DataFrame:
    """The numbers a study reports with each value's text kept (its last digit is its
    rounding)."""
    return pd.read_csv(path, dtype={"value": str})


def rounding(text) -> float:
    """Half the last digit of a number as written ('8.0' → 0.05, '355.6' → 0.05, '140' → 0.5)."""
    exponent = Decimal(str(text).strip()).as_tuple().exponent
    return 0.5 * 10.0 ** int(exponent)


def pairs(text) -> list[tuple[float, float]]:
    """Spring pairs written '3400-21700 3400-6100' (N/m, softer first); empty text: none."""
    if not isinstance(text, str) or not text.strip():
        return []
    out = []
    for item in text.split():
        a, _, b = item.partition("-")
        out.append((float(a), float(b)))
    return out


def read_significance(path: str | Path) -> pd.DataFrame:
    """The significance statements a study makes, one row each (columns
    :data:`SIGNIFICANCE_COLUMNS`; ``different``/``not_different``: the pairs it calls so)."""
    frame = pd.read_csv(path, dtype=str, keep_default_na=False)
    for column in SIGNIFICANCE_COLUMNS:
        if column not in frame.columns:
            raise InputError(path, column, f"columns {', '.join(SIGNIFICANCE_COLUMNS)}")
    for column in ("different", "not_different"):
        for text in frame[column]:
            try:
                found = pairs(text)
            except ValueError:
                raise InputError(path, column, "pairs like '3400-21700', space-separated",
                                 text) from None  # fmt: skip
            if any(a >= b for a, b in found):
                raise InputError(path, column, "each pair's softer spring first", text)
    return frame


def read_mean_cycle(path: str | Path) -> pd.DataFrame:
    """Phantom mean knee-flexion cycle (docs/rig.md §1) with time and radians added."""
    frame = pd.read_csv(path)
    for column in MEAN_CYCLE_COLUMNS:
        if column not in frame.columns:
            raise InputError(path, column, f"columns {', '.join(MEAN_CYCLE_COLUMNS)}")
        if not np.isfinite(frame[column].to_numpy(float)).all():
            raise InputError(path, column, "finite numbers only")
    pct = frame["gait_cycle_pct"].to_numpy(float)
    if pct[0] != 0.0 or not (np.diff(pct) > 0).all() or pct[-1] >= 100.0:
        raise InputError(path, "gait_cycle_pct", "strictly increasing values in [0, 100)")
    flexion = frame["knee_flexion_deg"].to_numpy(float)
    return pd.DataFrame(
        {
            "gait_cycle_pct": pct,
            "t_s": pct / 100.0 * STRIDE_TIME_S,
            "knee_flexion_deg": flexion,
            "knee_flexion_rad": np.deg2rad(flexion),
        }
    )


def swing_fraction(cycle: pd.DataFrame) -> float:
    """Share of the stride at which the mean cycle peaks in flexion (mid-swing)."""
    return float(cycle["gait_cycle_pct"][cycle["knee_flexion_deg"].idxmax()]) / 100.0


def mean_cycle_figure(cycle: pd.DataFrame):
    """Figure of the reference mean knee-flexion cycle over the gait cycle, and its caption."""
    from exobench import figures

    fig, axes = figures.new_figure()
    ax = axes[0, 0]
    ax.plot(cycle["gait_cycle_pct"], cycle["knee_flexion_deg"], color=figures.PALETTE[0])
    ax.set(
        xlabel="gait cycle (%)",
        ylabel="knee flexion (deg)",
        title="Phantom mean crouch-gait knee cycle (reference)",
    )
    caption = (
        "Mean crouch-gait knee flexion of the gel phantom over one stride, 0–100 % of the "
        f"cycle ({STRIDE_TIME_S:g} s), as shipped with the project "
        "(``raw/reference/phantom_knee_flexion_mean_cycle.csv``, "
        f"{len(cycle)} samples; ``reference/mean_cycle.parquet``). The phantom digital twin "
        "perturbs its peaks and valleys stride by stride (docs/rig.md §1).",
    )
    return fig, caption
