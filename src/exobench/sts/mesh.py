"""Quadratic triangle meshes of a flat bar with circular holes (gmsh), for the plane-stress link.

The bar spans x0 ≤ x ≤ x1 and −H/2 ≤ y ≤ H/2 (mm). gmsh meshes it with 6-node triangles whose
mid-side nodes lie on the holes' circles (curved, isoparametric edges, as the study's
second-order tetrahedra are), the element size falling from ``size`` to ``hole_size`` at the
holes. The result is a scikit-fem ``MeshTri2``: corner nodes first, then one mid-side node per
edge in scikit-fem's edge order.
"""

from __future__ import annotations

from dataclasses import dataclass

import gmsh
import numpy as np
from skfem import MeshTri, MeshTri2

SIX_NODE_TRIANGLE = 9  # gmsh element type
# corner pairs of a gmsh 6-node triangle's edges and the mid-side node of each
EDGES = ((0, 1, 3), (1, 2, 4), (2, 0, 5))


@dataclass(frozen=True)
class Hole:
    """A circular hole: centre (mm) and diameter (mm)."""

    name: str
    x_mm: float
    y_mm: float
    diameter_mm: float

    @property
    def radius_mm(self) -> float:
        """Half the diameter."""
        return self.diameter_mm / 2.0


@dataclass(frozen=True)
class Bar:
    """A flat bar x0..x1 (mm), depth H (mm, centred on y = 0), with holes."""

    x0_mm: float
    x1_mm: float
    depth_mm: float
    holes: tuple[Hole, ...] = ()


def _gmsh_triangles(bar: Bar, size: float, hole_size: float,
                    corner_size: float | None) -> tuple[np.ndarray, np.ndarray]:  # fmt: skip
    """Node coordinates (n, 2) and 6-node connectivity (elements, 6) from gmsh, one thread."""
    gmsh.initialize(readConfigFiles=False, interruptible=False)
    try:
        for option, value in (("General.Terminal", 0), ("General.NumThreads", 1),
                              ("Mesh.ElementOrder", 2), ("Mesh.MeshSizeFromPoints", 0),
                              ("Mesh.MeshSizeFromCurvature", 0),
                              ("Mesh.MeshSizeExtendFromBoundary", 0)):  # fmt: skip
            gmsh.option.setNumber(option, value)
        occ = gmsh.model.occ
        plate = occ.addRectangle(
            bar.x0_mm, -bar.depth_mm / 2, 0, bar.x1_mm - bar.x0_mm, bar.depth_mm
        )
        disks = [occ.addDisk(h.x_mm, h.y_mm, 0, h.radius_mm, h.radius_mm) for h in bar.holes]
        if disks:
            occ.cut([(2, plate)], [(2, d) for d in disks])
        occ.synchronize()
        field = gmsh.model.mesh.field
        circles = [c for _, c in gmsh.model.getEntities(1) if gmsh.model.getType(1, c) != "Line"]
        size_field = field.add("MathEval")
        field.setString(size_field, "F", f"{size}")
        if circles:
            distance = field.add("Distance")
            field.setNumbers(distance, "CurvesList", circles)
            field.setNumber(distance, "Sampling", 400)
            size_field = field.add("Threshold")
            field.setNumber(size_field, "InField", distance)
            field.setNumber(size_field, "SizeMin", hole_size)
            field.setNumber(size_field, "SizeMax", size)
            field.setNumber(size_field, "DistMin", 0.0)
            field.setNumber(size_field, "DistMax", 4.0 * size)
        if corner_size is not None:  # the two corners of the end x = x0, refined
            corners = [p for _, p in gmsh.model.getEntities(0)
                       if np.isclose(gmsh.model.getValue(0, p, [])[0], bar.x0_mm)]  # fmt: skip
            near = field.add("Distance")
            field.setNumbers(near, "PointsList", corners)
            corner_field = field.add("Threshold")
            field.setNumber(corner_field, "InField", near)
            field.setNumber(corner_field, "SizeMin", corner_size)
            field.setNumber(corner_field, "SizeMax", size)
            field.setNumber(corner_field, "DistMin", 0.0)
            field.setNumber(corner_field, "DistMax", 4.0 * size)
            smallest = field.add("Min")
            field.setNumbers(smallest, "FieldsList", [size_field, corner_field])
            size_field = smallest
        field.setAsBackgroundMesh(size_field)
        gmsh.model.mesh.generate(2)
        tags, coordinates, _ = gmsh.model.mesh.getNodes()
        types, _, nodes = gmsh.model.mesh.getElements(2)
    finally:
        gmsh.finalize()
    if list(types) != [SIX_NODE_TRIANGLE]:
        raise RuntimeError(f"gmsh returned element types {list(types)}, not 6-node triangles")
    index = np.zeros(int(tags.max()) + 1, dtype=np.int64)
    index[tags.astype(np.int64)] = np.arange(len(tags))
    return coordinates.reshape(-1, 3)[:, :2], index[nodes[0].astype(np.int64)].reshape(-1, 6)


def bar_mesh(bar: Bar, size: float, hole_size: float, corner_size: float | None = None) -> MeshTri2:
    """The bar as a quadratic mesh: ``size`` away, ``hole_size`` at holes, ``corner_size`` at x0."""
    xy, six = _gmsh_triangles(bar, size, hole_size, corner_size)
    corners = np.unique(six[:, :3])
    renumber = -np.ones(len(xy), dtype=np.int64)
    renumber[corners] = np.arange(len(corners))
    # C-ordered arrays, as scikit-fem keeps them (it copies and warns otherwise)
    linear = MeshTri(
        np.ascontiguousarray(xy[corners].T), np.ascontiguousarray(renumber[six[:, :3]].T)
    )
    n = len(corners)
    # the mid-side node of each gmsh edge, found by its corner pair among scikit-fem's edges
    keys, middles = [], []
    for a, b, m in EDGES:
        i, j = renumber[six[:, a]], renumber[six[:, b]]
        keys.append(np.minimum(i, j) * n + np.maximum(i, j))
        middles.append(xy[six[:, m]])
    keys, middles = np.concatenate(keys), np.concatenate(middles)
    order = np.argsort(keys, kind="stable")
    facets = linear.facets.astype(np.int64)
    edges = facets.min(axis=0) * n + facets.max(axis=0)
    middle = middles[order][np.searchsorted(keys[order], edges)]
    return MeshTri2(np.ascontiguousarray(np.hstack([linear.p, middle.T])), linear.t)


def hole_facets(mesh: MeshTri2, hole: Hole, tolerance_mm: float = 1e-6) -> np.ndarray:
    """Boundary facets of ``mesh`` whose two corners lie on ``hole``'s circle."""
    boundary = mesh.boundary_facets()
    ends = mesh.p[:, mesh.facets[:, boundary]]  # (xy, 2 ends, facets)
    radius = np.hypot(ends[0] - hole.x_mm, ends[1] - hole.y_mm)
    return boundary[np.all(np.abs(radius - hole.radius_mm) < tolerance_mm, axis=0)]
