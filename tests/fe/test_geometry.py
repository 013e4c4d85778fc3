"""Small-motion kinematics: skew(r) v = r x v, and rigid_transport against u + theta x r, its
composition and inverse, and its transpose carrying a force to the wrench [f; r x f]."""

from __future__ import annotations

import numpy as np

from flexarm.fe.geometry import rigid_transport, skew


def test_skew_is_the_cross_product_batched():
    rng = np.random.default_rng(0)
    r, v = rng.normal(size=(2, 4, 3)), rng.normal(size=(2, 4, 3))
    S = skew(r)
    assert S.shape == (2, 4, 3, 3)
    np.testing.assert_allclose(np.einsum("...ij,...j->...i", S, v), np.cross(r, v), atol=1e-15)
    np.testing.assert_array_equal(S, -np.swapaxes(S, -1, -2))
    np.testing.assert_allclose(np.einsum("...ij,...j->...i", S, r), 0.0, atol=1e-15)
    # S S = r r^T - |r|^2 I
    a = r[0, 0]
    np.testing.assert_allclose(skew(a) @ skew(a), np.outer(a, a) - a @ a * np.eye(3), atol=1e-14)


def test_rigid_transport_moves_a_point_with_the_reference():
    rng = np.random.default_rng(1)
    r = rng.normal(size=3)
    for x in rng.normal(size=(5, 6)):
        out = rigid_transport(r) @ x
        np.testing.assert_allclose(out[:3], x[:3] + np.cross(x[3:], r), atol=1e-15)
        np.testing.assert_array_equal(out[3:], x[3:])


def test_rigid_transport_composes_and_inverts():
    a, b = np.array([0.3, -1.0, 2.0]), np.array([1.5, 0.2, -0.7])
    np.testing.assert_allclose(rigid_transport(a) @ rigid_transport(b), rigid_transport(a + b),
                               atol=1e-15)
    np.testing.assert_allclose(rigid_transport(a) @ rigid_transport(-a), np.eye(6), atol=1e-15)
    assert rigid_transport(np.zeros((2, 3))).shape == (2, 6, 6)


def test_transpose_carries_a_force_to_its_wrench():
    """Virtual work: A^T [f; 0] is the force f and its moment r x f about the reference."""
    r, f = np.array([0.5, 0.0, 1.0]), np.array([0.0, 200.0, -50.0])
    w = rigid_transport(r).T @ np.r_[f, 0.0, 0.0, 0.0]
    np.testing.assert_allclose(w, np.r_[f, np.cross(r, f)], atol=1e-13)
