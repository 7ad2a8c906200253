"""The nominal rig of the contract and the violations a recording may carry (term key →
parameter, what each needs, the values each may take)."""

import math
from collections.abc import Mapping
from numbers import Real

import numpy as np

# Rig constants: the nominal rig of the contract (docs/rig.md §1; the spring's pretension and free
# length and the clutch release are the project's nominal values). The analysis uses these; a
# violation changes the real rig the recording comes from.
G = 9.81
L_THIGH, L_SHANK = 0.299, 0.304
M_THIGH, M_SHANK = 2.51 + 0.64, 1.23 + 0.39
COM_THIGH, COM_SHANK = 0.152, 0.113
I_THIGH, I_SHANK = 0.0165, 0.0130
PULLEY_R = 0.030
CHAIN_RATIO = 5.0
K_TENSIONER = 0.1
F0_N = 3.0
SPRING_LEN_M = 0.080
STRIDE_S = 2.0
FS_ANALOG = 1000
FS_POINT = 100
CLUTCH_RELEASE_FRACTION = 0.35
SYNC_V, SYNC_S = 5.0, 0.020
SHIFT_SD_DEG = 4.0

# Lab geometry of the markers (chosen): hip centre position and lateral (+Z) offsets, mm.
HIP_MM = np.array([0.0, 950.0, 0.0])
JOINT_HALF_WIDTH_MM = {"HIP": 70.0, "KNEE": 50.0, "ANK": 35.0}
BAR_Z_MM, SPRING_Z_MM = 85.0, 100.0
THIGH_BAR_MARKERS_M = {"EX_THIGH_PROX": 0.22, "EX_THIGH_DIST": 0.07}
SHANK_BAR_MARKERS_M = {"EX_SHANK_PROX": 0.07, "EX_SHANK_DIST": 0.22}
SPRING_FIXED_FROM_HINGE_M, SPRING_ANTERIOR_M = 0.21, 0.03

MARKERS = (
    "PH_HIP_MED",
    "PH_HIP_LAT",
    "PH_KNEE_MED",
    "PH_KNEE_LAT",
    "PH_ANK_MED",
    "PH_ANK_LAT",
    "EX_THIGH_PROX",
    "EX_THIGH_DIST",
    "EX_SHANK_PROX",
    "EX_SHANK_DIST",
    "EX_SPRING_A",
    "EX_SPRING_B",
)
ANKLE_CELLS = ("LC_ANKLE_1", "LC_ANKLE_2", "LC_ANKLE_3")
LOAD_CELLS = (*ANKLE_CELLS, "LC_SPRING")
CHANNELS = (*LOAD_CELLS, "SYNC")
CHANNEL_UNITS = ("N", "N", "N", "N", "V")
MANIFEST_COLUMNS = ("trial", "file", "spring_stiffness_N_per_m", "test_order", "ramp_strides")

# Every relaxation of docs/assumptions.md: term key → its parameter (the table's name).
VIOLATIONS: dict[str, tuple[str, ...]] = {
    "interface.elastic": ("k_interface_Nm_per_rad",),
    "interface.stiffening": ("stiffening_per_rad2",),
    "interface.viscous": ("c_interface_Nms_per_rad",),
    "interface.coulomb": ("friction_Nm",),
    "interface.drifting": ("drift_per_s",),
    "interface.play": ("play_rad",),
    "frame.elastic": ("k_frame_Nm_per_rad",),
    "frame.stiffening": ("stiffening_per_rad2",),
    "frame.viscous": ("c_frame_Nms_per_rad",),
    "frame.drifting": ("drift_per_s",),
    "spring.value": ("scale",),
    "spring.stiffening": ("quadratic_per_m",),
    "spring.viscous": ("c_spring_Ns_per_m",),
    "spring.coulomb": ("friction_Nm",),
    "spring.drifting": ("drift_per_s",),
    "transmission.play": ("play_rad",),
    "clutch.delay": ("delay_s",),
    "pulley_radius.value": ("scale",),
    "chain_ratio.value": ("scale",),
    "tensioner.value": ("scale",),
    "knee.elastic": ("k_Nm_per_rad",),
    "knee.viscous": ("c_Nms_per_rad",),
    "knee.coulomb": ("friction_Nm",),
    "hip.viscous": ("c_Nms_per_rad",),
    "hip.coulomb": ("friction_Nm",),
    "hip.elastic": ("k_Nm_per_rad",),
    "thigh_mass.value": ("scale",),
    "thigh_com.value": ("scale",),
    "thigh_inertia.value": ("scale",),
    "shank_mass.value": ("scale",),
    "shank_com.value": ("scale",),
    "shank_inertia.value": ("scale",),
    "bars.offset": ("angle_rad",),
    "segment_lengths.value": ("scale",),
    "ankle_path.offset": ("offset_mm",),
    "cell_direction.tilt": ("tilt_rad",),
    "knee_markers.offset": ("offset_mm",),
    **{
        f"{cell}.{family}": (parameter,)
        for cell in LOAD_CELLS
        for family, parameter in (
            ("gain", "gain"),
            ("offset", "offset_N"),
            ("drift", "drift_N_per_s"),
            ("delay", "delay_s"),
            ("crosstalk", "share"),
        )
    },
    "clocks.delay": ("analog_delay_s",),
    "clocks.drift": ("rate_error",),
    "cell_linearity.nonlinearity": ("quadratic_per_kN",),
    "straps_between.between": ("spread",),
    "cells_zero_between.between": ("spread_N",),
}
# The between-trial relaxations: a constant re-set per trial, z_i ~ N(0, 1) truncated at ±Z_MAX.
BETWEEN = ("straps_between.between", "cells_zero_between.between")
Z_MAX = 3.0
# Term key → the term keys it needs present (the table's "needs").
REQUIRES: dict[str, tuple[str, ...]] = {
    **{f"interface.{f}": ("interface.elastic",) for f in ("stiffening", "viscous", "coulomb")},
    "interface.drifting": ("interface.elastic",),
    "straps_between.between": ("interface.elastic",),
    **{f"frame.{f}": ("frame.elastic",) for f in ("stiffening", "viscous", "drifting")},
}

# The values a violation may take (beyond being a finite real number).
_POSITIVE = (
    "interface.elastic",
    "frame.elastic",
    "spring.value",
    "pulley_radius.value",
    "chain_ratio.value",
    "segment_lengths.value",
    *(f"{seg}_{what}.value" for seg in ("thigh", "shank") for what in ("mass", "com", "inertia")),
    *(f"{cell}.gain" for cell in LOAD_CELLS),
)
_NON_NEGATIVE = (
    *(f"{el}.{f}" for el in ("interface", "frame") for f in ("stiffening", "viscous")),
    "interface.coulomb",
    "interface.play",
    *(f"spring.{f}" for f in ("stiffening", "viscous", "coulomb")),
    "transmission.play",
    "tensioner.value",
    *(f"knee.{f}" for f in ("elastic", "viscous", "coulomb")),
    *(f"hip.{f}" for f in ("viscous", "coulomb", "elastic")),
    "cells_zero_between.between",
)
_BOUNDED = {  # key → (lowest, highest) allowed, open at a finite end unless it is 0
    "clutch.delay": (0.0, CLUTCH_RELEASE_FRACTION * STRIDE_S),
    "bars.offset": (-math.pi / 2, math.pi / 2),
    "cell_direction.tilt": (-math.pi / 2, math.pi / 2),
    **{f"{cell}.delay": (0.0, STRIDE_S) for cell in LOAD_CELLS},
    **{f"{cell}.crosstalk": (-1.0, 1.0) for cell in LOAD_CELLS},
    "clocks.delay": (-STRIDE_S, STRIDE_S),
    "clocks.drift": (-0.01, 0.01),
    # k·(1 + s·z) stays > 0 for every |z| ≤ Z_MAX
    "straps_between.between": (0.0, 1.0 / Z_MAX),
}
DRIFTS = ("interface.drifting", "frame.drifting", "spring.drifting")


def checked_violations(violations: Mapping[str, Mapping[str, float]] | None) -> dict:
    """Validated copy of violations: known keys, exact parameters, needs met, physical values."""
    out = {}
    for key, params in (violations or {}).items():
        if key not in VIOLATIONS:
            raise ValueError(f"unknown violation {key!r}; expected one of {sorted(VIOLATIONS)}")
        if not isinstance(params, Mapping) or set(params) != set(VIOLATIONS[key]):
            got = sorted(params) if isinstance(params, Mapping) else params
            raise ValueError(f"violation {key!r} needs exactly {VIOLATIONS[key]}, got {got}")
        (name,) = VIOLATIONS[key]
        value = params[name]
        if isinstance(value, bool) or not isinstance(value, Real) or not math.isfinite(value):
            raise ValueError(f"violation {key!r}: {name} must be a finite number, got {value!r}")
        value = float(value)
        if key in _POSITIVE and not value > 0.0:
            raise ValueError(f"violation {key!r}: {name} must be > 0, got {value}")
        if key in _NON_NEGATIVE and not value >= 0.0:
            raise ValueError(f"violation {key!r}: {name} must be ≥ 0, got {value}")
        if key in _BOUNDED:
            low, high = _BOUNDED[key]
            if not ((low <= value if low == 0.0 else low < value) and value < high):
                raise ValueError(
                    f"violation {key!r}: {name} must lie in [{low}, {high}), got {value}"
                )
        out[key] = {name: value}
    for key in out:
        missing = [need for need in REQUIRES.get(key, ()) if need not in out]
        if missing:
            raise ValueError(f"violation {key!r} needs {missing} present")
    return out


def value_of(violations: Mapping[str, Mapping[str, float]], key: str, neutral: float) -> float:
    """The one parameter of violation `key`, or its neutral value when the key is absent."""
    if key not in violations:
        return neutral
    return float(violations[key][VIOLATIONS[key][0]])


def check_duration(violations: Mapping[str, Mapping[str, float]], duration_s: float) -> None:
    """Refuse a drift that takes a stiffness to k·(1 + ρ·t) ≤ 0 within a trial of duration_s."""
    for key in DRIFTS:
        rho = value_of(violations, key, 0.0)
        if 1.0 + rho * duration_s <= 0.0:
            raise ValueError(
                f"violation {key!r}: drift_per_s = {rho} makes the stiffness k·(1 + ρ·t) ≤ 0 "
                f"within a {duration_s:g} s trial"
            )
