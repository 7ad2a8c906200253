"""The strides the statistics keep (seed 000 §2.4) and the spring column that groups them."""

from __future__ import annotations

import pandas as pd

SPRING = "spring_stiffness_N_per_m"


def at_spring(spring) -> str:
    """' at 9.2 kN/m' for a spring rate in N/m, '' for a number of no spring (NaN)."""
    return "" if pd.isna(spring) else f" at {float(spring) / 1e3:g} kN/m"


def included(metrics: pd.DataFrame) -> pd.DataFrame:
    """Strides kept for the statistics: included ones (seed 000 §2.4)."""
    return metrics[metrics["included"].astype(bool)]
