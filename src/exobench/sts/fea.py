"""The thigh link by finite elements: the study's load cases on the configured link, mesh
convergence, the load-introduction hypotheses and the beam formulas against the field.

The link is the configured bar (depth H, thickness t, holes on its centreline) from ``e`` behind
the knee pin to ``e`` beyond the hip pin (the end margin), built in at the knee end
(:func:`exobench.sts.elastic.built_in_end`) and loaded through the hip pin by the design load F:
- bending (the seated, horizontal thigh): the pin presses F across the link, a cosine bearing
  pressure on the half of the hole it pushes (:func:`exobench.sts.elastic.bearing`);
- compression (the upright link): the pin pushes F along the link towards the knee, the same way;
- the same two loads as a concentrated force on the hole's node where the pin presses (the
  load-introduction hypothesis: its stress grows without bound as the mesh refines).
The loaded end is the link within one section depth H of the hip pin (St-Venant's distance).
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass

import numpy as np

from exobench.errors import InputError
from exobench.sts import beam, elastic, strength
from exobench.sts.beam import Section
from exobench.sts.mesh import Bar, Hole, bar_mesh

# load cases: the force the pin applies to the link, its direction and how it is introduced
CASES = {
    "bending": {"angle_rad": -np.pi / 2, "introduction": "bearing"},
    "compression": {"angle_rad": np.pi, "introduction": "bearing"},
    "bending_concentrated": {"angle_rad": -np.pi / 2, "introduction": "concentrated"},
    "compression_concentrated": {"angle_rad": np.pi, "introduction": "concentrated"},
}
HOLE_BAND_MM = 0.5  # a peak this close to a hole's edge (or nearer) is the hole's
POWER_LAW_LEVELS = 3  # refinements the concentrated loads' power law is fitted through


@dataclass(frozen=True)
class Link:
    """The configured thigh link as a plane-stress bar: geometry, plate, load and its pin."""

    bar: Bar
    plate: elastic.Plate
    section: Section
    load_N: float
    length_mm: float
    margin_mm: float

    @property
    def pin(self) -> Hole:
        """The loaded (hip) pin: the hole at the link's length from the knee."""
        return min(self.bar.holes, key=lambda h: abs(h.x_mm - self.length_mm))

    @property
    def loaded_end_mm(self) -> float:
        """Where the loaded end starts: one section depth before the hip pin."""
        return self.length_mm - self.section.depth_mm


def link_from_config(cfg: Mapping, length_mm: float, load_N: float) -> Link:
    """The ``sts.thigh_link`` block as a bar from −e to L + e (e: ``end_margin_mm``)."""
    section, material, holes = strength.link_from_config(cfg)
    margin = float(cfg["end_margin_mm"])
    for hole in holes:
        radius = hole["diameter_mm"] / 2.0
        inside = -margin < hole["position_mm"] - radius and (
            hole["position_mm"] + radius < length_mm + margin
        )
        if not (inside and hole["diameter_mm"] < section.depth_mm):
            raise InputError(
                "config",
                "sts.thigh_link.holes",
                f"holes inside the bar from −{margin:g} to {length_mm + margin:g} mm "
                f"(sts.thigh_link.end_margin_mm) and narrower than its depth",
                f"hole '{hole['name']}' at {hole['position_mm']:g} mm, {hole['diameter_mm']:g} mm",
            )
    bar = Bar(
        -margin,
        length_mm + margin,
        section.depth_mm,
        tuple(Hole(h["name"], h["position_mm"], 0.0, h["diameter_mm"]) for h in holes),
    )
    plate = elastic.Plate(material.E_MPa, material.poisson, section.thickness_mm)
    return Link(bar, plate, section, float(load_N), float(length_mm), margin)


def load_vectors(link: Link, basis) -> tuple[np.ndarray, np.ndarray]:
    """The constrained dofs and one load column per case (:data:`CASES`) with its reaction."""
    t = link.plate.thickness_mm
    fixed, reaction = elastic.built_in_end(basis, link.bar.x0_mm, link.bar.depth_mm, link.load_N, t)
    pin = link.pin
    columns = []
    for case in CASES.values():
        angle = case["angle_rad"]
        direction = np.array([np.cos(angle), np.sin(angle)])
        if case["introduction"] == "bearing":
            load = elastic.bearing(basis, pin, link.load_N, angle, t)
        else:
            contact = (pin.x_mm + pin.radius_mm * direction[0], pin.radius_mm * direction[1])
            load = elastic.point_force(basis, contact, link.load_N * direction)
        # the built-in end carries the transverse load as shear, the axial one by u_x = 0
        columns.append(load + abs(direction[1]) * reaction)
    return fixed, np.column_stack(columns)


def where(link: Link, x: float, y: float) -> str:
    """A stress point in words: a hole's edge, the built-in end, an outer fibre, or inside."""
    for hole in link.bar.holes:
        if np.hypot(x - hole.x_mm, y - hole.y_mm) <= hole.radius_mm + HOLE_BAND_MM:
            return f"edge of the {hole.name} hole"
    if np.isclose(x, link.bar.x0_mm):
        return "built-in end, outer fibre" if np.isclose(abs(y), link.bar.depth_mm / 2) else (
            "built-in end")  # fmt: skip
    if np.isclose(abs(y), link.bar.depth_mm / 2):
        return f"outer fibre at {x:.0f} mm from the knee pin"
    return f"inside the link at ({x:.0f}, {y:.0f}) mm"


def peak(link: Link, stress: elastic.NodalStress, mask=None) -> dict:
    """Largest von Mises stress (over ``mask`` of the element nodes), where it is."""
    values = stress.von_mises if mask is None else np.where(mask, stress.von_mises, -np.inf)
    index = np.unravel_index(int(np.argmax(values)), values.shape)
    x, y = float(stress.x_mm[index]), float(stress.y_mm[index])
    return {"MPa": float(values[index]), "x_mm": x, "y_mm": y, "where": where(link, x, y)}


def solve_level(link: Link, size_mm: float, hole_size_mm: float) -> dict:
    """Every case on one mesh: the mesh, basis, displacements and element-node stresses."""
    mesh = bar_mesh(link.bar, size_mm, hole_size_mm)
    basis = elastic.vector_basis(mesh)
    fixed, loads = load_vectors(link, basis)
    u = elastic.solve(elastic.stiffness(basis, link.plate), loads, fixed)
    stresses = dict(zip(CASES, elastic.nodal_stresses(basis, u, link.plate), strict=True))
    return {"mesh": mesh, "basis": basis, "u": u, "stress": stresses}


def level_results(link: Link, level: Mapping) -> dict:
    """Peaks (overall and at the loaded end) and the largest displacement of every case."""
    out = {"dofs": int(level["basis"].N)}
    for k, (name, stress) in enumerate(level["stress"].items()):
        displacement = elastic.vertex_displacements(level["basis"], level["u"][:, k])
        out[name] = {
            "peak": peak(link, stress),
            "loaded_end_peak": peak(link, stress, stress.x_mm >= link.loaded_end_mm),
            "max_displacement_mm": float(np.hypot(*displacement).max()),
        }
    return out


def change_pct(values: Sequence[float]) -> float:
    """Change between the last two refinements, % of the last: 100·|v_n − v_(n−1)|/|v_n|."""
    return float(100.0 * abs(values[-1] - values[-2]) / abs(values[-1]))


CONVERGED = {  # quantity -> (case, path in the case's results)
    "bending peak (MPa)": ("bending", ("peak", "MPa")),
    "bending peak at the loaded end (MPa)": ("bending", ("loaded_end_peak", "MPa")),
    "tip deflection (mm)": ("bending", ("max_displacement_mm",)),
    "compression peak (MPa)": ("compression", ("peak", "MPa")),
    "concentrated bending load's peak at the loaded end (MPa)": (
        "bending_concentrated", ("loaded_end_peak", "MPa")),
    "concentrated compression load's peak at the loaded end (MPa)": (
        "compression_concentrated", ("loaded_end_peak", "MPa")),
}  # fmt: skip
CONCENTRATED = ("concentrated bending load's peak at the loaded end (MPa)",
                "concentrated compression load's peak at the loaded end (MPa)")  # fmt: skip


def _value(results: Mapping, case: str, path: Sequence[str]) -> float:
    """One number of a level's results."""
    value = results[case]
    for key in path:
        value = value[key]
    return float(value)


def convergence(levels: Sequence[Mapping], sizes: Sequence[tuple[float, float]],
                tolerance_pct: float) -> dict:  # fmt: skip
    """Each quantity per refinement, its last change (%) and whether within the tolerance."""
    rows = [{"element_mm": s, "hole_element_mm": h, "dofs": r["dofs"],
             **{q: _value(r, c, p) for q, (c, p) in CONVERGED.items()}}
            for (s, h), r in zip(sizes, levels, strict=True)]  # fmt: skip
    change = {q: change_pct([row[q] for row in rows]) for q in CONVERGED}
    return {
        "tolerance_pct": tolerance_pct,
        "table": rows,
        "last_change_pct": change,
        "converged": {q: change[q] <= tolerance_pct for q in CONVERGED},
    }


def power_law(sizes: Sequence[float], peaks: Sequence[float]) -> tuple[float, float]:
    """Exponent p and factor a of σ = a·h^(−p) through the refinements (log–log least squares)."""
    slope, intercept = np.polyfit(np.log(sizes), np.log(peaks), 1)
    return float(-slope), float(np.exp(intercept))


def hypotheses(link: Link, finest: Mapping, table: Sequence[Mapping], reported: Mapping) -> dict:
    """Study numbers against bearing (K_b = σ/(F/(d t))) and concentrated (h = (a/σ)^(1/p))."""
    pin, t, force = link.pin, link.plate.thickness_mm, link.load_N
    target = float(reported["bending_peak_MPa"])
    low_d, high_d = reported["tip_deflection_mm"]
    low_c, high_c = reported["compression_peak_MPa"]
    end = finest["bending"]["loaded_end_peak"]["MPa"]
    deflection = finest["bending"]["max_displacement_mm"]
    compression = finest["compression"]["peak"]["MPa"]
    factor = end / (force / (pin.diameter_mm * t))
    bearing = {
        "loaded_end_peak_MPa": end,
        "loaded_end_peak_where": finest["bending"]["loaded_end_peak"]["where"],
        "tip_deflection_mm": deflection,
        "compression_peak_MPa": compression,
        "compression_peak_where": finest["compression"]["peak"]["where"],
        "nominal_bearing_stress_MPa": force / (pin.diameter_mm * t),
        "bearing_factor": factor,
        "pin_diameter_for_reported_peak_mm": factor * force / (target * t),
        "load_for_reported_peak_N": force * target / end,
        "load_for_reported_deflection_N": force * float(np.mean([low_d, high_d])) / deflection,
        "load_for_reported_compression_N": force * float(np.mean([low_c, high_c])) / compression,
        "reproduces": {
            "bending_peak_at_loaded_end": bool(abs(end - target) <= 0.05 * target),
            "tip_deflection": bool(low_d <= deflection <= high_d),
            "compression_peak": bool(low_c <= compression <= high_c),
        },
    }
    finer = table[-POWER_LAW_LEVELS:]  # the coarsest meshes do not resolve the singularity yet
    sizes = [row["hole_element_mm"] for row in finer]
    bend_p, bend_a = power_law(sizes, [row[CONCENTRATED[0]] for row in finer])
    comp_p, comp_a = power_law(sizes, [row[CONCENTRATED[1]] for row in finer])
    size = (bend_a / target) ** (1.0 / bend_p)
    at_size = comp_a * size ** (-comp_p)
    concentrated = {
        "exponent": bend_p,
        "element_mm_for_reported_peak": size,
        "within_the_meshes": bool(min(sizes) <= size <= max(sizes)),
        "compression_peak_at_that_size_MPa": at_size,
        "tip_deflection_mm": deflection,
        "reproduces": {
            "bending_peak_at_loaded_end": bool(bend_p > 0.1),
            "tip_deflection": bool(low_d <= deflection <= high_d),
            "compression_peak": bool(low_c <= at_size <= high_c),
        },
    }
    return {"bearing": bearing, "concentrated": concentrated}


def beam_against_fe(link: Link, level: Mapping, finest: Mapping) -> list[dict]:
    """The closed forms for the same bar, clamp and load against the converged field."""
    holes = [{"name": h.name, "position_mm": h.x_mm + link.margin_mm, "diameter_mm": h.diameter_mm,
              "pin": h is link.pin} for h in link.bar.holes]  # fmt: skip
    lever = link.length_mm + link.margin_mm
    sitting = strength.sitting_case(link.load_N, lever, link.section, holes)
    standing = strength.standing_case(link.load_N, link.section, holes)
    bend, comp = level["stress"]["bending"], level["stress"]["compression"]
    rows = [_row("bending stress at the built-in end (outer fibre)",
                 sitting["nominal_stress_MPa"],
                 peak(link, bend, np.isclose(bend.x_mm, link.bar.x0_mm))["MPa"], "MPa",
                 "the built-in end holds the section plane against its shear warping, which "
                 "raises the outer fibre's stress near it")]  # fmt: skip
    for hole in link.bar.holes:
        if hole is link.pin:
            continue
        band = np.abs(bend.x_mm - hole.x_mm) <= hole.radius_mm
        rows.append(_row(f"bending peak across the {hole.name} hole (Roark Table 17.1, case 1c)",
                         sitting["holes"][hole.name]["bending_peak_MPa"],
                         peak(link, bend, band)["MPa"], "MPa",
                         "the hole's interaction with the free edges and the shear"))  # fmt: skip
        comp_band = np.abs(comp.x_mm - hole.x_mm) <= hole.radius_mm
        axial = beam.hole_stresses(0.0, link.load_N, hole.diameter_mm, link.section)
        rows.append(_row(f"compression peak at the {hole.name} hole (Roark Table 17.1, case 1a)",
                         axial["axial_peak_MPa"], peak(link, comp, comp_band)["MPa"], "MPa",
                         "the factor is for a long plate far from loads and ends"))  # fmt: skip
    rows.append(_row("peak at the loaded pin, bending (bearing F/(d·t))",
                     standing["pin_bearing_stress_MPa"],
                     finest["bending"]["loaded_end_peak"]["MPa"], "MPa",
                     "the concentration of the pin's pressure at the hole"))  # fmt: skip
    rows.append(_row("compression peak (largest of bearing F/(d·t) and the holes' Roark peaks)",
                     max(standing["peak_stress_MPa"], standing["pin_bearing_stress_MPa"]),
                     finest["compression"]["peak"]["MPa"], "MPa",
                     "the concentration of the pin's pressure at the hole"))  # fmt: skip
    beam_tip = tip_deflection_beam(link)
    rows.append(_row("largest deflection (Euler–Bernoulli + shear, free end)", beam_tip,
                     finest["bending"]["max_displacement_mm"], "mm",
                     "the holes' compliance and the pin's bearing deformation"))  # fmt: skip
    return rows


def tip_deflection_beam(link: Link) -> float:
    """δ = F a³/(3EI) + F a²(l − a)/(2EI) + F a/(κGA), κ = 5/6."""
    a = link.length_mm + link.margin_mm
    free = link.bar.x1_mm - link.bar.x0_mm
    E, inertia = link.plate.E_MPa, link.section.inertia_mm4
    shear = (
        link.load_N
        * a
        / (beam.SHEAR_COEFFICIENT * E / (2 * (1 + link.plate.poisson)) * link.section.area_mm2)
    )
    return link.load_N * a**2 * (a / 3 + (free - a) / 2) / (E * inertia) + shear


def _row(quantity: str, formula: float, fe: float, unit: str, missed: str) -> dict:
    """One comparison row: the formula, the field, their difference (% of the field)."""
    return {"quantity": quantity, "formula": float(formula), "fe": float(fe), "unit": unit,
            "difference_pct": float(100.0 * (formula - fe) / fe), "missed": missed}  # fmt: skip


def field_tables(level: Mapping) -> tuple[dict, dict]:
    """The finest mesh's vertex stresses and bending displacement, and its triangles."""
    mesh, basis, u = level["mesh"], level["basis"], level["u"]
    bending = list(CASES).index("bending")
    displacement = elastic.vertex_displacements(basis, u[:, bending])
    vertices = mesh.doflocs[:, : mesh.t.max() + 1]
    nodes = {
        "x_mm": vertices[0],
        "y_mm": vertices[1],
        "bending_von_mises_MPa": elastic.vertex_values(mesh, level["stress"]["bending"].von_mises),
        "compression_von_mises_MPa": elastic.vertex_values(
            mesh, level["stress"]["compression"].von_mises
        ),
        "bending_displacement_mm": np.hypot(*displacement),
    }
    return nodes, {f"vertex_{k}": mesh.t[k] for k in range(3)}


def analyse(link: Link, fe: Mapping, reported: Mapping) -> tuple[dict, tuple[dict, dict]]:
    """Every refinement, its convergence, the hypotheses and the beam check; the finest field."""
    sizes = [(float(s), float(s) / fe["hole_refinement"]) for s in fe["element_mm"]]
    results = []
    for size, hole_size in sizes:
        level = solve_level(link, size, hole_size)
        results.append(level_results(link, level))
    finest = results[-1]
    table = convergence(results, sizes, float(fe["convergence_tolerance_pct"]))
    report = {
        "model": {
            "elements": "quadratic (six-node) triangles, curved on the holes (gmsh, scikit-fem)",
            "state": "linear elastic, plane stress",
            "support": "built in at the knee end: section held plane, shear reaction parabolic",
            "cases": {name: case["introduction"] for name, case in CASES.items()},
            "load_N": link.load_N,
            "end_margin_mm": link.margin_mm,
            "lever_mm": link.length_mm + link.margin_mm,
        },
        "finest": finest,
        "convergence": table,
        "hypotheses": hypotheses(link, finest, table["table"], reported),
        "beam_against_fe": beam_against_fe(link, level, finest),
        "loaded_end_from_mm": link.loaded_end_mm,
    }
    return report, field_tables(level)


def fixed_support(link: Link, fe: Mapping) -> dict:
    """End face fixed (u = 0), corners refined: peak per level, its power law σ = a·h^(−p)."""
    size = float(fe["fixed_face"]["element_mm"])
    hole = size / float(fe["hole_refinement"])
    t, rows = link.plate.thickness_mm, []
    for corner in fe["fixed_face"]["corner_element_mm"]:
        basis = elastic.vector_basis(bar_mesh(link.bar, size, hole, float(corner)))
        load = elastic.bearing(basis, link.pin, link.load_N, CASES["bending"]["angle_rad"], t)
        fixed = elastic.fixed_face(basis, link.bar.x0_mm)
        u = elastic.solve(elastic.stiffness(basis, link.plate), load, fixed)[:, 0]
        stress = elastic.nodal_stresses(basis, u, link.plate)[0]
        face = peak(link, stress, stress.x_mm <= link.bar.x0_mm + link.section.depth_mm / 4)
        rows.append({"corner_element_mm": float(corner), "dofs": int(basis.N),
                     "fixed_face_peak_MPa": face["MPa"], "where": face["where"],
                     "largest_displacement_mm": float(np.hypot(*elastic.vertex_displacements(
                         basis, u)).max())})  # fmt: skip
    tolerance = float(fe["convergence_tolerance_pct"])
    peaks = [r["fixed_face_peak_MPa"] for r in rows]
    change = change_pct(peaks)
    exponent, _ = power_law([r["corner_element_mm"] for r in rows[1:]], peaks[1:])
    return {
        "support": "end face fully fixed (u = 0 on it), as the study's 'rigidly constrained' end",
        "table": rows,
        "peak_last_change_pct": change,
        "peak_exponent": exponent,
        "peak_converges": bool(change <= tolerance),
        "singular_corner": bool(change > tolerance and peaks[-1] > peaks[-2] > peaks[-3]),
        "deflection_last_change_pct": change_pct([r["largest_displacement_mm"] for r in rows]),
        "element_mm": size,
        "tolerance_pct": tolerance,
    }


def levers(link: Link) -> dict:
    """Eq. (5)'s lever l_BC and the configured one l_BC + e, each with its moment F·lever."""
    return {
        "eq5_lever_mm": link.length_mm,
        "eq5_moment_Nm": link.load_N * link.length_mm / 1000.0,
        "configured_lever_mm": link.length_mm + link.margin_mm,
        "configured_moment_Nm": link.load_N * (link.length_mm + link.margin_mm) / 1000.0,
    }
