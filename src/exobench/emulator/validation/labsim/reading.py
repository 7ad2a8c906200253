"""One lab's reading of Heer's thesis and the rig contract: its controller's release and engage
rules, velocity estimate, motor and cable, its own cable calibration, encoder, torque filter,
noise and motion-capture zero; NOMINAL reads them as the project does, draw_reading draws one."""

import math
from dataclasses import dataclass

import numpy as np

from .rig import (
    ENCODER_COUNTS_PER_TURN,
    EXTENSION,
    FLEXION,
    FS,
    MOCAP_SD_DEG,
    MOTOR_TIME_CONSTANT_S,
    TORQUE_CUTOFF_HZ,
    TORQUE_SD_NM,
    VELOCITY_CUTOFF_HZ,
)

RELEASE_RULES = ("peak_extension", "heel_strike", "velocity_threshold")
ENGAGE_RULES = ("table_6_1", "latched")
VELOCITY_ESTIMATES = ("butterworth", "centred_difference")
CALIBRATIONS = ("session", "per_trial")
# The centred difference looks this many samples back on each side of the instant it estimates
# (chosen: a 10 ms span, short against a stride, long against the encoder's count): the newest it
# can be in real time is the one about sample i − k.
CENTRED_HALF_SPAN = 5

# What draw_reading draws, axis by axis; each keeps the project's reading with this probability.
AXES = ("release_rule", "release_delay", "engage_rule", "velocity", "motor", "friction",
        "cable_law", "calibration", "encoder", "torque_filter", "load_cell_sd", "mocap_sd",
        "mocap_rezeroed")  # fmt: skip
NOMINAL_SHARE = 1.0 / 3.0
# velocity_threshold: the release once ω rises above −v_th (°/s), v_th in this range.
RELEASE_THRESHOLD_DEG_PER_S = (10.0, 40.0)
# The release's delay after its event (s).
RELEASE_DELAY_S = (0.0, 0.05)
# A Butterworth velocity filter's order and cut-off (Hz).
VELOCITY_ORDERS = (1, 2)
VELOCITY_CUTOFF_RANGE_HZ = (4.0, 10.0)
# The motor's first-order lag (s) and the cable's friction bias while it pulls (N·m).
MOTOR_TIME_CONSTANT_RANGE_S = (0.002, 0.03)
FRICTION_BIAS_NM = (0.0, 0.15)
# The lab's cable calibration about the nominal one, per direction: B × (1 ± 30 %), C × (1 ± 15 %),
# D ± 1° (uniform); a per-trial calibration about the session's: B ± 5 %, C ± 2 %, D ± 0.25°.
CALIBRATION_SPREAD = (0.30, 0.15, 1.0)
TRIAL_CALIBRATION_SPREAD = (0.05, 0.02, 0.25)
# Encoders other than the nominal 5000 counts per turn.
ENCODER_COUNTS = (2000, 4096, 10000)
# A torque filter's other cut-off (Hz), the load cell's noise SD (N·m), motion capture's (deg).
TORQUE_FILTER_RANGE_HZ = (10.0, 40.0)
LOAD_CELL_SD_RANGE_NM = (0.005, 0.05)
MOCAP_SD_RANGE_DEG = (0.3, 1.5)
# A re-zeroed motion capture's zero per trial lies within ± this (deg; uniform).
MOCAP_ZERO_DEG = 2.5


@dataclass(frozen=True)
class Reading:
    """A lab's reading: the controller's rules, velocity estimate, motor, cable and channels.

    release_rule: "peak_extension" (Table 6.1: ω_i−1 < 0 ≤ ω_i), "velocity_threshold"
    (ω_i−1 < −v_th ≤ ω_i, v_th = release_threshold_deg_per_s) or "heel_strike" (Table 5.1's heel
    strike event), taking effect release_delay_s later; engage_rule: "table_6_1" (θ_e > 40°,
    ω_i−1 > 0 ≥ ω_i) or "latched" (θ_e > 40° once met stays met: ω_i−1 > 0 ≥ ω_i engages);
    velocity_estimate: "butterworth" (velocity_order, velocity_cutoff_Hz, causal) or
    "centred_difference" (unfiltered); flexion, extension: the real cable's (B, C, D), redone
    per trial about them when calibration is "per_trial"; torque_filter_Hz None: unfiltered.
    """

    release_rule: str = "peak_extension"
    release_threshold_deg_per_s: float = 0.0
    release_delay_s: float = 0.0
    engage_rule: str = "table_6_1"
    velocity_estimate: str = "butterworth"
    velocity_order: int = 2
    velocity_cutoff_Hz: float = VELOCITY_CUTOFF_HZ
    motor_time_constant_s: float = MOTOR_TIME_CONSTANT_S
    friction_bias_Nm: float = 0.0
    flexion: tuple[float, float, float] = FLEXION
    extension: tuple[float, float, float] = EXTENSION
    calibration: str = "session"
    encoder_counts_per_turn: int = ENCODER_COUNTS_PER_TURN
    torque_filter_Hz: float | None = TORQUE_CUTOFF_HZ
    load_cell_sd_Nm: float = TORQUE_SD_NM
    mocap_sd_deg: float = MOCAP_SD_DEG
    mocap_rezeroed: bool = False

    def __post_init__(self) -> None:
        """Refuse an unknown rule or a value outside its domain."""
        choices = {
            "release_rule": RELEASE_RULES,
            "engage_rule": ENGAGE_RULES,
            "velocity_estimate": VELOCITY_ESTIMATES,
            "calibration": CALIBRATIONS,
            "velocity_order": VELOCITY_ORDERS,
            "mocap_rezeroed": (False, True),
        }
        for name, options in choices.items():
            value = getattr(self, name)
            if value not in options or type(value) is not type(options[0]):
                raise ValueError(f"{name} = {value!r}: one of {options}")
        nyquist = FS / 2.0
        bounds = {
            "release_threshold_deg_per_s": (0.0, math.inf),
            "release_delay_s": (0.0, 0.5),
            "velocity_cutoff_Hz": (math.ulp(0.0), nyquist),
            "motor_time_constant_s": (math.ulp(0.0), math.inf),
            "friction_bias_Nm": (0.0, math.inf),
            "load_cell_sd_Nm": (0.0, math.inf),
            "mocap_sd_deg": (0.0, math.inf),
        }
        if self.torque_filter_Hz is not None:
            bounds["torque_filter_Hz"] = (math.ulp(0.0), nyquist)
        for name, (low, high) in bounds.items():
            value = getattr(self, name)
            if isinstance(value, bool) or not low <= value < high:
                raise ValueError(f"{name} = {value!r} lies outside [{low}, {high})")
        if self.release_threshold_deg_per_s and self.release_rule != "velocity_threshold":
            raise ValueError("release_threshold_deg_per_s belongs to the velocity_threshold rule")
        for name in ("flexion", "extension"):  # a hashable, exact (B, C, D)
            object.__setattr__(self, name, tuple(map(float, getattr(self, name))))
        counts = self.encoder_counts_per_turn
        if isinstance(counts, bool) or not isinstance(counts, int) or counts < 1:
            raise ValueError(f"encoder_counts_per_turn = {counts!r}: a whole number ≥ 1")
        for name in ("flexion", "extension"):
            b, c, d = getattr(self, name)
            if not (math.isfinite(b) and c > 0.0 and math.isfinite(c) and math.isfinite(d)):
                raise ValueError(f"{name} = {getattr(self, name)!r}: finite (B, C > 0, D)")

    def transmission(self) -> dict[str, dict[str, float]]:
        """The session's calibration b(τ) = B·τ² + C·τ + D per direction, as {B, C, D} dicts."""
        return {"flexion": _bcd(self.flexion), "extension": _bcd(self.extension)}

    def as_dict(self) -> dict:
        """The reading's every field, JSON-serialisable (the calibration as {B, C, D} dicts)."""
        out = {name: getattr(self, name) for name in self.__dataclass_fields__}
        out.update(self.transmission())
        return out

    def lab_config(self) -> dict:
        """What the lab states: the emulator config block's parts it overrides, and under "lab"
        what has no project key (its rules in words, encoder, motor, friction, re-zeroing)."""
        butterworth = self.velocity_estimate == "butterworth"
        return {
            "transmission": self.transmission(),
            "transmission_calibrated": self.calibration,
            "controller": {
                "torque_filter_Hz": self.torque_filter_Hz,
                "velocity_cutoff_Hz": self.velocity_cutoff_Hz if butterworth else None,
            },
            "sensors": {"mocap_sd_deg": self.mocap_sd_deg, "load_cell_sd_Nm": self.load_cell_sd_Nm},
            "lab": {
                "release_rule": self.release_rule,
                "release_threshold_deg_per_s": self.release_threshold_deg_per_s,
                "release_delay_s": self.release_delay_s,
                "engage_rule": self.engage_rule,
                "velocity_estimate": self.velocity_estimate,
                "velocity_order": self.velocity_order if butterworth else None,
                "encoder_counts_per_turn": self.encoder_counts_per_turn,
                "motor_time_constant_s": self.motor_time_constant_s,
                "friction_bias_Nm": self.friction_bias_Nm,
                "mocap_rezeroed": self.mocap_rezeroed,
            },
        }


NOMINAL = Reading()


def _bcd(values: tuple[float, float, float]) -> dict[str, float]:
    """(B, C, D) as {"B": B, "C": C, "D": D}."""
    return dict(zip("BCD", map(float, values), strict=True))


def _around(
    values: tuple[float, float, float], spread: tuple[float, float, float], rng: np.random.Generator
) -> tuple[float, float, float]:
    """(B·(1 + s_B·u), C·(1 + s_C·u'), D + s_D·u''), each u ~ U(−1, 1)."""
    u = rng.uniform(-1.0, 1.0, 3)
    b, c, d = values
    return (
        float(b * (1.0 + spread[0] * u[0])),
        float(c * (1.0 + spread[1] * u[1])),
        float(d + spread[2] * u[2]),
    )


def trial_reading(reading: Reading, rng: np.random.Generator) -> dict:
    """Trial i's draws of a reading: its calibration about the session's (per_trial), and its
    motion-capture zero z_i ~ U(−2.5°, 2.5°) (re-zeroed)."""
    drawn: dict = {}
    if reading.calibration == "per_trial":
        drawn["transmission"] = {
            "flexion": _bcd(_around(reading.flexion, TRIAL_CALIBRATION_SPREAD, rng)),
            "extension": _bcd(_around(reading.extension, TRIAL_CALIBRATION_SPREAD, rng)),
        }
    if reading.mocap_rezeroed:
        drawn["mocap_zero_deg"] = float(rng.uniform(-MOCAP_ZERO_DEG, MOCAP_ZERO_DEG))
    return drawn


def draw_reading(rng: np.random.Generator) -> Reading:
    """One lab's reading: each axis on its own keeps NOMINAL's value with probability 1/3, else
    takes one of its variants (a choice uniform among them, a value uniform in its range)."""
    keep = dict(zip(AXES, (rng.random(len(AXES)) < NOMINAL_SHARE).tolist(), strict=True))
    fields: dict = {}
    if not keep["release_rule"]:
        fields["release_rule"] = RELEASE_RULES[1 + int(rng.integers(2))]
        if fields["release_rule"] == "velocity_threshold":
            fields["release_threshold_deg_per_s"] = float(rng.uniform(*RELEASE_THRESHOLD_DEG_PER_S))
    if not keep["release_delay"]:
        fields["release_delay_s"] = float(rng.uniform(*RELEASE_DELAY_S))
    if not keep["engage_rule"]:
        fields["engage_rule"] = "latched"
    if not keep["velocity"]:
        variant = int(rng.integers(3))  # Butterworth of order 1 or 2 at a drawn cut-off, centred
        if variant == 2:
            fields["velocity_estimate"] = "centred_difference"
        else:
            fields["velocity_order"] = VELOCITY_ORDERS[variant]
            fields["velocity_cutoff_Hz"] = float(rng.uniform(*VELOCITY_CUTOFF_RANGE_HZ))
    if not keep["motor"]:
        fields["motor_time_constant_s"] = float(rng.uniform(*MOTOR_TIME_CONSTANT_RANGE_S))
    if not keep["friction"]:
        fields["friction_bias_Nm"] = float(rng.uniform(*FRICTION_BIAS_NM))
    if not keep["cable_law"]:
        fields["flexion"] = _around(FLEXION, CALIBRATION_SPREAD, rng)
        fields["extension"] = _around(EXTENSION, CALIBRATION_SPREAD, rng)
    if not keep["calibration"]:
        fields["calibration"] = "per_trial"
    if not keep["encoder"]:
        fields["encoder_counts_per_turn"] = ENCODER_COUNTS[int(rng.integers(len(ENCODER_COUNTS)))]
    if not keep["torque_filter"]:
        filtered = bool(rng.integers(2))
        fields["torque_filter_Hz"] = (
            float(rng.uniform(*TORQUE_FILTER_RANGE_HZ)) if filtered else None
        )
    if not keep["load_cell_sd"]:
        fields["load_cell_sd_Nm"] = float(rng.uniform(*LOAD_CELL_SD_RANGE_NM))
    if not keep["mocap_sd"]:
        fields["mocap_sd_deg"] = float(rng.uniform(*MOCAP_SD_RANGE_DEG))
    if not keep["mocap_rezeroed"]:
        fields["mocap_rezeroed"] = True
    return Reading(**fields)
