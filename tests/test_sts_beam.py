"""Thigh-link checks against an independent 2-D frame FEM (anastruct) and the seed's FEA."""

from __future__ import annotations

import itertools

import numpy as np
import pandas as pd
import pytest
import yaml
from anastruct import SystemElements

from conftest import REPO
from exobench.errors import InputError
from exobench.sts import beam, kinematics, loads, motion, strength

CONFIG = yaml.safe_load((REPO / "config" / "config.yaml").read_text())["sts"]
REPORTED = REPO / "raw" / "reference" / "seed001_reported.csv"


def fem_cantilever(length_mm, E_MPa, section, load_N, angle_rad=np.pi / 2, elements=20):
    """Clamped at the origin, link at ``angle_rad`` from the vertical, vertical tip load."""
    ss = SystemElements(EI=E_MPa * section.inertia_mm4, EA=E_MPa * section.area_mm2)
    tip = length_mm * np.array([np.sin(angle_rad), np.cos(angle_rad)])
    nodes = np.linspace(0.0, 1.0, elements + 1)[:, None] * tip
    for a, b in itertools.pairwise(nodes):
        ss.add_element(location=[a.tolist(), b.tolist()])
    ss.add_support_fixed(node_id=1)
    ss.point_load(node_id=elements + 1, Fy=-load_N)
    ss.solve()
    displacement = ss.get_node_displacements(node_id=elements + 1)
    clamp = ss.get_element_results(element_id=1)
    return {
        "deflection_mm": float(np.hypot(displacement["ux"], displacement["uy"])),
        "moment_Nmm": float(max(abs(clamp["Mmin"]), abs(clamp["Mmax"]))),
        "axial_N": float(max(abs(clamp["Nmin"]), abs(clamp["Nmax"]))),
    }


def _random_cases(count: int):
    rng = np.random.default_rng(101)
    for _ in range(count):
        yield (
            float(rng.uniform(300, 700)),
            beam.Section(float(rng.uniform(20, 90)), float(rng.uniform(5, 25))),
            float(rng.uniform(500, 3000)),
        )


def test_configured_link_matches_the_fem_within_one_percent():
    section, material, _holes = strength.link_from_config(CONFIG["thigh_link"])
    length = CONFIG["links_mm"]["l_BC"]
    load = CONFIG["design_load_N"]
    report = strength.check(
        CONFIG["thigh_link"], load, length, ([745.5], [0.0]), strength.read_reported(REPORTED)
    )
    fem = fem_cantilever(length, material.E_MPa, section, load)
    assert report["tip_deflection_bending_mm"] == pytest.approx(fem["deflection_mm"], rel=0.01)
    fem_stress = fem["moment_Nmm"] * section.depth_mm / 2 / section.inertia_mm4
    assert report["nominal_bending_stress_MPa"] == pytest.approx(fem_stress, rel=0.01)
    assert report["max_bending_moment_Nm"] == pytest.approx(fem["moment_Nmm"] / 1000, rel=0.01)


@pytest.mark.parametrize("case", list(_random_cases(5)))
def test_random_cantilevers_match_the_fem_within_one_percent(case):
    length, section, load = case
    E = 206000.0
    fem = fem_cantilever(length, E, section, load)
    deflection = beam.tip_deflection_bending_mm(load, length, E, section.inertia_mm4)
    assert deflection == pytest.approx(fem["deflection_mm"], rel=0.01)
    stress = beam.bending_stress(load * length, section)
    assert stress == pytest.approx(
        fem["moment_Nmm"] * section.depth_mm / 2 / section.inertia_mm4, rel=0.01
    )


def test_thigh_loads_along_the_motion_match_an_inclined_fem_cantilever():
    chain = kinematics.Chain()
    bodies = loads.Bodies(1500.0, (0.0, 0.0, 0.0))
    sampled = motion.piecewise(motion.time_grid(100.0))
    bending, axial = loads.thigh_loads(chain, bodies, sampled)
    theta = kinematics.link_angles(chain, sampled)[0][:, 1]
    section = beam.Section(60.0, 16.0)
    for k in (10, 60, 120, 170):
        fem = fem_cantilever(500.0, 206000.0, section, 1500.0, angle_rad=float(theta[k]))
        assert bending[k] == pytest.approx(fem["moment_Nmm"] / 1000, rel=0.01)
        assert axial[k] == pytest.approx(fem["axial_N"], rel=0.01)


def test_hole_factors_reach_their_known_limits():
    assert beam.kt_hole_axial(0.0) == pytest.approx(beam.KIRSCH_KT)
    section = beam.Section(60.0, 10.0)
    tiny = beam.hole_stresses(1e6, 0.0, 1e-6, section)
    assert tiny["bending_net_outer_fibre_MPa"] == pytest.approx(beam.bending_stress(1e6, section))
    # a small hole at the neutral axis: twice the beam stress at its edge, 2·M·r/I
    assert tiny["bending_hole_edge_MPa"] == pytest.approx(2 * 1e6 * 0.5e-6 / section.inertia_mm4)


def test_fatigue_line_and_goodman_reduce_to_their_end_points():
    assert beam.fatigue_strength_MPa(400.0, 150.0, 1e6) == pytest.approx(150.0)
    assert beam.fatigue_strength_MPa(400.0, 150.0, 1e3) == pytest.approx(0.9 * 400.0)
    assert beam.goodman_safety_factor(50.0, -50.0, 150.0, 400.0) == pytest.approx(3.0)
    # repeated stress 0 → σ: 1/n = (σ/2)/S_f + (σ/2)/S_ut
    n = beam.goodman_safety_factor(100.0, 0.0, 150.0, 400.0)
    assert 1 / n == pytest.approx(50 / 150 + 50 / 400)


def test_seed_fea_numbers_are_not_one_uniform_cantilever():
    family = strength.seed_fea_family(strength.read_reported(REPORTED), 1500.0, 500.0, 206000.0)
    assert not family["consistent"]
    assert family["members_with_plausible_kt"] > 0
    assert family["max_buckling_load_N"] < 1500.0


def test_numbers_from_a_real_uniform_cantilever_are_recognised_as_consistent():
    rng = np.random.default_rng(5)
    depth, thickness = rng.uniform(30, 80), rng.uniform(10, 30)
    kt_b, kt_c = rng.uniform(1.2, 2.5), rng.uniform(1.2, 2.5)
    load, length, E = 1500.0, 500.0, 206000.0
    inertia, area = thickness * depth**3 / 12, depth * thickness
    # what a tool would report for this bar (written out here, not from the beam module)
    reported = {
        "bending_peak_MPa": kt_b * load * length * depth / 2 / inertia,
        "compression_peak_MPa": [0.99 * kt_c * load / area, 1.01 * kt_c * load / area],
        "tip_deflection_mm": [
            0.99 * load * length**3 / (3 * E * inertia),
            1.01 * load * length**3 / (3 * E * inertia),
        ],
    }
    family = strength.seed_fea_family(reported, load, length, E, grid=81)
    assert family["consistent"]
    assert family["depth_mm_range"][0] <= depth <= family["depth_mm_range"][1]


def test_a_reported_file_without_a_metric_names_it(tmp_path):
    frame = pd.read_csv(REPORTED)
    broken = tmp_path / "seed001_reported.csv"
    frame[frame["metric"] != "fea_tip_deflection_mm"].to_csv(broken, index=False)
    with pytest.raises(InputError, match="fea_tip_deflection_mm") as error:
        strength.read_reported(broken)
    assert str(broken) in str(error.value)
