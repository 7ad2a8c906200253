"""The strides the statistics keep (seed 000 §2.4) and the spring column that groups them."""

from __future__ import annotations

import pandas as pd

SPRING = "spring_stiffness_N_per_m"


def included(metrics: pd.DataFrame) -> pd.DataFrame:
    """Strides kept for the statistics: included ones (seed 000 §2.4)."""
    return metrics[metrics["included"].astype(bool)]
