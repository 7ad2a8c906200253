"""Closed-form strength and stiffness checks of the thigh link (seed 001 §4, eq. 5).

The link is a uniform solid rectangular bar of depth H (in the bending plane) and thickness t,
clamped at the knee and loaded at the hip end, with circular holes on its centreline.
Formulas and their sources:
- bending σ = M·y/I, axial σ = N/A, tip deflection F·L³/(3EI) + F·L/(κGA) (κ = 5/6),
  Euler buckling of a clamped–free column P = π²EI_min/(2L)²;
- holes, Roark's Formulas for Stress and Strain (8th ed.) Table 17.1 case 1: axial load
  K_t = 3 − 3.13(d/H) + 3.66(d/H)² − 1.53(d/H)³ on the net section; in-plane bending
  K_t = 2 on the hole-edge stress 12·M·r/[t(H³ − d³)], the net-section outer fibre
  6·M·H/[t(H³ − d³)] checked beside it;
- pin bearing F/(d·t);
- fatigue, Shigley's Mechanical Engineering Design (10th ed.) §6-7 to §6-14: S'e = 0.5·S_ut,
  Marin factors k_a = a·S_ut^b, k_b = 1.24·d_e^−0.107 (d_e = 0.808√(Ht)), k_c, k_d = 1, k_e
  (reliability), Neuber notch sensitivity q, K_f = 1 + q(K_t − 1), finite-life line
  S_f = a·N^b with f = 0.9, modified Goodman 1/n = σ_a/S_f + σ_m/S_ut.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass

import numpy as np

SHEAR_COEFFICIENT = 5.0 / 6.0  # rectangle, Timoshenko
KT_HOLE_BENDING = 2.0  # Roark Table 17.1 case 1c, on the hole-edge nominal stress
KIRSCH_KT = 3.0  # circular hole in an infinite plate under tension: upper bound of Table 17.1
MPA_PER_KPSI = 6.894757
MM_PER_INCH = 25.4
# Shigley Table 6-2: surface factor k_a = a·S_ut^b with S_ut in MPa
SURFACE_FACTORS = {
    "ground": (1.58, -0.085),
    "machined": (4.51, -0.265),
    "hot-rolled": (57.7, -0.718),
    "as-forged": (272.0, -0.995),
}
# Shigley Table 6-5: reliability factor k_e
RELIABILITY_FACTORS = {50: 1.000, 90: 0.897, 95: 0.868, 99: 0.814, 99.9: 0.753, 99.99: 0.702}


@dataclass(frozen=True)
class Section:
    """Solid rectangular section: depth H in the bending plane, thickness t (mm)."""

    depth_mm: float
    thickness_mm: float

    @property
    def area_mm2(self) -> float:
        return self.depth_mm * self.thickness_mm

    @property
    def inertia_mm4(self) -> float:
        return self.thickness_mm * self.depth_mm**3 / 12.0

    @property
    def weak_inertia_mm4(self) -> float:
        return self.depth_mm * self.thickness_mm**3 / 12.0


@dataclass(frozen=True)
class Material:
    """Elastic constants and strengths (MPa)."""

    E_MPa: float
    poisson: float
    yield_MPa: float
    allowable_MPa: float
    ultimate_MPa: float

    @property
    def shear_modulus_MPa(self) -> float:
        return self.E_MPa / (2.0 * (1.0 + self.poisson))


def bending_stress(moment_Nmm: np.ndarray | float, section: Section) -> np.ndarray | float:
    """Outer-fibre bending stress M·(H/2)/I of the gross section (MPa)."""
    return moment_Nmm * section.depth_mm / 2.0 / section.inertia_mm4


def tip_deflection_bending_mm(load_N: float, length_mm: float, E_MPa: float, inertia_mm4: float):
    """Euler–Bernoulli tip deflection of a clamped–free beam with a tip load, F·L³/(3EI)."""
    return load_N * length_mm**3 / (3.0 * E_MPa * inertia_mm4)


def tip_deflection_shear_mm(load_N: float, length_mm: float, material: Material, section: Section):
    """Shear (Timoshenko) part of the tip deflection, F·L/(κGA)."""
    return load_N * length_mm / (SHEAR_COEFFICIENT * material.shear_modulus_MPa * section.area_mm2)


def euler_buckling_N(E_MPa: float, weak_inertia_mm4, length_mm: float):
    """Clamped–free Euler load π²EI_min/(2L)²."""
    return np.pi**2 * E_MPa * weak_inertia_mm4 / (2.0 * length_mm) ** 2


def kt_hole_axial(d_over_H: float) -> float:
    """Roark Table 17.1 case 1a: central circular hole, axial load, net-section K_t."""
    x = d_over_H
    return 3.0 - 3.13 * x + 3.66 * x**2 - 1.53 * x**3


def hole_stresses(
    moment_Nmm: float, axial_N: float, diameter_mm: float, section: Section
) -> dict[str, float]:
    """Peak stresses at a centreline hole: bending (Roark 1c, K_t = 2) and axial (Roark 1a)."""
    H, t, d = section.depth_mm, section.thickness_mm, diameter_mm
    net_cubed = t * (H**3 - d**3)
    hole_nominal = 12.0 * moment_Nmm * (d / 2.0) / net_cubed
    outer_fibre = 6.0 * moment_Nmm * H / net_cubed
    axial_nominal = axial_N / (t * (H - d))
    hole_edge = KT_HOLE_BENDING * hole_nominal
    return {
        "kt_bending": KT_HOLE_BENDING,
        "kt_axial": kt_hole_axial(d / H),
        "bending_hole_nominal_MPa": hole_nominal,
        "axial_net_nominal_MPa": axial_nominal,
        "bending_hole_edge_MPa": hole_edge,
        "bending_net_outer_fibre_MPa": outer_fibre,
        "bending_peak_MPa": max(hole_edge, outer_fibre),
        "axial_peak_MPa": kt_hole_axial(d / H) * axial_nominal,
    }


def marin_endurance_MPa(material: Material, section: Section, fatigue: Mapping) -> dict:
    """Endurance limit S_e = k_a·k_b·k_c·k_d·k_e·0.5·S_ut of the link in bending (Shigley §6-9)."""
    a, b = SURFACE_FACTORS[fatigue["surface"]]
    k_a = a * material.ultimate_MPa**b
    d_e = 0.808 * np.sqrt(section.depth_mm * section.thickness_mm)
    k_b = 1.24 * d_e**-0.107 if d_e <= 51.0 else 1.51 * d_e**-0.157
    k_e = RELIABILITY_FACTORS[fatigue["reliability_pct"]]
    factors = {"k_a": k_a, "k_b": float(k_b), "k_c": 1.0, "k_d": 1.0, "k_e": k_e}
    s_e = 0.5 * material.ultimate_MPa * np.prod(list(factors.values()))
    return {"marin_factors": factors, "endurance_limit_MPa": float(s_e)}


def notch_sensitivity(ultimate_MPa: float, notch_radius_mm: float) -> float:
    """Neuber notch sensitivity q = 1/(1 + √a/√r) of steels in bending (Shigley eq. 6-35a)."""
    s = ultimate_MPa / MPA_PER_KPSI
    sqrt_a = 0.246 - 3.08e-3 * s + 1.51e-5 * s**2 - 2.67e-8 * s**3  # √inch
    return 1.0 / (1.0 + sqrt_a / np.sqrt(notch_radius_mm / MM_PER_INCH))


def fatigue_strength_MPa(ultimate_MPa: float, endurance_MPa: float, cycles: float) -> float:
    """Finite-life strength S_f = a·N^b between 10³ and 10⁶ cycles, f = 0.9 (Shigley eq. 6-13)."""
    if cycles >= 1e6:
        return endurance_MPa
    f_sut = 0.9 * ultimate_MPa
    a = f_sut**2 / endurance_MPa
    b = -np.log10(f_sut / endurance_MPa) / 3.0
    return float(a * max(cycles, 1e3) ** b)


def goodman_safety_factor(sigma_max: float, sigma_min: float, strength: float, ultimate: float):
    """Modified Goodman factor 1/n = σ_a/S_f + σ_m/S_ut; compressive mean: n = S_f/σ_a."""
    amplitude = (sigma_max - sigma_min) / 2.0
    mean = (sigma_max + sigma_min) / 2.0
    if mean <= 0.0:
        return strength / amplitude
    return 1.0 / (amplitude / strength + mean / ultimate)
