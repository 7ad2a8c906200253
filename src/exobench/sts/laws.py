"""Motion laws as data: one schema for the study's laws, their readings and any user's law file.

A law (:class:`Law`) gives the joint coordinates (φ1 hip, φ2 knee, φ3 ankle) at knots in time,
how they run between the knots (``linear``: eq. (4)'s straight stages; ``min_jerk``: quintic
segments starting and ending each at rest), the seat's knot (when the seat is reached), the sign
convention (each link's angle from the vertical as a combination of the coordinates, rows CD,
BC, AB), the way the user faces along the study's Dx axis (+1 or −1), the link lengths, the
loaded point and, optionally, the seat height (by default the hip's height at the seat knot).
A reading of the study is the study's law with one facing and one sign convention
(:func:`readings`).
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, replace
from pathlib import Path

import numpy as np
import yaml

from exobench.errors import InputError
from exobench.sts.kinematics import Chain
from exobench.sts.motion import COORDINATES, Motion

INTERPOLATIONS = ("linear", "min_jerk")
LINKS = ("CD", "BC", "AB")


@dataclass(frozen=True)
class Law:
    """One motion law under one reading (module docstring)."""

    name: str
    knots_s: tuple[float, ...]
    angles_rad: np.ndarray  # (knots, 3): φ1, φ2, φ3
    interpolation: str
    seat_s: float
    signs: tuple[tuple[float, float, float], ...]
    facing: int
    links_mm: Mapping
    loaded_point: str = "A"
    seat_height_mm: float | None = None

    @property
    def chain(self) -> Chain:
        """The chain with this law's links and sign convention."""
        return Chain.from_config(self.links_mm, self.signs)

    @property
    def seat_index(self) -> int:
        """Index of the seat knot in ``knots_s``."""
        return self.knots_s.index(self.seat_s)


def _field(source, data: Mapping, key: str, kind=None):
    """One required field of a law mapping, InputError naming it otherwise."""
    if key not in data:
        raise InputError(source, key, f"a law field '{key}'", sorted(data))
    if kind is None:
        return data[key]
    try:
        return kind(data[key])
    except (TypeError, ValueError) as error:
        raise InputError(source, key, f"a {kind.__name__}", data[key]) from error


def _numbers(source, key: str, values) -> list[float]:
    """A list of numbers, InputError naming the field otherwise."""
    try:
        return [float(v) for v in values]
    except (TypeError, ValueError) as error:
        raise InputError(source, key, "a list of numbers", values) from error


def _mapping(source, data: Mapping, key: str) -> Mapping:
    """A required field that is a mapping, InputError naming it otherwise."""
    value = _field(source, data, key)
    if not isinstance(value, Mapping):
        raise InputError(source, key, "a mapping", value)
    return value


def from_mapping(data: Mapping, source: object = "law") -> Law:
    """A law from a law file's mapping; InputError naming the source and field."""
    knots = _numbers(source, "knots_s", _field(source, data, "knots_s"))
    if len(knots) < 2 or knots[0] != 0.0 or np.any(np.diff(knots) <= 0):
        raise InputError(source, "knots_s", "increasing times from 0 s, at least two", knots)
    angles = _mapping(source, data, "angles_deg")
    angles = {c: _numbers(source, f"angles_deg.{c}", v) for c, v in angles.items()}
    if sorted(angles) != sorted(COORDINATES) or any(len(angles[c]) != len(knots) for c in angles):
        raise InputError(source, "angles_deg", f"{list(COORDINATES)}, one angle per knot", angles)
    interpolation = _field(source, data, "interpolation", str)
    if interpolation not in INTERPOLATIONS:
        raise InputError(source, "interpolation", f"one of {list(INTERPOLATIONS)}", interpolation)
    seat = _field(source, data, "seat_s", float)
    if seat not in knots:
        raise InputError(source, "seat_s", f"one of the knots {knots}", seat)
    signs = _mapping(source, data, "signs")
    signs = {k: _numbers(source, f"signs.{k}", v) for k, v in signs.items()}
    if sorted(signs) != sorted(LINKS) or any(len(signs[k]) != 3 for k in LINKS):
        raise InputError(source, "signs", f"rows {list(LINKS)} of three numbers each", signs)
    facing = _field(source, data, "facing", int)
    if facing not in (1, -1):
        raise InputError(source, "facing", "+1 or -1 (the user faces +x or -x)", facing)
    links = _mapping(source, data, "links_mm")
    links = dict(zip(links, _numbers(source, "links_mm", links.values()), strict=True))
    if sorted(links) != ["l_AB", "l_BC", "l_CD"] or min(links.values()) <= 0:
        raise InputError(source, "links_mm", "positive l_CD, l_BC, l_AB (mm)", links)
    point = str(data.get("loaded_point", "A"))
    if point not in ("A", "B", "C"):
        raise InputError(source, "loaded_point", "one of A, B, C", point)
    height = (
        None
        if data.get("seat_height_mm") is None
        else _field(source, data, "seat_height_mm", float)
    )
    return Law(
        str(data.get("name", Path(str(source)).stem)),
        tuple(knots),
        np.radians(np.array([angles[c] for c in COORDINATES], float).T),
        interpolation,
        seat,
        tuple(tuple(float(v) for v in signs[k]) for k in LINKS),
        facing,
        {k: float(v) for k, v in links.items()},
        point,
        height,
    )


def load(path: Path | str) -> Law:
    """A user's law file (YAML, the schema of :func:`from_mapping`)."""
    try:
        data = yaml.safe_load(Path(path).read_text())
    except (OSError, yaml.YAMLError) as error:
        raise InputError(path, "(file)", "a readable YAML law file", str(error)) from error
    if not isinstance(data, Mapping):
        raise InputError(path, "(file)", "a mapping of law fields", type(data).__name__)
    return from_mapping(data, path)


def study_law(sts: Mapping) -> Law:
    """The study's law (``sts.study_law`` on ``sts.links_mm``) as printed, facing +x."""
    rows = sts["readings"]["signs"]["as_written"]["rows"]
    return from_mapping(
        {
            "name": "study",
            **sts["study_law"],
            "signs": rows,
            "facing": 1,
            "links_mm": sts["links_mm"],
        },
        "config: sts.study_law",
    )


def readings(sts: Mapping) -> dict[str, tuple[Law, str, bool]]:
    """Each facing × each sign convention as a law '<signs>, facing ±x', its basis, admitted."""
    base, cfg = study_law(sts), sts["readings"]
    out = {}
    for sign_name, sign in cfg["signs"].items():
        rows = tuple(tuple(float(v) for v in sign["rows"][k]) for k in LINKS)
        for facing_name, facing in cfg["facings"].items():
            name = f"{sign_name}, {facing_name}"
            law = replace(base, name=name, facing=int(facing["facing"]), signs=rows)
            out[name] = (law, f"{sign['basis']}; {facing['basis']}", bool(sign["admitted"]))
    return out


def time_grid(law: Law, sample_rate_Hz: float) -> np.ndarray:
    """Samples from 0 to the last knot with a sample on every knot."""
    steps = np.asarray(law.knots_s) * sample_rate_Hz
    if not np.allclose(steps, np.round(steps)):
        raise InputError(
            "config",
            "sts.sample_rate_Hz",
            f"a rate that puts a sample on every knot of law '{law.name}' {list(law.knots_s)}",
            sample_rate_Hz,
        )
    return np.linspace(0.0, law.knots_s[-1], round(law.knots_s[-1] * sample_rate_Hz) + 1)


def sample(law: Law, t_s: np.ndarray) -> Motion:
    """Linear with impulses Δφ̇/Δt, or q = q₀ + Δq s + T(v₀h₀ + v₁h₁), s = 10τ³ − 15τ⁴ + 6τ⁵."""
    knots = np.asarray(law.knots_s)
    segment = np.clip(np.searchsorted(knots, t_s) - 1, 0, len(knots) - 2)  # a knot ends its stage
    duration = np.diff(knots)[segment][:, None]
    start, change = law.angles_rad[segment], np.diff(law.angles_rad, axis=0)[segment]
    tau = ((t_s - knots[segment]) / duration[:, 0])[:, None]
    if law.interpolation == "linear":
        rate = change / duration
        q, qd = start + change * tau, rate.copy()
        rates = np.vstack(
            [np.zeros(3), np.diff(law.angles_rad, axis=0) / np.diff(knots)[:, None], np.zeros(3)]
        )
        qdd = np.zeros_like(q)
        dt = t_s[1] - t_s[0]
        at = np.searchsorted(t_s, knots - 1e-9)
        qdd[at] = np.diff(rates, axis=0) / dt
        qd[0], qd[-1] = 0.0, 0.0
        return Motion(t_s, q, qd, qdd)
    from scipy.interpolate import PchipInterpolator  # here: the DAG build's config check reads laws

    slopes = PchipInterpolator(knots, law.angles_rad, axis=0).derivative()(knots)
    slopes[[0, -1]] = 0.0
    v0, v1 = slopes[segment] * duration, slopes[segment + 1] * duration
    s, ds, dds = (
        tau**3 * (10 - 15 * tau + 6 * tau**2),
        30 * tau**2 * (1 - tau) ** 2,
        (60 * tau * (1 - tau) * (1 - 2 * tau)),
    )
    h0 = (
        tau - 6 * tau**3 + 8 * tau**4 - 3 * tau**5,
        1 - 18 * tau**2 + 32 * tau**3 - 15 * tau**4,
        -36 * tau + 96 * tau**2 - 60 * tau**3,
    )
    h1 = (
        -4 * tau**3 + 7 * tau**4 - 3 * tau**5,
        -12 * tau**2 + 28 * tau**3 - 15 * tau**4,
        -24 * tau + 84 * tau**2 - 60 * tau**3,
    )
    q = start + change * s + v0 * h0[0] + v1 * h1[0]
    qd = (change * ds + v0 * h0[1] + v1 * h1[1]) / duration
    qdd = (change * dds + v0 * h0[2] + v1 * h1[2]) / duration**2
    return Motion(t_s, q, qd, qdd)
