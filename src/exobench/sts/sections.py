"""The section search: which thigh links give the study's deflection and compression peak, and
what the study's numbers imply whatever the section.

Every depth H, thickness t, pin diameter d and material (``sts.sections``, each range with its
source) is screened with closed forms on the configured bar (lever a from the built-in end to
the hip pin, free end l): the tip deflection δ = F a²(a/3 + (l − a)/2)/(EI) + F a/(κGA) and the
compression peak K·F/(d t), K the bearing factor of the configured link's finite elements (its
compression peak over F/(d t)). Each material's candidates nearest to the study's two numbers
(the larger of the two relative misses against the midpoints of the study's ranges) are
confirmed by finite elements (:mod:`exobench.sts.fea`), the study's material first.
The section-free relation of a tip-loaded cantilever, δ/σ_clamp = a²/(3Ec) (c = H/2), states
what a deflection and a clamp stress imply together: the depth 2a²σ/(3Eδ) they need.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import replace

import numpy as np

from exobench.sts import beam, elastic, fea
from exobench.sts.mesh import Hole


def midpoint(reported_range) -> float:
    """The midpoint of one of the study's ranges, the target the search's misses are taken from."""
    return float(np.mean(reported_range))


def grid(cfg: Mapping) -> dict[str, np.ndarray]:
    """Every combination of the ranges (flattened), materials by name."""
    names = list(cfg["materials"])
    h, t, d, m = np.meshgrid(
        cfg["depth_mm"]["values"],
        cfg["thickness_mm"]["values"],
        cfg["pin_diameter_mm"]["values"],
        np.arange(len(names)),
        indexing="ij",
    )
    keep = d <= h / 2  # a pin at most half the depth leaves the lug's sides
    material = np.array(names)[m[keep]]
    return {
        "depth_mm": h[keep].astype(float),
        "thickness_mm": t[keep].astype(float),
        "pin_diameter_mm": d[keep].astype(float),
        "material": material,
        "E_MPa": np.array([cfg["materials"][n]["E_MPa"] for n in material], float),
        "poisson": np.array([cfg["materials"][n]["poisson"] for n in material], float),
    }


def screen(candidates: Mapping, link: fea.Link, bearing_factor: float, reported: Mapping) -> dict:
    """Closed-form δ and K·F/(d t) of every candidate, miss = max |x/x_study − 1| (midpoints)."""
    h, t, d = candidates["depth_mm"], candidates["thickness_mm"], candidates["pin_diameter_mm"]
    E, nu, force = candidates["E_MPa"], candidates["poisson"], link.load_N
    a = link.length_mm + link.margin_mm
    free = link.bar.x1_mm - link.bar.x0_mm
    inertia, area = t * h**3 / 12.0, t * h
    shear = force * a / (beam.SHEAR_COEFFICIENT * E / (2 * (1 + nu)) * area)
    deflection = force * a**2 * (a / 3 + (free - a) / 2) / (E * inertia) + shear
    compression = bearing_factor * force / (d * t)
    want_d, want_c = (
        midpoint(reported["tip_deflection_mm"]),
        midpoint(reported["compression_peak_MPa"]),
    )
    miss = np.maximum(np.abs(deflection / want_d - 1), np.abs(compression / want_c - 1))
    return {
        **candidates,
        "deflection_mm": deflection,
        "compression_peak_MPa": compression,
        "clamp_stress_MPa": force * a * (h / 2) / inertia,
        "miss": miss,
    }


def candidate_link(
    link: fea.Link, depth: float, thickness: float, pin: float, E: float, poisson: float
) -> fea.Link:
    """The configured link with another section, pins and material (holes kept where they fit)."""
    holes = tuple(
        replace(h, diameter_mm=pin) if h.name.endswith("pin") else h
        for h in link.bar.holes
        if h.name.endswith("pin") or h.diameter_mm <= depth / 2
    )
    bar = replace(
        link.bar,
        depth_mm=depth,
        holes=tuple(Hole(h.name, h.x_mm, h.y_mm, h.diameter_mm) for h in holes),
    )
    section = beam.Section(depth, thickness)
    return replace(link, bar=bar, section=section, plate=elastic.Plate(E, poisson, thickness))


def confirm(link: fea.Link, size_mm: float, hole_size_mm: float) -> dict:
    """One candidate's FE deflection, compression peak and loaded-end bending peak."""
    results = fea.level_results(link, fea.solve_level(link, size_mm, hole_size_mm))
    return {
        "fe_deflection_mm": results["bending"]["max_displacement_mm"],
        "fe_compression_peak_MPa": results["compression"]["peak"]["MPa"],
        "fe_loaded_end_peak_MPa": results["bending"]["loaded_end_peak"]["MPa"],
        "fe_peak_MPa": results["bending"]["peak"]["MPa"],
        "fe_peak_where": results["bending"]["peak"]["where"],
    }


def bearing_factor(link: fea.Link, report: Mapping) -> float:
    """K = σ_compression,FE / (F/(d t)) of the configured link's finest mesh."""
    nominal = link.load_N / (link.pin.diameter_mm * link.plate.thickness_mm)
    return float(report["finest"]["compression"]["peak"]["MPa"] / nominal)


def search(
    cfg: Mapping,
    link: fea.Link,
    bearing_factor: float,
    reported: Mapping,
    sizes: tuple[float, float],
) -> tuple[list[dict], int]:
    """Each material's best ``confirm`` screened candidates by FE, the study's material first."""
    screened = screen(grid(cfg), link, bearing_factor, reported)
    names = sorted(cfg["materials"], key=lambda n: n != cfg["study_material"])
    order = [
        k
        for name in names
        for k in np.flatnonzero(screened["material"] == name)[
            np.argsort(screened["miss"][screened["material"] == name], kind="stable")
        ][: int(cfg["materials"][name]["confirm"])]
    ]
    tolerance = float(cfg["tolerance_pct"]) / 100.0
    want_d, want_c = (
        midpoint(reported["tip_deflection_mm"]),
        midpoint(reported["compression_peak_MPa"]),
    )
    rows = []
    for k in order:
        row = {
            key: (value[k].item() if hasattr(value[k], "item") else value[k])
            for key, value in screened.items()
        }
        fe = confirm(
            candidate_link(
                link,
                row["depth_mm"],
                row["thickness_mm"],
                row["pin_diameter_mm"],
                row["E_MPa"],
                row["poisson"],
            ),
            *sizes,
        )
        row.update(fe)
        row["study_material"] = row["material"] == cfg["study_material"]
        row["fe_deflection_miss_pct"] = 100 * (fe["fe_deflection_mm"] / want_d - 1)
        row["fe_compression_miss_pct"] = 100 * (fe["fe_compression_peak_MPa"] / want_c - 1)
        row["confirmed"] = bool(
            abs(row["fe_deflection_miss_pct"]) <= 100 * tolerance
            and abs(row["fe_compression_miss_pct"]) <= 100 * tolerance
        )
        rows.append(row)
    return rows, int(screened["miss"].size)


def implied(reported: Mapping, lever_mm: float, E_MPa: float, depth_mm: float) -> dict:
    """δ/σ_clamp = a²/(3Ec): depth 2a²σ/(3Eδ) for the study's pair, clamp stress 3Ecδ/a²."""
    deflection = midpoint(reported["tip_deflection_mm"])
    stress = float(reported["bending_peak_MPa"])
    return {
        "lever_mm": lever_mm,
        "E_MPa": E_MPa,
        "ratio_mm_per_MPa_for_depth": lever_mm**2 / (3 * E_MPa * depth_mm / 2),
        "study_deflection_mm": deflection,
        "study_ratio_mm_per_MPa": deflection / stress,
        "depth_if_peak_were_clamp_stress_mm": 2 * lever_mm**2 * stress / (3 * E_MPa * deflection),
        "clamp_stress_for_study_deflection_MPa": 3
        * E_MPa
        * (depth_mm / 2)
        * deflection
        / lever_mm**2,
        "depth_mm": depth_mm,
    }
