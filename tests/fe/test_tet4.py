"""Tet4 shape functions: partition of unity, Kronecker delta at the nodes, zero-sum and exact
gradients, linear completeness, and the consistent mass V (1 + delta_ab) / 20 at mass_degree."""

from __future__ import annotations

import numpy as np
import pytest

from flexarm.fe import Tet4, tet_quadrature

NODES = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]], dtype=float)


@pytest.fixture(scope="module")
def xi():
    rng = np.random.default_rng(0)
    return rng.dirichlet(np.ones(4), size=50)[:, 1:]


def test_shapes(xi):
    assert Tet4.n_nodes == 4
    assert Tet4.shape(xi).shape == (50, 4) and Tet4.shape_grad(xi).shape == (50, 4, 3)
    assert Tet4.shape(np.array([0.1, 0.2, 0.3])).shape == (1, 4)  # one point


def test_partition_of_unity_and_linear_completeness(xi):
    N = Tet4.shape(xi)
    np.testing.assert_allclose(N.sum(axis=1), 1.0, rtol=0, atol=1e-15)
    np.testing.assert_allclose(N @ NODES, xi, atol=1e-15)  # sum N_a x_a = x
    assert np.all(N >= 0)  # inside the element


def test_kronecker_delta_at_the_nodes():
    np.testing.assert_array_equal(Tet4.shape(NODES), np.eye(4))


def test_gradients_sum_to_zero_and_match_finite_differences(xi):
    G = Tet4.shape_grad(xi)
    np.testing.assert_array_equal(G.sum(axis=1), 0.0)
    h = 1e-3
    for j in range(3):
        e = np.zeros(3)
        e[j] = h
        fd = (Tet4.shape(xi + e) - Tet4.shape(xi - e)) / (2 * h)
        np.testing.assert_allclose(G[:, :, j], fd, atol=1e-12)
    # sum x_a grad N_a = I: the reference Jacobian of the reference tet is the identity
    np.testing.assert_allclose(np.einsum("ai,qaj->qij", NODES, G), np.broadcast_to(np.eye(3),
                                                                                     (50, 3, 3)))


def test_gradient_array_is_a_private_copy(xi):
    G = Tet4.shape_grad(xi[:2])
    G[:] = 99.0
    np.testing.assert_array_equal(Tet4.shape_grad(xi[:2])[0, 0], [-1.0, -1.0, -1.0])


def test_mass_degree_integrates_the_consistent_mass():
    """int N_a N_b over the reference tet (V = 1/6) = V (1 + delta_ab) / 20."""
    pts, w = tet_quadrature(Tet4.mass_degree)
    N = Tet4.shape(pts)
    np.testing.assert_allclose(np.einsum("q,qa,qb->ab", w, N, N), (1 + np.eye(4)) / 120,
                               rtol=1e-14)
    pts, w = tet_quadrature(Tet4.stiffness_degree)
    G = Tet4.shape_grad(pts)
    np.testing.assert_allclose(np.einsum("q,qak,qbl->abkl", w, G, G),
                               np.einsum("ak,bl->abkl", G[0], G[0]) / 6, rtol=1e-15)
