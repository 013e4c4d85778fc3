"""Bodies: the rigid-body mass matrix of a point mass against m |u + theta x r|^2, attachment
points by rigid transport, combined mass properties against the reduced-mass formula and a box
cut in two, lumped masses, and Body validation."""

from __future__ import annotations

import numpy as np
import pytest

from flexarm.assembly.bodies import (
    Body,
    combine_mass_properties,
    point_mass_properties,
    rigid_body,
    rigid_transport,
)
from flexarm.fe import TetMesh, mass_properties


def test_point_mass_rigid_body():
    """M = m [[I, -S], [S, -S S]] with S = skew(c - ref); kinetic energy m |u + theta x r|^2."""
    m, c, ref = 7.0, np.array([0.4, -0.1, 0.25]), np.array([0.1, 0.2, 0.0])
    body = rigid_body("mass", point_mass_properties(m, c), ref, {"tip": [1.0, 0.2, 0.0]})
    r = c - ref
    S = np.array([[0, -r[2], r[1]], [r[2], 0, -r[0]], [-r[1], r[0], 0]])
    expected = m * np.block([[np.eye(3), -S], [S, -S @ S]])
    np.testing.assert_allclose(body.M, expected, rtol=1e-14, atol=1e-15)
    rng = np.random.default_rng(0)
    for x in rng.normal(size=(4, 6)):
        v = x[:3] + np.cross(x[3:], r)
        assert x @ body.M @ x == pytest.approx(m * v @ v, rel=1e-12)
    assert body.is_rigid and body.n_nodes == 1 and body.n_dofs == 6
    assert body.damping_ratio == 0.0 and not body.K.any()
    np.testing.assert_array_equal(body.node_positions, [ref])
    np.testing.assert_array_equal(body.G("tip"), rigid_transport(np.array([0.9, 0.0, 0.0])))


def test_combined_point_masses_reduced_mass():
    """Two point masses: I_c = m1 m2 / (m1 + m2) (|d|^2 I - d d^T), d = b - a."""
    m1, m2 = 2.0, 6.0
    a, b = np.array([0.0, 1.0, 0.0]), np.array([1.0, 1.0, 2.0])
    mp = combine_mass_properties([point_mass_properties(m1, a), point_mass_properties(m2, b)])
    d = b - a
    assert mp.mass == 8.0
    np.testing.assert_allclose(mp.center_of_mass, (m1 * a + m2 * b) / 8.0)
    np.testing.assert_allclose(mp.inertia, m1 * m2 / 8.0 * (d @ d * np.eye(3) - np.outer(d, d)),
                               atol=1e-14)


def test_combined_halves_equal_the_whole_box():
    whole = mass_properties(TetMesh.box((2.0, 1.0, 0.5), (2, 1, 1)), 1000.0)
    left = mass_properties(TetMesh.box((1.0, 1.0, 0.5), (1, 1, 1)), 1000.0)
    right = mass_properties(TetMesh.box((1.0, 1.0, 0.5), (1, 1, 1), origin=(1, 0, 0)), 1000.0)
    mp = combine_mass_properties([left, right])
    assert mp.mass == pytest.approx(whole.mass, rel=1e-14)
    np.testing.assert_allclose(mp.center_of_mass, whole.center_of_mass, rtol=1e-14)
    np.testing.assert_allclose(mp.inertia, whole.inertia, rtol=1e-12, atol=1e-12)


def test_point_mass_properties_inertia_forms():
    np.testing.assert_array_equal(point_mass_properties(1.0, [0, 0, 0]).inertia, np.zeros((3, 3)))
    np.testing.assert_array_equal(point_mass_properties(1.0, [0, 0, 0], [1, 2, 3]).inertia,
                                  np.diag([1.0, 2.0, 3.0]))
    J = [[1.0, 0.1, 0.0], [0.1, 2.0, 0.0], [0.0, 0.0, 3.0]]
    np.testing.assert_array_equal(point_mass_properties(1.0, [0, 0, 0], J).inertia, J)
    with pytest.raises(ValueError, match="lumped mass must be >= 0 kg, got -1.0"):
        point_mass_properties(-1.0, [0, 0, 0])
    with pytest.raises(ValueError, match=r"lumped inertia must be \(3,\) or \(3, 3\), got \(2,\)"):
        point_mass_properties(1.0, [0, 0, 0], [1.0, 2.0])
    with pytest.raises(ValueError, match="combined body has no mass"):
        combine_mass_properties([point_mass_properties(0.0, [0, 0, 0])])


def test_multi_node_body():
    """Two 6-DOF nodes and two modal DOFs: translation modes move both nodes, not the modes."""
    M, K = np.eye(14), np.diag(np.r_[np.zeros(12), 1.0, 2.0])
    G = np.zeros((6, 14))
    G[:, 6:12] = np.eye(6)
    b = Body("flex", M, K, [[0, 0, 0], [1.0, 0, 0]], {"tip": G})
    assert (b.n_nodes, b.n_dofs, b.is_rigid) == (2, 14, False)
    U = b.translation_modes()
    expected = np.zeros((14, 3))
    expected[0:3] = expected[6:9] = np.eye(3)
    np.testing.assert_array_equal(U, expected)
    with pytest.raises(ValueError, match="read-only"):
        b.M[0, 0] = 2.0
    with pytest.raises(KeyError, match=r"body 'flex' has no point 'tcp' \(has \['tip'\]\)"):
        b.G("tcp")


@pytest.mark.parametrize("args, message", [
    ((np.eye(6), np.eye(7), [[0, 0, 0]]), "body 'b': M and K must be square and equal, got "
                                          r"\(6, 6\) and \(7, 7\)"),
    ((np.eye(6), np.eye(6), [[0, 0, 0], [1, 0, 0]]), "body 'b': 2 nodes need >= 12 DOFs, got 6"),
])
def test_body_validation(args, message):
    with pytest.raises(ValueError, match=message):
        Body("b", *args)
    with pytest.raises(ValueError, match=r"body 'b' point 'p': G must be \(6, 6\), got \(3, 6\)"):
        Body("b", np.eye(6), np.zeros((6, 6)), [[0, 0, 0]], {"p": np.zeros((3, 6))})
