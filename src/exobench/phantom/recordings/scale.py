"""Unit slips of a whole recording: markers or ankle load cells 1000× off the rig they record.

The glitch screening's ranges catch a channel 1000× too large; these checks catch what stays in
range: markers in metres under ``POINT:UNITS`` = ``mm`` (segments 0.3 mm long) and load cells
in kN under the unit N (an ankle force of hundredths). Each compares a scale the recording
measures with the rig's (``phantom.rig``) and names the slip when it is 1000× off, within the
factors of ``phantom.chain.unit_slips``.
"""

from __future__ import annotations

from collections.abc import Mapping

import numpy as np

from exobench.errors import InputError
from exobench.phantom.recordings.c3d import Recording
from exobench.phantom.rig import GRAVITY_M_PER_S2, LOAD_CELLS, Rig

SLIP = 1000.0
JOINTS = {"hip": "PH_HIP", "knee": "PH_KNEE", "ankle": "PH_ANK"}
# POINT:UNITS and the size of a mm in them (for the message: the distance as the file states it)
POINT_SCALE = {"mm": 1.0, "m": 0.001}


def slip(ratio: float, factor: float) -> int:
    """-1 when ``ratio`` (measured over expected) is 1000× too small within ``factor``, +1 when
    1000× too large, 0 otherwise (a finite positive ratio near 1, or none at all)."""
    if not np.isfinite(ratio) or ratio <= 0:
        return 0
    if 1.0 / factor <= ratio * SLIP <= factor:
        return -1
    if 1.0 / factor <= ratio / SLIP <= factor:
        return 1
    return 0


def joint_centre(markers_mm: Mapping[str, np.ndarray], joint: str) -> np.ndarray:
    """A joint's centre per frame: the midpoint of its medial and lateral markers (docs/rig.md)."""
    prefix = JOINTS[joint]
    return (markers_mm[f"{prefix}_MED"] + markers_mm[f"{prefix}_LAT"]) / 2.0


def leg_length_mm(markers_mm: Mapping[str, np.ndarray]) -> float:
    """Hip–knee plus knee–ankle joint-centre distance, each the median over frames (NaN when no
    frame has both joints)."""
    hip, knee, ankle = (joint_centre(markers_mm, joint) for joint in JOINTS)
    total = 0.0
    for a, b in ((hip, knee), (knee, ankle)):
        distance = np.linalg.norm(b - a, axis=1)
        distance = distance[np.isfinite(distance)]
        if distance.size == 0:
            return float("nan")
        total += float(np.median(distance))
    return total


def mean_ankle_force_N(analogs: Mapping[str, np.ndarray]) -> float:
    """Mean of |LC_ANKLE_1 + LC_ANKLE_2 + LC_ANKLE_3| over the samples where all three are
    finite (NaN when none is)."""
    total = np.abs(np.sum([np.asarray(analogs[c], float) for c in LOAD_CELLS], axis=0))
    total = total[np.isfinite(total)]
    return float(total.mean()) if total.size else float("nan")


def check_markers(recording: Recording, rig: Rig, factor: float) -> None:
    """Refuse markers 1000× off the unit ``POINT:UNITS`` states: joint-centre segments 1000×
    shorter (metres under mm) or longer (mm under m) than ``rig``'s thigh and shank."""
    expected = 1000.0 * (rig.thigh_length_m + rig.shank_length_m)
    measured = leg_length_mm(recording.markers_mm)
    direction = slip(measured / expected, factor)
    if direction == 0:
        return
    unit = recording.point_units
    if direction < 0 and unit == "mm":
        likely = "markers look to be in metres while POINT:UNITS says mm"
    elif direction > 0 and unit == "m":
        likely = "markers look to be in millimetres while POINT:UNITS says m"
    else:
        likely = f"markers look {SLIP:g}× too {'small' if direction < 0 else 'large'}"
        likely += f" for POINT:UNITS {unit}"
    raise InputError(
        recording.path,
        "POINT:UNITS",
        "markers in the unit POINT:UNITS states (hip–knee + knee–ankle joint centres "
        f"{expected:.0f} mm apart, as phantom.rig's thigh_length_m + shank_length_m)",
        f"{unit}, with the joint centres {measured * POINT_SCALE[unit]:.4g} {unit} apart: {likely}",
    )


def check_load_cells(recording: Recording, rig: Rig, factor: float, labels: Mapping) -> None:
    """Refuse ankle load cells in kN under the unit N: a mean vertical ankle force 1000× below
    the phantom's weight (``rig``'s thigh and shank masses, times g)."""
    weight = (rig.thigh_mass_kg + rig.shank_mass_kg) * GRAVITY_M_PER_S2
    force = mean_ankle_force_N(recording.analogs)
    if slip(force / weight, factor) >= 0:
        return
    cells = ", ".join(str(labels.get(cell, cell)) for cell in LOAD_CELLS)
    raise InputError(
        recording.path,
        f"ANALOG:UNITS of {cells}",
        f"ankle load cells in N (a mean vertical ankle force near the phantom's weight, "
        f"{weight:.3g} N: phantom.rig's thigh_mass_kg + shank_mass_kg, times g)",
        f"N, with a mean ankle force of {force:.3g} N: the ankle load cells look to be in kN",
    )


def check(recording: Recording, rig: Rig, factors: Mapping, labels: Mapping) -> None:
    """Both unit-slip checks; ``factors``: ``phantom.chain.unit_slips``."""
    check_markers(recording, rig, float(factors["length_factor"]))
    check_load_cells(recording, rig, float(factors["force_factor"]), labels)
