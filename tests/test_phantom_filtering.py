"""The filter stage's two files: marker paths apart from the 1000 Hz channels and flags."""

from __future__ import annotations

import numpy as np
import pandas as pd

from exobench.phantom.chain import filtering


def test_split_gives_the_markers_and_the_channels_every_column_once():
    rng = np.random.default_rng(0)
    columns = ["t_s", *filtering.MARKER_COLUMNS, "LC_SPRING_N", "SYNC_V", "marker_gap"]
    filtered = pd.DataFrame(rng.normal(size=(50, len(columns))), columns=columns)
    markers, channels = filtering.split(filtered)
    assert list(markers.columns) == ["t_s", *filtering.MARKER_COLUMNS]
    assert list(channels.columns) == ["t_s", "LC_SPRING_N", "SYNC_V", "marker_gap"]
    joined = pd.concat([markers, channels.drop(columns="t_s")], axis=1)[columns]
    pd.testing.assert_frame_equal(joined, filtered)
