"""Load vectors: gravity sums to rho V g with the moment m c x g (consistent mass), nodal loads
total or per node, shape checks."""

from __future__ import annotations

import numpy as np
import pytest

from flexarm.fe import (
    STANDARD_GRAVITY,
    TetMesh,
    gravity_load,
    mass_matrix,
    mass_properties,
    nodal_load,
)


def test_standard_gravity_points_down_z():
    np.testing.assert_array_equal(STANDARD_GRAVITY, [0.0, 0.0, -9.80665])


@pytest.mark.parametrize("order", [1, 2])
def test_gravity_resultant_and_moment_are_those_of_the_weight(order):
    """Sum of f = rho V g; sum of x x f = m c x g (M reproduces linear fields exactly)."""
    rho, size = 2700.0, np.array([0.6, 0.3, 0.2])
    mesh = TetMesh.box(size, (3, 2, 2), order=order, origin=(0.5, -1.0, 2.0))
    M = mass_matrix(mesh, rho)
    g = np.array([1.5, -2.0, -9.0])
    f = gravity_load(M, g).reshape(-1, 3)
    mass = rho * np.prod(size)
    np.testing.assert_allclose(f.sum(axis=0), mass * g, rtol=1e-12)
    com = np.array([0.5, -1.0, 2.0]) + size / 2
    moment = np.cross(mesh.points, f).sum(axis=0)
    np.testing.assert_allclose(moment, np.cross(mass * com, g), rtol=1e-11)
    assert mass_properties(mesh, rho).mass == pytest.approx(mass, rel=1e-12)


def test_gravity_default_is_standard_gravity():
    M = mass_matrix(TetMesh.unit_tet(), 600.0)
    f = gravity_load(M).reshape(-1, 3)
    np.testing.assert_allclose(f.sum(axis=0), 100.0 * STANDARD_GRAVITY, rtol=1e-13)
    # Tet4 consistent mass: every node of a single element gets a quarter of the weight
    np.testing.assert_allclose(f[:, 2], np.full(4, -100.0 * 9.80665 / 4), rtol=1e-13)


def test_gravity_must_be_a_3_vector():
    M = mass_matrix(TetMesh.unit_tet(), 1.0)
    with pytest.raises(ValueError, match=r"gravity must be a \(3,\) vector, got shape \(2,\)"):
        gravity_load(M, [0.0, -9.8])


def test_nodal_load_distributed_total_or_per_node():
    f = nodal_load(5, [1, 3], [10.0, 0.0, -4.0]).reshape(-1, 3)
    np.testing.assert_array_equal(f[[1, 3]], [[5.0, 0, -2.0]] * 2)
    np.testing.assert_array_equal(f[[0, 2, 4]], 0.0)
    g = nodal_load(5, [1, 3], [10.0, 0.0, -4.0], distribute=False).reshape(-1, 3)
    np.testing.assert_array_equal(g.sum(axis=0), [20.0, 0.0, -8.0])
    # a node named twice gets its share twice (the total is kept)
    h = nodal_load(3, [2, 2, 0, 0], [4.0, 8.0, 0.0]).reshape(-1, 3)
    np.testing.assert_array_equal(h, [[2.0, 4.0, 0], [0, 0, 0], [2.0, 4.0, 0]])


def test_nodal_force_must_be_a_3_vector():
    with pytest.raises(ValueError, match=r"force must be a \(3,\) vector, got shape \(6,\)"):
        nodal_load(4, [0], np.zeros(6))
