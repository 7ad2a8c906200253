"""Acquisition stage: one C3D trial of the manifest, checked against the contract, screened for
glitches and resampled to the analysis rates, to tidy Parquet tables."""

from __future__ import annotations

import logging
from collections.abc import Mapping
from pathlib import Path

import pandas as pd

from exobench.phantom.recordings import c3d, qc, resample, scale
from exobench.phantom.rig import ANALOG_RATE_HZ, Rig

LOG = logging.getLogger("exobench")


def screened_trial(path: Path, labels: Mapping, chain: Mapping, rig: Rig | None = None):
    """Markers (100 Hz), analog channels (1000 Hz, with ``load_cell_saturated``) and the QC
    events of one C3D trial: contract checked, unit slips against ``rig`` refused
    (``chain["unit_slips"]``), glitches blanked (``chain["glitches"]``), spring sign checked;
    each event says whether its gap fits ``chain["max_gap_frames"]``; an analog channel left
    unmapped in a file without SYNC is a warning and a QC row (``chain["sync_threshold_V"]``); a
    file the parser has not read within ``chain["read_timeout_s"]`` (when given) is refused."""
    recording = c3d.read_recording(path, labels, chain.get("read_timeout_s"))
    if "unit_slips" in chain:
        scale.check(recording, rig or Rig(), chain["unit_slips"], labels)
    screened = qc.screen(recording, chain["glitches"])
    markers, analog = c3d.analysis_tables(screened.recording)
    recording = screened.recording
    analog["load_cell_saturated"] = resample.resample_flags(
        screened.saturated, recording.analog_rate_hz, ANALOG_RATE_HZ, len(analog)
    )
    c3d.check_spring_sign(path, markers, analog["LC_SPRING_N"].to_numpy())
    events = qc.repairs(screened.events, markers, analog, int(chain["max_gap_frames"]))
    if recording.unmapped and "sync_threshold_V" in chain:
        threshold = float(chain["sync_threshold_V"])
        LOG.warning("%s", qc.unmapped_warning(recording, threshold))
        unmapped = qc.unmapped_events(recording, threshold)
        events = pd.concat([events, unmapped], ignore_index=True).astype(unmapped.dtypes)
    return markers, analog, events
