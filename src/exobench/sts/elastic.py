"""Linear plane-stress elasticity of a bar with quadratic triangles (scikit-fem, ElementTriP2).

Displacements u (mm) under loads in N on a plate of thickness t (mm), stresses in MPa:
K = t ∫ ε(v) : C ε(u) dA with the plane-stress C (λ* = 2λμ/(λ + 2μ)); tractions enter as
t ∫ T·v ds. Stresses are evaluated at the six nodes of every element (not averaged), so a peak
is the largest of them; von Mises σ_v = √(σxx² − σxx σyy + σyy² + 3τxy²).
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass

import numpy as np
from scipy.sparse.linalg import splu
from skfem import Basis, ElementTriP2, ElementVector, FacetBasis, LinearForm, asm, condense
from skfem.helpers import dot, sym_grad
from skfem.models.elasticity import lame_parameters, linear_elasticity, linear_stress

from exobench.sts.mesh import Hole, hole_facets

# scikit-fem's reference nodes of the quadratic triangle: corners, then mid-sides
REFERENCE_NODES = np.ascontiguousarray(ElementTriP2.doflocs.T)


@dataclass(frozen=True)
class Plate:
    """Young's modulus (MPa), Poisson's ratio and thickness (mm) of a plane-stress plate."""

    E_MPa: float
    poisson: float
    thickness_mm: float

    @property
    def lame(self) -> tuple[float, float]:
        """Plane-stress Lamé parameters λ* = 2λμ/(λ + 2μ) and μ (MPa)."""
        lam, mu = lame_parameters(self.E_MPa, self.poisson)
        return 2.0 * lam * mu / (lam + 2.0 * mu), mu


def vector_basis(mesh) -> Basis:
    """Quadratic vector basis on a (quadratic) triangle mesh."""
    return Basis(mesh, ElementVector(ElementTriP2()), intorder=4)


def stiffness(basis: Basis, plate: Plate):
    """Plane-stress stiffness matrix t ∫ ε(v) : C ε(u) dA (N/mm)."""
    return plate.thickness_mm * asm(linear_elasticity(*plate.lame), basis)


def traction(basis: Basis, facets: np.ndarray, field: Callable, thickness_mm: float):
    """Load vector t ∫ T(x)·v ds of a traction T(x, y) -> (2, ...) MPa on boundary facets."""
    facet_basis = FacetBasis(basis.mesh, basis.elem, facets=facets, intorder=8)

    @LinearForm
    def form(v, w):
        """The traction's virtual work density T · v."""
        return dot(field(w.x[0], w.x[1]), v)

    return thickness_mm * asm(form, facet_basis)


def bearing(basis: Basis, hole: Hole, force_N: float, angle_rad: float, thickness_mm: float):
    """Pin bearing p = p₀ cos(θ − angle) on the pressed half, p₀ = 2F/(π r t)."""
    p0 = 2.0 * force_N / (np.pi * hole.radius_mm * thickness_mm)

    def pressure(x, y):
        """Bearing traction p₀ max(cos(θ − angle), 0) along the radius from the hole's centre."""
        theta = np.arctan2(y - hole.y_mm, x - hole.x_mm)
        p = p0 * np.maximum(np.cos(theta - angle_rad), 0.0)
        return np.array([p * np.cos(theta), p * np.sin(theta)])

    return traction(basis, hole_facets(basis.mesh, hole), pressure, thickness_mm)


def point_force(basis: Basis, xy: Sequence[float], force_N: Sequence[float]) -> np.ndarray:
    """A concentrated force (N) on the mesh node nearest to ``xy`` (mm)."""
    nodal = basis.nodal_dofs
    locations = basis.doflocs[:, nodal[0]]
    node = int(np.argmin(np.hypot(locations[0] - xy[0], locations[1] - xy[1])))
    out = np.zeros(basis.N)
    out[nodal[:, node]] = force_N
    return out


def built_in_end(basis: Basis, x_mm: float, depth_mm: float, shear_N: float, thickness_mm: float):
    """Section held plane, parabolic shear τ = 1.5V/(tH)(1 − (2y/H)²), u_y = 0 mid-depth."""
    mesh = basis.mesh
    face = mesh.facets_satisfying(lambda x: np.isclose(x[0], x_mm), boundaries_only=True)
    axial = basis.get_dofs(face).all("u^1")
    mid = basis.doflocs
    candidates = basis.nodal_dofs[1]
    distance = np.hypot(mid[0, candidates] - x_mm, mid[1, candidates])
    fixed = np.union1d(axial, [candidates[int(np.argmin(distance))]])
    peak = 1.5 * shear_N / (thickness_mm * depth_mm)

    def shear(x, y):
        """Parabolic shear traction τ = τ_max (1 − (2y/H)²) at (x, y)."""
        tau = peak * (1.0 - (2.0 * y / depth_mm) ** 2)
        return np.array([np.zeros_like(tau), tau])

    return fixed, traction(basis, face, shear, thickness_mm)


def fixed_face(basis: Basis, x_mm: float) -> np.ndarray:
    """Every degree of freedom on the face x = ``x_mm`` (u = 0; its corners singular)."""
    face = basis.mesh.facets_satisfying(lambda x: np.isclose(x[0], x_mm), boundaries_only=True)
    return basis.get_dofs(face).all()


def solve(stiffness_matrix, loads: np.ndarray, fixed: np.ndarray) -> np.ndarray:
    """Displacements K u = f per load column, zero at ``fixed`` (one sparse LU)."""
    loads = np.atleast_2d(loads.T).T
    reduced, _, _, free = condense(stiffness_matrix, loads[:, 0], D=fixed)
    factor = splu(reduced.tocsc(), permc_spec="COLAMD")
    out = np.zeros_like(loads)
    out[free] = factor.solve(np.ascontiguousarray(loads[free]))
    return out


@dataclass(frozen=True)
class NodalStress:
    """Stresses (MPa) at the six nodes of every element: arrays (elements, 6); node positions."""

    x_mm: np.ndarray
    y_mm: np.ndarray
    sxx: np.ndarray
    syy: np.ndarray
    sxy: np.ndarray

    @property
    def von_mises(self) -> np.ndarray:
        """σ_vm = √(σxx² − σxx σyy + σyy² + 3τxy²) (plane stress)."""
        return np.sqrt(self.sxx**2 - self.sxx * self.syy + self.syy**2 + 3.0 * self.sxy**2)


def nodal_stresses(basis: Basis, u: np.ndarray, plate: Plate) -> list[NodalStress]:
    """Plane stresses C ε(u) at each element's six nodes (unaveraged), one per column of u."""
    at_nodes = Basis(basis.mesh, basis.elem, quadrature=(REFERENCE_NODES, np.full(6, 1 / 12)))
    x, y = at_nodes.mapping.F(REFERENCE_NODES)
    stress = linear_stress(*plate.lame)
    out = []
    for column in np.atleast_2d(u.T):
        s = stress(sym_grad(at_nodes.interpolate(column)))
        out.append(NodalStress(x, y, s[0, 0], s[1, 1], s[0, 1]))
    return out


def vertex_values(mesh, element_node_values: np.ndarray) -> np.ndarray:
    """Element-corner values averaged at each mesh vertex (for contour plots)."""
    corners = element_node_values[:, :3]
    total = np.bincount(mesh.t.T.ravel(), weights=corners.ravel())
    return total / np.bincount(mesh.t.T.ravel())


def vertex_displacements(basis: Basis, u: np.ndarray) -> np.ndarray:
    """Displacements (2, vertices) of the mesh's corner nodes (mm)."""
    return u[basis.nodal_dofs][:, : basis.mesh.t.max() + 1]
