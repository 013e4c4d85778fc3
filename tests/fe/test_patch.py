"""Patch tests: linear displacement fields and rigid motions on irregular meshes.

The classic displacement patch test: prescribe ``u = a + B x`` on the boundary nodes of
an irregular patch, solve ``K u = 0`` for the interior nodes, and require the interior
displacements to reproduce the linear field; independently, the strain evaluated from
the element gradients must be the constant ``sym(B)`` everywhere.
"""

from __future__ import annotations

import numpy as np
import pytest

from flexarm.fe import (
    Tet4,
    Tet10,
    dof_split,
    is_affine,
    node_dofs,
    static_solve,
    stiffness_matrix,
    tet_quadrature,
)

A = np.array([1.0e-3, -2.0e-3, 0.5e-3])  # [m]
B = np.array([[1.0e-3, 2.0e-4, -3.0e-4], [5.0e-4, -2.0e-3, 1.0e-4], [-1.0e-4, 3.0e-4, 1.5e-3]])
TOL = 1e-10

MESHES = ["irregular_tet4", "irregular_tet10", "curved_tet10"]


def linear_field(points: np.ndarray) -> np.ndarray:
    """(3n,) u = a + B x at the nodes."""
    return (A + points @ B.T).ravel()


def strains_at_quadrature_points(mesh, u: np.ndarray) -> np.ndarray:
    """(e, q, 3, 3) small strain from the isoparametric element gradients (independent of fe)."""
    el = Tet4 if mesh.order == 1 else Tet10
    pts, _ = tet_quadrature(3)
    dN = el.shape_grad(pts)  # (q, nn, 3)
    X = mesh.points[mesh.tets]  # (e, nn, 3)
    J = np.einsum("eai,qaj->eqij", X, dN)
    assert np.linalg.det(J).min() > 0, "patch mesh has an inverted element"
    G = np.einsum("qaj,eqji->eqai", dN, np.linalg.inv(J))  # dN_a/dx_i
    ue = u.reshape(-1, 3)[mesh.tets]  # (e, nn, 3)
    grad = np.einsum("eai,eqaj->eqij", ue, G)  # du_i/dx_j
    return 0.5 * (grad + grad.transpose(0, 1, 3, 2))


@pytest.mark.parametrize("name", MESHES)
def test_patch_meshes_are_irregular(name, request):
    """The fixtures really are what the patch tests claim (not a regular grid)."""
    mesh = request.getfixturevalue(name)
    vol = mesh.volumes()
    assert vol.min() > 0
    assert vol.std() / vol.mean() > 0.1
    assert is_affine(mesh) == (name != "curved_tet10")


@pytest.mark.parametrize("name", MESHES)
def test_linear_field_gives_constant_strain(name, request):
    mesh = request.getfixturevalue(name)
    eps = strains_at_quadrature_points(mesh, linear_field(mesh.points))
    sym_b = 0.5 * (B + B.T)
    assert np.abs(eps - sym_b).max() <= TOL * np.abs(sym_b).max()


@pytest.mark.parametrize("name", MESHES)
def test_displacement_patch_test(name, request, steel):
    """Boundary nodes prescribed, interior solved: the linear field is reproduced to 1e-10.

    For a curved (isoparametric) Tet10 the nodal force of a constant stress is
    ``sigma : int grad_xi N_a cof(J) dxi``, a cubic polynomial in the reference
    coordinates: the stiffness quadrature must be exact to degree 3 for the patch test
    to pass (the straight-sided case only needs degree 2).
    """
    mesh = request.getfixturevalue(name)
    K = stiffness_matrix(mesh, steel)
    u_exact = linear_field(mesh.points)
    split = dof_split(mesh.n_dofs, node_dofs(mesh.boundary_nodes()))
    assert split.free.size >= 3 * 8  # a real patch: several interior nodes
    u = static_solve(K, np.zeros(mesh.n_dofs), split, u_fixed=u_exact[split.fixed])
    err = np.abs(u[split.free] - u_exact[split.free]).max() / np.abs(u_exact).max()
    assert err <= TOL, f"{name}: interior displacement error {err:.2e}"


@pytest.mark.parametrize("name", MESHES)
def test_constant_stress_is_self_equilibrated_inside(name, request, steel):
    """K u_linear has no force at interior nodes (the divergence of a constant stress)."""
    mesh = request.getfixturevalue(name)
    K = stiffness_matrix(mesh, steel)
    u = linear_field(mesh.points)
    f = K @ u
    interior = np.setdiff1d(np.arange(mesh.n_nodes), mesh.boundary_nodes())
    scale = np.abs(f).max()
    residual = np.abs(f[node_dofs(interior)]).max() / scale
    assert residual <= TOL, f"{name}: interior force of a constant stress {residual:.2e}"
    # ... and the boundary forces carry the traction sigma.n: their resultant is zero.
    assert np.abs(f.reshape(-1, 3).sum(axis=0)).max() <= TOL * scale


@pytest.mark.parametrize("name", MESHES)
def test_rigid_motions_are_stress_free(name, request, steel, make_rigid_body_vectors):
    mesh = request.getfixturevalue(name)
    K = stiffness_matrix(mesh, steel)
    R = make_rigid_body_vectors(mesh.points, center=(0.3, -0.2, 0.7))
    rel = np.abs(K @ R).max(axis=0) / (abs(K).max() * np.abs(R).max(axis=0))
    assert rel.max() <= TOL, f"rigid-mode forces {rel}"
