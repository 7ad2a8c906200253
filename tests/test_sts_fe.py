"""The plane-stress solver against closed forms (a plate with a hole in tension, a cantilever's
tip deflection), the pin's bearing load and the curved hole edges, on coarse meshes."""

from __future__ import annotations

import numpy as np
import pytest
import yaml

from conftest import REPO
from exobench.errors import InputError
from exobench.sts import elastic, fea, mesh, sections

CONFIG = yaml.safe_load((REPO / "config" / "config.yaml").read_text())["sts"]


def roark_kt_net(d_over_w: float) -> float:
    """Roark's Formulas for Stress and Strain (8th ed.), Table 17.1 case 1a: a central circular
    hole in a plate of finite width under tension, K_t on the net-section stress (typed out
    here, not taken from exobench.sts.beam)."""
    x = d_over_w
    return 3.0 - 3.13 * x + 3.66 * x**2 - 1.53 * x**3


def tension_ends(basis, half_length: float, stress: float):
    """Uniform tension ``stress`` (MPa) on both ends x = ±half_length of a unit-thick plate."""
    out = 0.0
    for side in (-1.0, 1.0):
        end = basis.mesh.facets_satisfying(lambda x, s=side: np.isclose(x[0], s * half_length),
                                           boundaries_only=True)  # fmt: skip
        out = out + elastic.traction(
            basis, end, lambda x, y, s=side: np.array([s * stress + 0 * y, 0 * y]), 1.0
        )
    return out


@pytest.mark.parametrize("d_over_w", [0.1, float(np.random.default_rng(42).uniform(0.15, 0.4))])
def test_a_plate_with_a_hole_in_tension_reaches_roarks_stress_concentration(d_over_w):
    width, length = 100.0, 400.0
    d = d_over_w * width
    bar = mesh.Bar(-length / 2, length / 2, width, (mesh.Hole("hole", 0.0, 0.0, d),))
    basis = elastic.vector_basis(mesh.bar_mesh(bar, size=15.0, hole_size=d / 24))
    plate = elastic.Plate(200000.0, 0.3, 1.0)
    nodal = basis.nodal_dofs
    xy = basis.doflocs[:, nodal[0]]
    # remove the rigid motions only: x at the ends of the vertical centre line, y at one end
    top = int(np.argmin(np.hypot(xy[0], xy[1] - width / 2)))
    bottom = int(np.argmin(np.hypot(xy[0], xy[1] + width / 2)))
    right = int(np.argmin(np.hypot(xy[0] - length / 2, xy[1])))
    fixed = np.array([nodal[0, top], nodal[0, bottom], nodal[1, right]])
    u = elastic.solve(elastic.stiffness(basis, plate), tension_ends(basis, length / 2, 1.0),
                      fixed)  # fmt: skip
    stress = elastic.nodal_stresses(basis, u, plate)[0]
    net = 1.0 / (1.0 - d_over_w)  # net-section stress for a unit remote stress
    assert stress.sxx.max() == pytest.approx(roark_kt_net(d_over_w) * net, rel=0.03)
    assert stress.von_mises.max() == pytest.approx(stress.sxx.max(), rel=0.01)


def test_a_cantilever_deflects_as_euler_bernoulli_with_shear():
    length, depth, t, force, E, nu = 400.0, 40.0, 10.0, 1000.0, 206000.0, 0.3
    basis = elastic.vector_basis(mesh.bar_mesh(mesh.Bar(0.0, length, depth), 8.0, 8.0))
    plate = elastic.Plate(E, nu, t)
    fixed, reaction = elastic.built_in_end(basis, 0.0, depth, force, t)
    tip = basis.mesh.facets_satisfying(lambda x: np.isclose(x[0], length), boundaries_only=True)
    peak = 1.5 * force / (t * depth)
    load = elastic.traction(
        basis, tip, lambda x, y: np.array([0 * y, -peak * (1 - (2 * y / depth) ** 2)]), t
    )
    u = elastic.solve(elastic.stiffness(basis, plate), load + reaction, fixed)[:, 0]
    inertia, area = t * depth**3 / 12, t * depth
    closed_form = force * length**3 / (3 * E * inertia) + force * length / (
        5 / 6 * E / (2 * (1 + nu)) * area
    )
    deflection = -elastic.vertex_displacements(basis, u)[1].min()
    assert deflection == pytest.approx(closed_form, rel=0.03)
    stress = elastic.nodal_stresses(basis, u, plate)[0]
    at_end = np.isclose(stress.x_mm, 0.0)
    assert stress.sxx[at_end].max() == pytest.approx(6 * force * length / (t * depth**2), rel=0.05)


@pytest.mark.parametrize("angle", [-np.pi / 2, np.pi, 0.7])
def test_the_bearing_pressure_adds_up_to_the_pin_force(angle):
    hole = mesh.Hole("pin", 0.0, 0.0, 12.0)
    basis = elastic.vector_basis(mesh.bar_mesh(mesh.Bar(-40.0, 40.0, 60.0, (hole,)), 8.0, 1.0))
    load = elastic.bearing(basis, hole, 1500.0, angle, 16.0)
    resultant = np.array(
        [
            load[basis.nodal_dofs[0]].sum() + load[basis.facet_dofs[0]].sum(),
            load[basis.nodal_dofs[1]].sum() + load[basis.facet_dofs[1]].sum(),
        ]
    )
    np.testing.assert_allclose(resultant, 1500.0 * np.array([np.cos(angle), np.sin(angle)]),
                               atol=1.0)  # fmt: skip


def test_the_hole_edges_are_curved_and_found():
    hole = mesh.Hole("pin", 5.0, 0.0, 12.0)
    quadratic = mesh.bar_mesh(mesh.Bar(-30.0, 30.0, 40.0, (hole,)), 6.0, 2.0)
    facets = mesh.hole_facets(quadratic, hole)
    assert len(facets) >= 12
    # the mid-side nodes of the hole's edges lie on the circle, not on the chords
    vertices = quadratic.t.max() + 1
    middle = quadratic.doflocs[:, vertices + facets]
    np.testing.assert_allclose(np.hypot(middle[0] - 5.0, middle[1]), 6.0, atol=1e-6)


def test_the_link_config_refuses_a_hole_outside_the_bar():
    cfg = yaml.safe_load(yaml.safe_dump(CONFIG["thigh_link"]))
    cfg["holes"][-1]["position_mm"] = 515.0  # the hip pin's edge beyond the bar's end
    with pytest.raises(InputError, match=r"sts\.thigh_link\.holes") as error:
        fea.link_from_config(cfg, 500.0, 1500.0)
    assert "hip pin" in str(error.value)


def test_peaks_are_named_by_where_they_are():
    link = fea.link_from_config(CONFIG["thigh_link"], 500.0, 1500.0)
    assert fea.where(link, 500.0, -6.2) == "edge of the hip pin hole"
    assert fea.where(link, -20.0, 30.0) == "built-in end, outer fibre"
    assert fea.where(link, 250.0, -30.0) == "outer fibre at 250 mm from the knee pin"
    assert fea.power_law([4.0, 2.0, 1.0], [10.0, 20.0, 40.0]) == pytest.approx((1.0, 40.0))


def test_a_fully_fixed_face_is_a_singular_corner():
    """The study's support: the peak at the fixed corner keeps growing as the corner's elements
    shrink (no converged stress) while the deflection settles (the configured support's
    convergence is checked on the small run's fe.json)."""
    link = fea.link_from_config(CONFIG["thigh_link"], CONFIG["links_mm"]["l_BC"],
                                CONFIG["design_load_N"])  # fmt: skip
    fixed = fea.fixed_support(link, {**CONFIG["fe"], "fixed_face": {
        "element_mm": 16.0, "corner_element_mm": [8.0, 4.0, 1.0]}})  # fmt: skip
    peaks = [row["fixed_face_peak_MPa"] for row in fixed["table"]]
    assert peaks[0] < peaks[1] < peaks[2] and fixed["singular_corner"]
    assert not fixed["peak_converges"] and fixed["peak_last_change_pct"] > 10.0
    assert all(row["where"].startswith("built-in end") for row in fixed["table"])
    assert fixed["deflection_last_change_pct"] < 0.1


def test_the_section_search_finds_a_link_with_the_studys_deflection_and_compression_peak():
    """Screened by closed forms, confirmed by finite elements, the study's steel first: its best
    candidate's deflection and compression peak lie within 10 % of the midpoints of the study's
    ranges; its deflection agrees with a cantilever typed out here, F a³/(3EI) + F a²(l − a)/(2EI),
    within the holes' few per cent."""
    link = fea.link_from_config(CONFIG["thigh_link"], CONFIG["links_mm"]["l_BC"],
                                CONFIG["design_load_N"])  # fmt: skip
    reported = {"tip_deflection_mm": [0.30, 0.32], "compression_peak_MPa": [26.0, 27.0],
                "bending_peak_MPa": 154.0}  # fmt: skip
    coarse = {"finest": fea.level_results(link, fea.solve_level(link, 16.0, 4.0))}
    factor = sections.bearing_factor(link, coarse)
    assert factor == pytest.approx(coarse["finest"]["compression"]["peak"]["MPa"] / (1500 / 192))
    steel = "steel St. 3"  # the study's material alone: one candidate to confirm
    only = {steel: {**CONFIG["sections"]["materials"][steel], "confirm": 1}}
    cfg = {**CONFIG["sections"], "study_material": steel, "materials": only}
    rows, screened = sections.search(cfg, link, factor, reported, (8.0, 2.0))
    assert [r["material"] for r in rows] == [steel]
    best = rows[0]
    assert screened > 50 and best["confirmed"] and best["study_material"]
    assert abs(best["fe_deflection_mm"] / 0.31 - 1) <= 0.10
    assert abs(best["fe_compression_peak_MPa"] / 26.5 - 1) <= 0.10
    a, free = 520.0, 540.0
    inertia = best["thickness_mm"] * best["depth_mm"] ** 3 / 12
    bending = 1500 * a**2 * (a / 3 + (free - a) / 2) / (best["E_MPa"] * inertia)
    assert best["fe_deflection_mm"] == pytest.approx(bending, rel=0.08)
    implied = sections.implied(reported, 500.0, 206000.0, 60.0)
    depth = implied["depth_if_peak_were_clamp_stress_mm"]
    # a cantilever that deep: deflection over clamp stress is the study's ratio
    assert 500.0**2 / (3 * 206000.0 * depth / 2) == pytest.approx(0.31 / 154.0)
