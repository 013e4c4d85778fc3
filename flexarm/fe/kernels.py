"""Vectorised element kernels: Tet4 / Tet10 stiffness and consistent mass.

One kernel evaluates all elements and quadrature points of a chunk at once.  Its
scatter layout ``(nn, nn, e, ...)``, node pair first and element second, is what the
assembly in :mod:`flexarm.fe.assembly` consumes without a copy; the public functions
give element-major views ``(e, ...)`` of it.  Straight-sided elements take a fast path
built from reference-element integrals and the inverse corner Jacobian.
"""

from __future__ import annotations

import numpy as np

from . import rows
from .material import Material
from .mesh import TetMesh
from .quadrature import tet_quadrature
from .tet4 import Tet4
from .tet10 import Tet10
from .tolerances import tol
from .topology import TET10_EDGES

__all__ = [
    "element_type",
    "is_affine",
    "stiffness_kernel",
    "stiffness_blocks",
    "element_stiffness",
    "mass_kernel",
    "element_mass",
    "reference_rule",
]


def element_type(mesh: TetMesh):
    """The element class (:class:`Tet4` or :class:`Tet10`) of ``mesh``."""
    return Tet4 if mesh.order == 1 else Tet10


def _geometry(coords: np.ndarray, dN: np.ndarray, weights: np.ndarray):
    """Physical gradients (e, q, nn, 3) and weights*detJ (e, q) of a chunk."""
    J = np.matmul(coords.transpose(0, 2, 1)[:, None], dN[None])
    detJ = np.linalg.det(J)
    G = np.matmul(dN[None], np.linalg.inv(J))
    return G, detJ * weights


def _affine_inverse(mesh: TetMesh, tets: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Inverse Jacobian (e, 3, 3) [1/m] and det J (e,) of the corner map, vectorised.

    Rows of the inverse are the cofactor vectors: no per-matrix LAPACK call.
    """
    X = mesh.points[tets[:, :4]]
    a = X[:, 1:] - X[:, :1]  # a[:, j] = dx/dxi_j
    c0, c1, c2 = np.cross(a[:, 1], a[:, 2]), np.cross(a[:, 2], a[:, 0]), np.cross(a[:, 0], a[:, 1])
    det = np.einsum("ei,ei->e", a[:, 0], c0)
    return np.stack([c0, c1, c2], axis=1) / det[:, None, None], det


def is_affine(mesh: TetMesh) -> bool:
    """True when every element is straight-sided (Tet4, or Tet10 with mid-edge midpoints)."""
    if mesh.order == 1:
        return True
    if rows.available():
        dev, scale = rows.midside_deviation(mesh)
        return bool(dev <= tol.straight_midside * scale)
    corners = mesh.points[mesh.tets[:, TET10_EDGES]]  # (m, 6, 2, 3)
    mids = mesh.points[mesh.tets[:, 4:]]
    dev = np.abs(mids - corners.mean(axis=2)).max()
    scale = np.abs(corners[:, :, 0] - corners[:, :, 1]).max()
    return bool(dev <= tol.straight_midside * scale)


def _reference_gradient_products(el) -> np.ndarray:
    """D[a, b, k, l] = int_ref dN_a/dxi_k dN_b/dxi_l (exact for straight elements)."""
    pts, w = tet_quadrature(el.stiffness_degree)
    dN = el.shape_grad(pts)
    return np.einsum("q,qak,qbl->abkl", w, dN, dN)


def stiffness_kernel(
    mesh: TetMesh, material: Material, elements=slice(None), affine: bool | None = None,
    out: np.ndarray | None = None,
) -> np.ndarray:
    """Element stiffness blocks in scatter layout (nn, nn, e, 3, 3) [N/m], C-contiguous.

    Node pair first, element second: the affine GEMM writes this layout directly and
    ``reshape(-1, 9)`` gives the rows (a, b, e) that the scatter consumes, no copy.
    ``out`` (at least nn^2 e 9 float64, contiguous) is reused as the GEMM target, which
    saves page faults on a fresh array per chunk.
    """
    el = element_type(mesh)
    tets = mesh.tets[elements]
    nn = el.n_nodes
    lam, mu = material.lame_lambda, material.lame_mu
    if affine is None:
        affine = is_affine(mesh)
    if not affine:
        pts, w = tet_quadrature(el.curved_stiffness_degree)
        G, wdet = _geometry(mesh.points[tets], el.shape_grad(pts), w)
        n_e = len(tets)
        Gf = G.reshape(n_e, len(w), 3 * nn)
        A = np.matmul((Gf * wdet[:, :, None]).transpose(0, 2, 1), Gf).reshape(n_e, nn, 3, nn, 3)
        S = np.einsum("eaibi->eab", A)
        K = lam * A + mu * A.transpose(0, 1, 4, 3, 2)
        K += mu * S[:, :, None, :, None] * np.eye(3)[None, None, :, None, :]
        return np.ascontiguousarray(K.transpose(1, 3, 0, 2, 4))
    n_e = len(tets)
    D = _reference_gradient_products(el)  # (nn, nn, 3, 3)
    lhs = (lam * D + mu * D.transpose(0, 1, 3, 2)).reshape(nn * nn, 9)
    P, det = _affine_inverse(mesh, tets)
    # Q[k, l, e, i, j] = det P[k, i] P[l, j], built in GEMM layout (no transposed copy)
    Pt = P.transpose(1, 0, 2)
    Q = (det[:, None] * Pt)[:, None, :, :, None] * Pt[None, :, :, None, :]
    size = nn * nn * n_e * 9
    K = np.zeros(size) if out is None or out.size < size else out.reshape(-1)[:size]
    K = np.matmul(lhs, Q.reshape(9, n_e * 9), out=K.reshape(nn * nn, n_e * 9))  # one GEMM
    K = K.reshape(nn, nn, n_e, 3, 3)
    # mu tr(D_ab P P^T) det on the diagonal i == j: a second, 9-deep GEMM
    G = np.matmul(det[:, None, None] * P, P.transpose(0, 2, 1)).reshape(n_e, 9)
    S = (mu * D.reshape(nn * nn, 9)) @ G.T  # (nn^2, e)
    K3 = K.reshape(nn * nn, n_e, 9)
    for d in (0, 4, 8):
        K3[:, :, d] += S
    return K


def stiffness_blocks(
    mesh: TetMesh, material: Material, elements=slice(None), affine: bool | None = None
) -> np.ndarray:
    """Element stiffness as node-pair blocks (e, nn, nn, 3, 3) [N/m].

    ``K[e, a, b, i, j] = int lam dNa/dx_i dNb/dx_j
    + mu (dNa/dx_j dNb/dx_i + delta_ij grad Na . grad Nb)``.

    Straight-sided elements take the fast path: with ``P = J^-1``,
    ``K_ab = det J (P^T (lam D_ab + mu D_ab^T) P + mu tr(D_ab P P^T) I)`` where ``D``
    holds the reference gradient products, so all elements of a chunk are one GEMM
    (plus a 9-deep one for the trace term).  The result is a transposed view of the
    scatter layout.
    """
    return stiffness_kernel(mesh, material, elements, affine).transpose(2, 0, 1, 3, 4)


def element_stiffness(mesh: TetMesh, material: Material, elements=slice(None)) -> np.ndarray:
    """Element stiffness stack (e, 3nn, 3nn) [N/m], local DOF ``3*a + i``.

    Examples
    --------
    >>> from flexarm.fe.material import MATERIALS
    >>> Ke = element_stiffness(TetMesh.unit_tet(), MATERIALS["steel"])
    >>> Ke.shape, bool(np.allclose(Ke[0], Ke[0].T))
    ((1, 12, 12), True)
    """
    B = stiffness_blocks(mesh, material, elements)
    n_e, nn = B.shape[:2]
    return B.transpose(0, 1, 3, 2, 4).reshape(n_e, 3 * nn, 3 * nn)


def _reference_mass(el) -> np.ndarray:
    pts, w = tet_quadrature(el.mass_degree)
    N = el.shape(pts)
    return np.einsum("q,qa,qb->ab", w, N, N)


def reference_rule(mesh: TetMesh) -> tuple[tuple[np.ndarray, np.ndarray], np.ndarray]:
    """What straight-sided elements of ``mesh`` need from the reference element.

    Returns ``(dN, w), N``: the reference gradients ``dN[q, a, k] = dN_a/dxi_k`` (q, nn, 3)
    at the points of the rule that integrates the stiffness exactly, its weights (q,), and
    ``N[a, b] = int N_a N_b`` (nn, nn) over the reference tetrahedron (volume 1/6).

    Examples
    --------
    >>> (dN, w), N = reference_rule(TetMesh.unit_tet())
    >>> dN.shape, round(float(N.sum()) * 6, 12)  # partition of unity: sum = volume
    ((1, 4, 3), 1.0)
    """
    el = element_type(mesh)
    pts, w = tet_quadrature(el.stiffness_degree)
    dN = np.ascontiguousarray(el.shape_grad(pts), dtype=np.float64)
    return (dN, np.ascontiguousarray(w, dtype=np.float64)), _reference_mass(el)


def mass_kernel(mesh: TetMesh, rho: float, elements=slice(None), affine: bool | None = None):
    """Scalar element mass in scatter layout (nn, nn, e) [kg], C-contiguous."""
    el = element_type(mesh)
    tets = mesh.tets[elements]
    if affine is None:
        affine = is_affine(mesh)
    if affine:
        _, det = _affine_inverse(mesh, tets)
        return _reference_mass(el)[:, :, None] * (rho * det)
    pts, w = tet_quadrature(el.mass_degree)
    N = el.shape(pts)
    J = np.matmul(mesh.points[tets].transpose(0, 2, 1)[:, None], el.shape_grad(pts)[None])
    wdet = np.linalg.det(J) * w
    NN = np.einsum("qa,qb->abq", N, N).reshape(-1, len(w))
    return (NN @ (rho * wdet).T).reshape(el.n_nodes, el.n_nodes, len(tets))


def element_mass(mesh: TetMesh, rho: float, elements=slice(None), affine: bool | None = None):
    """Scalar element mass stack (e, nn, nn) [kg]: ``rho int N_a N_b dV``.

    The vector mass matrix is this block times the 3x3 identity.
    """
    return mass_kernel(mesh, rho, elements, affine).transpose(2, 0, 1)
