"""The emulator's contract (docs/rig.md §3): file layout, rates, clutch rule and spring law."""

from __future__ import annotations

import numpy as np

from exobench.plausibility import ChannelRange

# the rates Heer's rig records at (the twin's); a lab's files are analysed at their own rate
# (sample_rate_Hz) within emulator.analysis.brace_rate_range_Hz and mocap_rate_range_Hz
BRACE_RATE_HZ = 1000.0
MOCAP_RATE_HZ = 100.0
MANIFEST_COLUMNS = ("trial", "file", "mocap_file", "speed_m_per_s", "stiffness_Nm_per_rad", "side")
BRACE_COLUMNS = (
    "time_s",
    "brace_angle_deg",
    "brace_torque_Nm",
    "desired_torque_Nm",
    "motor_angle_deg",
)
# optional: the controller's recorded clutch flag (non-zero while the spring is active)
OPTIONAL_BRACE_COLUMNS = ("clutch_engaged",)
MOCAP_COLUMNS = ("time_s", "knee_flexion_deg")
# Plausible values per column (chosen: well beyond a knee in treadmill walking and the brace's
# torque budget, well inside what a unit slip gives, e.g. N·mm for N·m).
CHANNEL_RANGES = {
    "brace_angle_deg": ChannelRange(-30.0, 150.0, "deg"),
    "brace_torque_Nm": ChannelRange(-30.0, 30.0, "N·m"),
    "desired_torque_Nm": ChannelRange(-30.0, 30.0, "N·m"),
    "motor_angle_deg": ChannelRange(-360.0, 360.0, "deg"),
    "knee_flexion_deg": ChannelRange(-30.0, 150.0, "deg"),
}
CLUTCH_ANGLE_DEG = 40.0  # Table 6.1: engage at peak flexion once above 40°
PEAK_FLEXION_DEG = 40.0  # Table 5.1 (knee): peak flexion above 40°
HEEL_STRIKE_DEG = 20.0  # Table 5.1 (knee): heel strike below 20° after peak extension
# gait-cycle % of the twin's trajectory landmarks (heel strike, loading peak, mid-stance minimum,
# toe-off, swing peak, terminal swing, peak extension, next heel strike); chosen, not Heer's:
# their angles come from the speed-dependent config values (emulator.twin.gait)
LANDMARK_PCT = (0.0, 14.0, 40.0, 62.0, 73.0, 87.0, 97.0, 100.0)


def spring_torque(stiffness_Nm_per_rad: float, equilibrium_deg: float, angle_deg) -> np.ndarray:
    """docs/rig.md §3 spring law τ = κ·max(0, θ_eq − θ), positive in flexion (resists extension)."""
    return stiffness_Nm_per_rad * np.radians(np.maximum(0.0, equilibrium_deg - angle_deg))


def sample_rate_Hz(t_s) -> float:
    """A recording's rate (Hz) from its time stamps: 1 / the median step, rounded to 1 µHz so
    that the stamps' float noise leaves a nominal rate (1000 Hz) exact."""
    return round(1.0 / float(np.median(np.diff(np.asarray(t_s, float)))), 6)
