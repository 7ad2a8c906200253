"""The nominal emulator rig of the contract and the violations a recording may carry (term key →
parameter, what each needs, the values each may take)."""

import math
from collections.abc import Mapping
from numbers import Real

# The nominal rig (docs/rig.md §3, Heer §5, config/config.yaml's emulator block). The analysis
# uses these; a violation changes the real rig the recording comes from.
FS = 1000  # the control loop and the brace file (Hz)
FS_MOCAP = 100  # motion capture (Hz)
ENCODER_COUNTS_PER_TURN = 5000  # 1250 lines in quadrature
EQUILIBRIUM_DEG = 40.0  # the spring's θ_eq (docs/rig.md §3)
ENGAGE_ABOVE_DEG = 40.0  # Table 6.1: engage at a peak flexion beyond this angle
# Table 5.1 (knee): a peak flexion beyond 40°, then a peak extension below 20°, then heel strike
# at the first fall of the velocity after it (the impact peak).
PEAK_FLEXION_ABOVE_DEG, PEAK_EXTENSION_BELOW_DEG = 40.0, 20.0
VELOCITY_CUTOFF_HZ = 6.0  # Heer §5.2: brace velocity, 2nd-order Butterworth of the derivative
TORQUE_CUTOFF_HZ = 20.0  # Heer §5.2: the torque channel's 2nd-order Butterworth
BLEND_DEG_PER_S = 25.0  # eq. 5.8: the two directions' set points blend below this speed
MOTOR_TIME_CONSTANT_S = 0.002  # the motor's position servo (config: chosen)
BRACE_PULLEY_M, MOTOR_PULLEY_M = 0.044, 0.048
PULLEY_RATIO = BRACE_PULLEY_M / MOTOR_PULLEY_M  # A of eq. 5.4
# The cable's calibration b(τ) = B·τ² + C·τ + D (motor degrees) per direction of motion.
FLEXION = (-0.3, 7.0, 1.0)
EXTENSION = (-0.3, 6.5, 0.0)
TORQUE_SD_NM = 0.02  # the torque channel's noise (emulator.sensors.load_cell_sd_Nm)
MOCAP_SD_DEG = 0.8  # motion capture's knee-angle noise (emulator.sensors.mocap_sd_deg)
SIDE = "right"
# Chosen by this generator: the controller runs this long before the recording starts (its
# filters and clutch settle), a count drop falls in this share of the trial unless its instant is
# given, and the soft tissue's time constant lies in the cuff law's range unless given.
WARMUP_S = 3.0
DROP_WINDOW = (0.2, 0.8)
CUFF_TIME_CONSTANT_S = (0.005, 0.05)

# The files' columns (docs/rig.md §3) and how each value is printed (time and whole encoder counts
# exactly, the rest below their noise; "z" prints a negative zero as 0).
BRACE_FORMATS = {
    "time_s": "{:.3f}",
    "brace_angle_deg": "{:z.3f}",
    "brace_torque_Nm": "{:z.5f}",
    "desired_torque_Nm": "{:z.5f}",
    "motor_angle_deg": "{:z.5f}",
}
MOCAP_FORMATS = {"time_s": "{:.2f}", "knee_flexion_deg": "{:z.4f}"}
MANIFEST_COLUMNS = ("trial", "file", "mocap_file", "speed_m_per_s", "stiffness_Nm_per_rad", "side")

# Every relaxation of docs/emulator_assumptions.md: term key → its parameter (the table's name).
VIOLATIONS: dict[str, tuple[str, ...]] = {
    "cable.coulomb": ("friction_fraction",),
    "cable.viscous": ("c_Nms_per_rad",),
    "cable.drifting": ("drift_per_s",),
    "cable.play": ("play_deg",),
    "cable.bias": ("bias_Nm",),
    "cable_calibration.value": ("scale",),
    "cable_calibration.offset": ("offset_deg",),
    "pulley_ratio.value": ("scale",),
    "cuff.elastic": ("compliance_deg_per_Nm",),
    "cuff.stiffening": ("stiffening_per_Nm",),
    "cuff.coulomb": ("friction_Nm",),
    "cuff.drifting": ("drift_per_s",),
    "cuff.play": ("play_deg",),
    "hinge.offset": ("offset_ratio",),
    "spring.value": ("scale",),
    "spring.offset": ("offset_deg",),
    "spring.stiffening": ("stiffening_per_rad",),
    "encoder.step": ("drop_deg",),
    "encoder.gain": ("gain",),
    "encoder.drift": ("drift_deg_per_s",),
    "motor_encoder.gain": ("gain",),
    "mocap.offset": ("zero_deg",),
    "mocap.gain": ("gain",),
    "mocap.harmonic": ("amplitude_deg",),
    "torque_sensor.offset": ("torque_offset_Nm",),
    "torque_sensor.gain": ("gain",),
    "torque_sensor.drift": ("drift_Nm_per_s",),
    "torque_sensor.delay": ("delay_s",),
    "clocks.delay": ("clock_offset_s",),
    "clocks.drift": ("rate_error",),
    "torque_linearity.nonlinearity": ("quadratic_per_Nm",),
    "clutch_engage.delay": ("delay_s",),
    "clutch_engage.event": ("loading_share",),
    "clutch_release.delay": ("release_delay_s",),
    "clutch_release.event": ("heel_strike_share",),
    "clutch_release.threshold": ("threshold_deg_per_s",),
    "velocity_estimate.delay": ("lead_s",),
    "straps_between.between": ("spread",),
    "mocap_zero_between.between": ("spread_deg",),
    "torque_zero_between.between": ("spread_Nm",),
    "cable_tension_between.between": ("spread_deg",),
}
# Term key → the term keys it needs present (the table's "needs").
REQUIRES: dict[str, tuple[str, ...]] = {
    **{f"cuff.{f}": ("cuff.elastic",) for f in ("stiffening", "coulomb", "drifting")},
    "straps_between.between": ("cuff.elastic",),
}
# The between-trial relaxations: a constant re-set per trial, z_i ~ N(0, 1) truncated at ±Z_MAX.
BETWEEN = (
    "straps_between.between",
    "mocap_zero_between.between",
    "torque_zero_between.between",
    "cable_tension_between.between",
)
Z_MAX = 3.0

# The values a violation may take: (lowest, highest, whether the lowest is allowed) — every
# parameter is a finite real number, any sign unless listed here.
_POSITIVE, _NON_NEGATIVE = (0.0, math.inf, False), (0.0, math.inf, True)
DOMAINS: dict[str, tuple[float, float, bool]] = {
    **dict.fromkeys(
        ("cable_calibration.value", "pulley_ratio.value", "spring.value", "encoder.gain"),
        _POSITIVE,
    ),
    **dict.fromkeys(("motor_encoder.gain", "mocap.gain", "torque_sensor.gain"), _POSITIVE),
    **dict.fromkeys(("cable.viscous", "cable.play", "cable.bias", *BETWEEN), _NON_NEGATIVE),
    **{f"cuff.{f}": _NON_NEGATIVE for f in ("elastic", "stiffening", "coulomb", "play")},
    "cable.coulomb": (-1.0, 1.0, False),
    "hinge.offset": (-1.0, 1.0, False),
    "torque_sensor.delay": (0.0, 1.0, True),
    "clocks.delay": (-1.0, 1.0, False),
    "clocks.drift": (-0.01, 0.01, False),
    "clutch_engage.delay": (0.0, 0.5, True),
    "clutch_engage.event": (0.0, math.nextafter(1.0, 2.0), True),  # a share: 0 to 1, both in
    "clutch_release.delay": (0.0, 0.5, True),
    "clutch_release.event": (-1.0, 2.0, False),
    "clutch_release.threshold": (0.0, math.inf, True),
}
DRIFTS = ("cable.drifting", "cuff.drifting")


def checked_violations(violations: Mapping[str, Mapping[str, float]] | None) -> dict:
    """Validated copy: known keys, each with its one parameter in its domain, every need present."""
    given = dict(violations or {})
    unknown = sorted(set(given) - set(VIOLATIONS))
    if unknown:
        raise ValueError(f"unknown violations {unknown}; the table's are {sorted(VIOLATIONS)}")
    out = {key: {VIOLATIONS[key][0]: _parameter(key, params)} for key, params in given.items()}
    lacking = {key: [n for n in REQUIRES.get(key, ()) if n not in out] for key in out}
    lacking = {key: needs for key, needs in lacking.items() if needs}
    if lacking:
        raise ValueError(f"violations without what they need: {lacking}")
    return out


def _parameter(key: str, params: object) -> float:
    """The violation's one parameter: a finite real number inside DOMAINS[key]."""
    (name,) = VIOLATIONS[key]
    if not isinstance(params, Mapping) or list(params) != [name]:
        raise ValueError(f"violation {key!r} takes {{{name!r}: value}} alone, got {params!r}")
    value = params[name]
    if isinstance(value, bool) or not isinstance(value, Real) or not math.isfinite(value):
        raise ValueError(f"{key}.{name} = {value!r}: a finite number expected")
    low, high, with_low = DOMAINS.get(key, (-math.inf, math.inf, False))
    if not (value >= low if with_low else value > low) or not value < high:
        side = "[" if with_low else "("
        raise ValueError(f"{key}.{name} = {value} lies outside {side}{low}, {high})")
    return float(value)


def value_of(violations: Mapping[str, Mapping[str, float]], key: str, neutral: float) -> float:
    """The one parameter of violation `key`, or its neutral value when the key is absent."""
    return float(violations[key][VIOLATIONS[key][0]]) if key in violations else neutral


def check_duration(violations: Mapping[str, Mapping[str, float]], duration_s: float) -> None:
    """Refuse a drift whose factor 1 + ρ·t (cable torque, cuff compliance) falls to 0 in a trial."""
    bad = [key for key in DRIFTS if 1.0 + value_of(violations, key, 0.0) * duration_s <= 0.0]
    if bad:
        raise ValueError(f"{bad}: 1 + ρ·t ≤ 0 within a {duration_s:g} s trial")
