"""The twin's true per-stride metrics: its truth files (every element's real angle, moment and
force, ``<raw_dir>/phantom/truth/``) through the metrics' own definitions, for the method check
(the chain's measurement of the same strides against what they hold)."""

from __future__ import annotations

from collections.abc import Mapping

import numpy as np
import pandas as pd

from exobench.phantom.chain import metrics
from exobench.phantom.rig import ANALOG_RATE_HZ

SPRING = "spring_stiffness_N_per_m"


def true_metrics(trial: str, spring: float, truth: pd.DataFrame, protocol: Mapping) -> pd.DataFrame:
    """One row per stride of a truth file (1 kHz samples, ``stride`` numbered): trial, spring,
    stride and every metric of :data:`metrics.METRIC_COLUMNS` from the true signals."""
    numbers = truth["stride"].unique()
    arrays = {c: truth[c].to_numpy().reshape(numbers.size, -1) for c in metrics.SIGNALS}
    length = truth["spring_extension_m"].to_numpy().reshape(numbers.size, -1)
    dt = 1.0 / ANALOG_RATE_HZ
    powers = metrics.power_partition(*(arrays[c] for c in metrics.SIGNALS), length, dt)
    per = metrics.stride_metrics(arrays, powers, dt, protocol)
    table = pd.DataFrame({"trial": trial, SPRING: float(spring), "stride": numbers})
    for column in metrics.METRIC_COLUMNS:
        table[column] = np.asarray(per[column], float)
    return table


def aligned(chain: pd.DataFrame, truth: pd.DataFrame) -> pd.DataFrame:
    """The chain's metrics table (its rows, inclusion and order) with every metric replaced by
    the twin's true value of the same stride."""
    keys = ["trial", "stride"]
    values = truth.set_index(keys)[list(metrics.METRIC_COLUMNS)]
    out = chain.copy()
    found = values.reindex(pd.MultiIndex.from_frame(chain[keys]))
    for column in metrics.METRIC_COLUMNS:
        out[column] = found[column].to_numpy()
    return out
