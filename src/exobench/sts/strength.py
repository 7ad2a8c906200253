"""Thigh-link load cases of the pelvis–foot study (standing, sitting, the motion between) and the
report."""

from __future__ import annotations

from collections.abc import Mapping
from pathlib import Path

import numpy as np
import pandas as pd

from exobench.errors import InputError
from exobench.sts import beam
from exobench.sts.beam import Material, Section
from exobench.studies import STS

SQRT3 = np.sqrt(3.0)


def link_from_config(cfg: Mapping) -> tuple[Section, Material, list[dict]]:
    """Section, material and holes of the ``sts.thigh_link`` config block."""
    section = Section(cfg["section"]["depth_mm"], cfg["section"]["thickness_mm"])
    m = cfg["material"]
    material = Material(
        m["E_MPa"], m["poisson"], m["yield_MPa"], m["allowable_MPa"], m["ultimate_MPa"]
    )
    return section, material, [dict(h) for h in cfg["holes"]]


def sitting_case(load_N: float, length_mm: float, section: Section, holes: list[dict]) -> dict:
    """Horizontal thigh: tip load F, bending M(x) = F·(L − x) from the knee (x = 0), eq. (5)."""
    moment = load_N * length_mm
    points = {"clamp outer fibre": beam.bending_stress(moment, section)}
    points["neutral axis shear (von Mises)"] = SQRT3 * 1.5 * load_N / section.area_mm2
    per_hole = {}
    for hole in holes:
        local = load_N * (length_mm - hole["position_mm"])
        per_hole[hole["name"]] = beam.hole_stresses(local, 0.0, hole["diameter_mm"], section)
        points[f"hole {hole['name']}"] = per_hole[hole["name"]]["bending_peak_MPa"]
    location = max(points, key=points.get)
    return {
        "moment_Nm": moment / 1000.0,
        "nominal_stress_MPa": points["clamp outer fibre"],
        "peak_von_mises_MPa": points[location],
        "peak_location": location,
        "holes": per_hole,
    }


def standing_case(load_N: float, section: Section, holes: list[dict]) -> dict:
    """Upright link: axial compression F; hole peaks (Roark 1a) and pin bearing F/(d·t)."""
    nominal = load_N / section.area_mm2
    peaks = {"gross section": nominal}
    for hole in holes:
        stresses = beam.hole_stresses(0.0, load_N, hole["diameter_mm"], section)
        peaks[f"hole {hole['name']}"] = stresses["axial_peak_MPa"]
    pins = [h for h in holes if h.get("pin", False)]
    bearing = max((load_N / (h["diameter_mm"] * section.thickness_mm) for h in pins), default=0.0)
    location = max(peaks, key=peaks.get)
    return {
        "nominal_stress_MPa": nominal,
        "peak_stress_MPa": peaks[location],
        "peak_location": location,
        "pin_bearing_stress_MPa": bearing,
    }


def fatigue_check(
    load_N: float,
    length_mm: float,
    section: Section,
    material: Material,
    holes: list[dict],
    fatigue: Mapping,
) -> dict:
    """Each sit-to-stand cycles every point from standing compression to sitting bending tension.

    Points: the clamp outer fibre (K_t = 1), each hole edge (bending K_t = 2, axial Roark 1a)
    and each net-section outer fibre; K_f = 1 + q(K_t − 1) with q at the hole radius; the
    safety factor is the smallest modified-Goodman factor at the stated number of cycles.
    """
    endurance = beam.marin_endurance_MPa(material, section, fatigue)
    strength = beam.fatigue_strength_MPa(
        material.ultimate_MPa, endurance["endurance_limit_MPa"], fatigue["cycles"]
    )
    cycles = {
        "clamp outer fibre": (
            beam.bending_stress(load_N * length_mm, section),
            -load_N / section.area_mm2,
        )
    }
    for hole in holes:
        d = hole["diameter_mm"]
        moment = load_N * (length_mm - hole["position_mm"])
        stresses = beam.hole_stresses(moment, load_N, d, section)
        q = beam.notch_sensitivity(material.ultimate_MPa, d / 2.0)
        kf_bending = 1.0 + q * (stresses["kt_bending"] - 1.0)
        kf_axial = 1.0 + q * (stresses["kt_axial"] - 1.0)
        axial_net = stresses["axial_net_nominal_MPa"]
        cycles[f"hole {hole['name']} edge"] = (
            kf_bending * stresses["bending_hole_nominal_MPa"],
            -kf_axial * axial_net,
        )
        cycles[f"hole {hole['name']} net outer fibre"] = (
            stresses["bending_net_outer_fibre_MPa"],
            -axial_net,
        )
    factors = {
        point: beam.goodman_safety_factor(hi, lo, strength, material.ultimate_MPa)
        for point, (hi, lo) in cycles.items()
    }
    critical = min(factors, key=factors.get)
    return {
        **endurance,
        "cycles": fatigue["cycles"],
        "fatigue_strength_MPa": strength,
        "stress_cycles_MPa": {p: {"max": hi, "min": lo} for p, (hi, lo) in cycles.items()},
        "goodman_safety_factors": factors,
        "critical_point": critical,
        "safety_factor": factors[critical],
    }


def seed_fea_family(
    reported: Mapping, load_N: float, length_mm: float, E_MPa: float, grid: int = 41
) -> dict:
    """Uniform solid rectangular cantilevers (L, tip load F) reproducing all three FEA results.

    For every bending K_t in [1, 3] (3 = Kirsch, the hole factor's upper bound), deflection and
    compression peak in their reported ranges: I follows from the deflection (F·L³/3Eδ), the
    section modulus from the bending peak (K_t·F·L/σ), so depth H = 2I/W and thickness
    t = 12I/H³; the compression peak then fixes the axial K_t = σ_c·H·t/F. A member is
    consistent when that K_t lies in [1, 3] and the bar does not buckle (π²EI_min/(2L)² ≥ F).
    """
    kt_b, delta, sigma_c = np.meshgrid(
        np.linspace(1.0, beam.KIRSCH_KT, grid),
        np.linspace(*reported["tip_deflection_mm"], grid),
        np.linspace(*reported["compression_peak_MPa"], grid),
        indexing="ij",
    )
    inertia = load_N * length_mm**3 / (3.0 * E_MPa * delta)
    modulus = kt_b * load_N * length_mm / reported["bending_peak_MPa"]
    depth = 2.0 * inertia / modulus
    thickness = 12.0 * inertia / depth**3
    kt_c = sigma_c * depth * thickness / load_N
    buckling = beam.euler_buckling_N(E_MPa, depth * thickness**3 / 12.0, length_mm)
    plausible_kt = (kt_c >= 1.0) & (kt_c <= beam.KIRSCH_KT)
    consistent = plausible_kt & (buckling >= load_N)
    # any section shape: I/A is the squared radius of gyration, bounded by the largest K_t
    area_max = beam.KIRSCH_KT * load_N / np.min(sigma_c)
    members = plausible_kt if plausible_kt.any() else np.ones_like(plausible_kt)
    return {
        "members_with_plausible_kt": int(plausible_kt.sum()),
        "members_consistent": int(consistent.sum()),
        "depth_mm_range": [float(depth[members].min()), float(depth[members].max())],
        "thickness_mm_range": [float(thickness[members].min()), float(thickness[members].max())],
        "max_buckling_load_N": float(buckling[members].max()),
        "required_inertia_mm4_range": [float(inertia.min()), float(inertia.max())],
        "max_area_mm2_any_shape": float(area_max),
        "min_radius_of_gyration_mm_any_shape": float(np.sqrt(inertia.min() / area_max)),
        "consistent": bool(consistent.any()),
    }


def configured_section_needs(
    reported: Mapping, sitting: Mapping, standing: Mapping, load_N: float, deflection_mm: float
) -> dict:
    """Loads at which the configured link would show each reported FEA number (linear scaling)."""
    return {
        "load_for_bending_peak_N": load_N
        * reported["bending_peak_MPa"]
        / sitting["peak_von_mises_MPa"],
        "load_for_compression_peak_N": load_N
        * float(np.mean(reported["compression_peak_MPa"]))
        / standing["peak_stress_MPa"],
        "load_for_tip_deflection_N": load_N
        * float(np.mean(reported["tip_deflection_mm"]))
        / deflection_mm,
    }


REPORTED_COLUMNS = ("metric", "low", "high", "unit", "source")
FEA_METRICS = {
    "bending_peak_MPa": "fea_bending_von_mises_peak_MPa",
    "compression_peak_MPa": "fea_compression_peak_MPa",
    "tip_deflection_mm": "fea_tip_deflection_mm",
}


def read_reported(path: str | Path) -> dict:
    """The pelvis–foot study's FEA numbers (raw/reference/seed001_reported.csv) as ranges."""
    frame = pd.read_csv(path)
    for column in REPORTED_COLUMNS:
        if column not in frame.columns:
            raise InputError(path, column, f"columns {', '.join(REPORTED_COLUMNS)}")
    rows = frame.set_index("metric")
    out = {}
    for key, metric in FEA_METRICS.items():
        if metric not in rows.index:
            raise InputError(path, "metric", f"a row '{metric}'")
        low, high = float(rows.loc[metric, "low"]), float(rows.loc[metric, "high"])
        if not 0.0 < low <= high:
            raise InputError(path, metric, f"0 < low <= high, found {low}, {high}")
        out[key] = [low, high]
    out["bending_peak_MPa"] = float(np.mean(out["bending_peak_MPa"]))
    return out


def check(
    cfg: Mapping,
    load_N: float,
    length_mm: float,
    motion_loads: tuple[np.ndarray, np.ndarray],
    reported: Mapping,
) -> dict:
    """Every closed-form check of the thigh link and the comparison with the study's FEA.

    ``motion_loads`` are the thigh's bending moment (N·m) and axial compression (N) along
    the motion; their combined outer-fibre stress N/A + M·(H/2)/I is reported at its peak.
    """
    section, material, holes = link_from_config(cfg)
    moment_Nm, axial_N = (np.asarray(x, dtype=float) for x in motion_loads)
    combined = axial_N / section.area_mm2 + beam.bending_stress(1000.0 * moment_Nm, section)
    sitting = sitting_case(load_N, length_mm, section, holes)
    standing = standing_case(load_N, section, holes)
    bending_deflection = beam.tip_deflection_bending_mm(
        load_N, length_mm, material.E_MPa, section.inertia_mm4
    )
    shear_deflection = beam.tip_deflection_shear_mm(load_N, length_mm, material, section)
    buckling = beam.euler_buckling_N(material.E_MPa, section.weak_inertia_mm4, length_mm)
    fatigue = fatigue_check(load_N, length_mm, section, material, holes, cfg["fatigue"])
    family = seed_fea_family(reported, load_N, length_mm, material.E_MPa)
    needs = configured_section_needs(
        reported, sitting, standing, load_N, bending_deflection + shear_deflection
    )
    peak = sitting["peak_von_mises_MPa"]
    return {
        "design_load_N": load_N,
        "link_length_mm": length_mm,
        "section": {
            "depth_mm": section.depth_mm,
            "thickness_mm": section.thickness_mm,
            "area_mm2": section.area_mm2,
            "inertia_mm4": section.inertia_mm4,
        },
        "max_bending_moment_Nm": sitting["moment_Nm"],
        "max_bending_moment_motion_Nm": float(moment_Nm.max()),
        "max_combined_stress_motion_MPa": float(combined.max()),
        "nominal_bending_stress_MPa": sitting["nominal_stress_MPa"],
        "nominal_axial_stress_MPa": standing["nominal_stress_MPa"],
        "peak_stress_MPa": peak,
        "peak_stress_location": sitting["peak_location"],
        "compression_peak_stress_MPa": standing["peak_stress_MPa"],
        "compression_peak_location": standing["peak_location"],
        "pin_bearing_stress_MPa": standing["pin_bearing_stress_MPa"],
        "holes": sitting["holes"],
        "tip_deflection_mm": bending_deflection + shear_deflection,
        "tip_deflection_bending_mm": bending_deflection,
        "tip_deflection_shear_mm": shear_deflection,
        "buckling_load_N": buckling,
        "buckling_safety_factor": buckling / load_N,
        "safety_factor_yield": material.yield_MPa / peak,
        "safety_factor_allowable": material.allowable_MPa / peak,
        "fatigue": fatigue,
        "fatigue_safety_factor": fatigue["safety_factor"],
        "seed_fea": dict(reported),
        "seed_fea_family": family,
        "configured_section_would_need": needs,
        "seed_fea_consistent": family["consistent"],
        "explanation": explain(family, needs, reported, load_N, length_mm, sitting),
    }


def explain(family, needs, reported, load_N, length_mm, sitting) -> str:
    """Plain-language reading of the consistency analysis, numbers included."""
    depth, thickness = family["depth_mm_range"], family["thickness_mm_range"]
    verdict = (
        "can all come from one uniform cantilever"
        if family["consistent"]
        else "cannot all come from one uniform cantilever"
    )
    return (
        f"The FEA numbers of {STS.key} ({reported['bending_peak_MPa']:g} MPa bending peak, "
        f"{reported['compression_peak_MPa'][0]:g}-{reported['compression_peak_MPa'][1]:g} MPa "
        f"compression, {reported['tip_deflection_mm'][0]:g}-{reported['tip_deflection_mm'][1]:g}"
        f" mm tip deflection) {verdict} of length {length_mm:g} mm under {load_N:g} N. "
        f"The deflection needs I >= {family['required_inertia_mm4_range'][0]:.3g} mm^4 while the "
        f"compression peak allows at most {family['max_area_mm2_any_shape']:.0f} mm^2 of section "
        f"even with K_t = 3, so any shape needs a radius of gyration of at least "
        f"{family['min_radius_of_gyration_mm_any_shape']:.0f} mm. Solid rectangles that match "
        f"all three with plausible K_t are {depth[0]:.0f}-{depth[1]:.0f} mm deep and "
        f"{thickness[0]:.2f}-{thickness[1]:.2f} mm thick and buckle at "
        f"{family['max_buckling_load_N']:.3g} N at most. The configured link would show the "
        f"bending peak at {needs['load_for_bending_peak_N']:.0f} N, the compression peak at "
        f"{needs['load_for_compression_peak_N']:.0f} N and the deflection at "
        f"{needs['load_for_tip_deflection_N']:.0f} N; its own peak under the design load is "
        f"{sitting['peak_von_mises_MPa']:.0f} MPa ({sitting['peak_location']}). The FEA cases "
        "therefore used different loads, levers or boundary conditions than the stated "
        "1500 N cantilever, or the bending peak is a local load-introduction stress: in a "
        "tip-loaded cantilever the moment at the loaded end, where the study places its peak, "
        "is close to zero."
    )
