"""The phantom rig of docs/rig.md §1: segment parameters, transmission, protocol, file labels."""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, fields

import numpy as np

from exobench.plausibility import ChannelRange

GRAVITY_M_PER_S2 = 9.81
PHANTOM_MARKERS = (
    "PH_HIP_MED",
    "PH_HIP_LAT",
    "PH_KNEE_MED",
    "PH_KNEE_LAT",
    "PH_ANK_MED",
    "PH_ANK_LAT",
)
EXO_MARKERS = (
    "EX_THIGH_PROX",
    "EX_THIGH_DIST",
    "EX_SHANK_PROX",
    "EX_SHANK_DIST",
    "EX_SPRING_A",
    "EX_SPRING_B",
)
MARKERS = PHANTOM_MARKERS + EXO_MARKERS
LOAD_CELLS = ("LC_ANKLE_1", "LC_ANKLE_2", "LC_ANKLE_3")
ANALOG_UNITS = {
    "LC_ANKLE_1": "N",
    "LC_ANKLE_2": "N",
    "LC_ANKLE_3": "N",
    "LC_SPRING": "N",
    "SYNC": "V",
}
REQUIRED_ANALOGS = (*LOAD_CELLS, "LC_SPRING")
# Analysis rates: every recording is resampled to these (markers, analog channels).
POINT_RATE_HZ = 100.0
ANALOG_RATE_HZ = 1000.0
# Camera rates a recording may have (docs/rig.md); the analog rate is a whole multiple of it.
POINT_RATE_LIMITS_HZ = (50.0, 500.0)
# POINT:UNITS a recording may state, and their size in mm.
POINT_UNITS_MM = {"mm": 1.0, "m": 1000.0}
MANIFEST_COLUMNS = ("trial", "file", "spring_stiffness_N_per_m", "test_order", "ramp_strides")
SYNC_HIGH_V = 5.0
SYNC_WIDTH_S = 0.020

# Plausible values per channel (chosen: well beyond what the phantom can produce, well inside
# what a sign, unit or wiring error gives). An extension spring cannot push; idle, it holds its
# pretension, so a flat run at its minimum is physical and only its maximum can clip.
ANALOG_RANGES = {
    "LC_ANKLE_1": ChannelRange(-1000.0, 1000.0, "N"),
    "LC_ANKLE_2": ChannelRange(-1000.0, 1000.0, "N"),
    "LC_ANKLE_3": ChannelRange(-1000.0, 1000.0, "N"),
    "LC_SPRING": ChannelRange(-20.0, 2000.0, "N", clip_low=False),
    "SYNC": ChannelRange(-1.0, 12.0, "V"),
}
MARKER_RANGE = ChannelRange(-3000.0, 3000.0, "mm")  # inside the capture volume
# Plausible spring rates of the manifest (chosen: a knee exoskeleton's extension springs are
# kN/m; a rate typed in kN/m or N/mm is a thousand times too small and is refused).
SPRING_RANGE = ChannelRange(200.0, 500_000.0, "N/m")


@dataclass(frozen=True)
class Rig:
    """Segment parameters (phantom + strapped exoskeleton part) and exoskeleton transmission."""

    thigh_length_m: float = 0.299
    thigh_mass_kg: float = 2.51 + 0.64
    thigh_com_m: float = 0.152
    thigh_inertia_kgm2: float = 0.0165
    shank_length_m: float = 0.304
    shank_mass_kg: float = 1.23 + 0.39
    shank_com_m: float = 0.113
    shank_inertia_kgm2: float = 0.0130
    pulley_radius_m: float = 0.030
    chain_ratio: float = 5.0
    tensioner_stiffness_Nm_per_rad: float = 0.1

    @classmethod
    def from_config(cls, block: Mapping | None) -> Rig:
        """Rig with the docs/rig.md values, overridden by the keys of ``block``."""
        names = {field.name for field in fields(cls)}
        return cls(**{key: float(value) for key, value in (block or {}).items() if key in names})

    @property
    def spring_travel_m_per_rad(self) -> float:
        """Spring elongation per radian of knee rotation through chain and pulley: r·T/t."""
        return self.pulley_radius_m * self.chain_ratio

    def joint_stiffness(self, spring_stiffness_N_per_m):
        """Rigid-theory knee stiffness k_θ = (k_l − k_tensioner/r²)(T/t)² r², seed 000 eq. (2.2)."""
        r, ratio = self.pulley_radius_m, self.chain_ratio
        k_l = np.asarray(spring_stiffness_N_per_m, dtype=float)
        return (k_l - self.tensioner_stiffness_Nm_per_rad / r**2) * ratio**2 * r**2
