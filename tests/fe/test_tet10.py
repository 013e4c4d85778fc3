"""Tet10 shape functions (VTK order): partition of unity, Kronecker delta at corners and
mid-edge nodes, zero-sum gradients equal to central differences, quadratic completeness, and the
nodal integrals -V/20 (corners) and V/5 (mid-edges) at mass_degree."""

from __future__ import annotations

import numpy as np
import pytest

from flexarm.fe import TET10_EDGES, Tet10, tet_quadrature

CORNERS = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]], dtype=float)
NODES = np.vstack([CORNERS, CORNERS[TET10_EDGES].mean(axis=1)])


@pytest.fixture(scope="module")
def xi():
    rng = np.random.default_rng(1)
    return rng.dirichlet(np.ones(4), size=40)[:, 1:]


def test_vtk_mid_edge_order():
    np.testing.assert_array_equal(TET10_EDGES, [[0, 1], [1, 2], [0, 2], [0, 3], [1, 3], [2, 3]])
    assert Tet10.n_nodes == 10


def test_kronecker_delta_at_the_ten_nodes():
    np.testing.assert_allclose(Tet10.shape(NODES), np.eye(10), atol=1e-15)


def test_partition_of_unity_and_zero_sum_gradients(xi):
    N, G = Tet10.shape(xi), Tet10.shape_grad(xi)
    assert N.shape == (40, 10) and G.shape == (40, 10, 3)
    np.testing.assert_allclose(N.sum(axis=1), 1.0, rtol=0, atol=1e-14)
    np.testing.assert_allclose(G.sum(axis=1), 0.0, atol=1e-13)


def test_quadratic_completeness(xi):
    """sum_a N_a f(x_a) = f(x) for every quadratic f (here a random one)."""
    rng = np.random.default_rng(2)
    A, b, c = rng.normal(size=(3, 3)), rng.normal(size=3), rng.normal()

    def f(x):
        return np.einsum("qi,ij,qj->q", x, A, x) + x @ b + c

    np.testing.assert_allclose(Tet10.shape(xi) @ f(NODES), f(xi), rtol=1e-12, atol=1e-13)
    # and its gradient: sum_a grad N_a f(x_a) = (A + A^T) x + b
    np.testing.assert_allclose(np.einsum("qaj,a->qj", Tet10.shape_grad(xi), f(NODES)),
                               xi @ (A + A.T) + b, rtol=1e-11, atol=1e-12)


def test_gradients_equal_central_differences(xi):
    """Central differences are exact for quadratics (up to rounding)."""
    G = Tet10.shape_grad(xi)
    h = 1e-3
    for j in range(3):
        e = np.zeros(3)
        e[j] = h
        fd = (Tet10.shape(xi + e) - Tet10.shape(xi - e)) / (2 * h)
        np.testing.assert_allclose(G[:, :, j], fd, atol=1e-11)


def test_nodal_integrals_and_exact_mass_rule():
    """int N_a = -V/20 at corners and V/5 at mid-edges (V = 1/6); the mass rule is exact."""
    pts, w = tet_quadrature(Tet10.mass_degree)
    N = Tet10.shape(pts)
    V = 1 / 6
    np.testing.assert_allclose(w @ N, [-V / 20] * 4 + [V / 5] * 6, rtol=1e-13)
    M = np.einsum("q,qa,qb->ab", w, N, N)
    pts8, w8 = tet_quadrature(8)
    N8 = Tet10.shape(pts8)
    np.testing.assert_allclose(M, np.einsum("q,qa,qb->ab", w8, N8, N8), rtol=1e-12, atol=1e-16)
    # textbook consistent mass, in units of V / 420: corner 6, corner-corner 1, corner and
    # adjacent mid -4, opposite mid -6, mid 32, mids sharing a corner 16, opposite mids 8
    for (a, b), value in {(0, 0): 6, (0, 1): 1, (0, 4): -4, (0, 5): -6, (4, 4): 32,
                          (4, 5): 16, (4, 9): 8}.items():
        assert M[a, b] == pytest.approx(value * V / 420, rel=1e-12), (a, b)


def test_stiffness_degree_integrates_gradient_products_exactly():
    pts, w = tet_quadrature(Tet10.stiffness_degree)
    G = Tet10.shape_grad(pts)
    pts6, w6 = tet_quadrature(6)
    G6 = Tet10.shape_grad(pts6)
    np.testing.assert_allclose(np.einsum("q,qak,qbl->abkl", w, G, G),
                               np.einsum("q,qak,qbl->abkl", w6, G6, G6), rtol=1e-12, atol=1e-15)
