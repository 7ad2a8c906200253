"""The user's body on the chain, and the seat: segment masses and centres from an anthropometric
table (the ``sts.body`` block names its source), the seat's contact and the support that bears
the weight at each sample.

The body rides on the chain's links: the shanks on CD, the thighs on BC, the trunk with the head
and neck and the arms (crossed on the chest, their mass at the shoulder) along AB's direction
from the hip. Segment lengths not on the chain (hip to shoulder, hip to ear) follow from the
stature the leg links imply with the table's leg proportions, H = (l_CD + l_BC)/(r_shank +
r_thigh). The feet stay on the ground and carry their own weight: they are left out of the centre
of mass whose support is judged. Positions are in the forward frame (x the way the user faces).
The seat: the hip B is on it from the first sample at which its height is at or below the seat's;
from then on the seat (under the hip: the ischia) and the feet share the weight, so a static
posture stands when the centre of mass lies between the hip and the toes (the sitting base);
before contact the feet carry it all (the standing base, heel to toe).
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass

import numpy as np

from exobench.errors import InputError

SEGMENTS = ("shank", "thigh", "trunk", "head_neck", "arms")
GRAVITY_M_PER_S2 = 9.81


@dataclass(frozen=True)
class Body:
    """Segment mass fractions (both sides), centres (m from the proximal joint), ankle height."""

    fractions: np.ndarray  # SEGMENTS order
    shank_from_knee: float  # fraction of CD from C
    thigh_from_hip: float  # fraction of BC from B
    trunk_centre_m: float  # along AB's direction from B
    shoulder_m: float
    ear_m: float
    source: str
    ankle_height_m: float = 0.0  # the ankle joint above the floor

    @classmethod
    def from_config(cls, cfg: Mapping, links_mm: Mapping) -> Body:
        """The ``sts.body`` block on the configured links (stature from the leg links)."""
        mass, centre, length = (
            cfg["mass_fraction"],
            cfg["centre_from_proximal"],
            cfg["length_per_stature"],
        )
        for name, block in (("mass_fraction", mass), ("length_per_stature", length)):
            for key, value in block.items():
                if not 0.0 < float(value) < 1.0:
                    raise InputError(
                        "config", f"sts.body.{name}.{key}", "a fraction in (0, 1)", value
                    )
        stature_m = (
            (links_mm["l_CD"] + links_mm["l_BC"]) / 1000.0 / (length["shank"] + length["thigh"])
        )
        trunk_m = length["trunk"] * stature_m
        fractions = np.array(
            [
                2 * mass["shank"],
                2 * mass["thigh"],
                mass["trunk"],
                mass["head_neck"],
                2 * mass["arm"],
            ]
        )
        return cls(
            fractions,
            float(centre["shank"]),
            float(centre["thigh"]),
            float(centre["trunk"]) * trunk_m,
            trunk_m,
            float(length["hip_to_ear"]) * stature_m,
            str(cfg["source"]),
            float(cfg["ankle_height_per_stature"]) * stature_m,
        )


def segment_centres(body: Body, points: np.ndarray) -> np.ndarray:
    """Segment centres (..., 5, xy) from C, B, A: on CD, on BC, along AB's direction from B."""
    c, b, a = points[..., 0, :], points[..., 1, :], points[..., 2, :]
    trunk = a - b
    unit = trunk / np.linalg.norm(trunk, axis=-1, keepdims=True)
    shank = (1.0 - body.shank_from_knee) * c
    thigh = b + body.thigh_from_hip * (c - b)
    along = [b + d * unit for d in (body.trunk_centre_m, body.ear_m, body.shoulder_m)]
    return np.stack([shank, thigh, *along], axis=-2)


def centre_of_mass(body: Body, points: np.ndarray) -> np.ndarray:
    """The body's centre of mass (..., xy) without the feet: Σ f_i r_i / Σ f_i."""
    return segment_centres(body, points).swapaxes(-1, -2) @ body.fractions / body.fractions.sum()


def centre_of_pressure(body: Body, t_s: np.ndarray, points: np.ndarray) -> np.ndarray:
    """Feet's centre of pressure about the floor: x_p = Σf(x(g + ÿ) − (y + h_ankle)ẍ)/Σf(g + ÿ)."""
    r = segment_centres(body, points)
    acc = np.gradient(np.gradient(r, t_s, axis=0), t_s, axis=0)
    vertical = GRAVITY_M_PER_S2 + acc[..., 1]
    moment = r[..., 0] * vertical - (r[..., 1] + body.ankle_height_m) * acc[..., 0]
    return (moment @ body.fractions) / (vertical @ body.fractions)


def contact_index(hip_height_m: np.ndarray, seat_m: float) -> int | None:
    """The first sample with the hip on the seat (height ≤ seat + 1 µm), None if never."""
    on = np.flatnonzero(hip_height_m <= seat_m + 1e-6)
    return int(on[0]) if on.size else None
