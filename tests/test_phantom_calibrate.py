"""Calibration of the twin: which parameters it fits and what it fits them to."""

from __future__ import annotations

import pandas as pd

from conftest import REPO
from exobench.phantom.rig import Rig
from exobench.phantom.twin import calibrate
from phantom_helpers import mean_cycle, settings, workflow_config

REPORTED = pd.read_csv(REPO / "raw" / "reference" / "seed000_reported.csv")


def test_fits_the_enabled_calibrated_effects_only():
    config = settings(workflow_config())
    effects, block = config["twin"]["effects"], config["calibration"]
    assert calibrate.fitted_parameters(effects, block) == (
        "k_interface_Nm_per_rad",
        "c_interface_Nms_per_rad",
        "k_frame_Nm_per_rad",
        "friction_Nm",
        "k_drive_N_per_m",
    )
    effects["drive_compliance"]["k_drive_N_per_m"] = 80000.0
    effects["frame_friction"]["enabled"] = False
    assert "k_drive_N_per_m" not in calibrate.fitted_parameters(effects, block)
    assert "friction_Nm" not in calibrate.fitted_parameters(effects, block)


def test_targets_include_the_reported_drop_of_phantom_stance_flexion():
    goal = calibrate.targets(REPORTED)
    drop = goal[goal["metric"] == "phantom_stance_flexion_median_difference_deg"]
    assert drop["value"].tolist() == [0.6]
    assert not (goal["metric"] == "phantom_stance_flexion_deg").any()  # the programme's level
    medians = {
        3400.0: {"phantom_stance_flexion_deg": 10.0, "peak_moment_Nm": 5.0},
        21700.0: {"phantom_stance_flexion_deg": 9.25, "peak_moment_Nm": 8.0},
    }
    difference = "phantom_stance_flexion_median_difference_deg"
    assert calibrate.model_value(difference, float("nan"), medians) == 0.75
    assert calibrate.model_value("peak_moment_Nm", 21700.0, medians) == 8.0


def test_the_fit_simulates_the_calibration_strides_whatever_the_recordings_length():
    fits = []
    for recorded, ramps in ((12, 1), (40, 3)):
        config = settings(workflow_config())
        config["protocol"].update(strides=recorded, ramp_strides=ramps)
        config["calibration"].update(strides=8, ramp_strides=1)
        fitted, summary, _, _ = calibrate.fit(
            mean_cycle(), REPORTED, Rig(), config, config["calibration"]
        )
        assert summary["strides_per_spring"] == 8 - 2  # ramp strides dropped at both ends
        fits.append(fitted)
    assert fits[0] == fits[1]
