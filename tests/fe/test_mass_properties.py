"""Mass properties: the reference tetrahedron and a rotated box against their closed forms,
scaling laws (m ~ s^3, I ~ s^5), and the rigid-body mass matrix against m |u + theta x r|^2."""

from __future__ import annotations

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

from flexarm.fe import MassProperties, TetMesh, mass_properties, rigid_body_mass_matrix


def test_reference_tetrahedron_closed_form():
    """V = 1/6, c = 1/4; int x^2 = 1/60, int xy = 1/120 -> I_xx = rho/80, I_xy = rho/480."""
    rho = 1200.0
    mp = mass_properties(TetMesh.unit_tet(), rho)
    assert mp.mass == pytest.approx(rho / 6, rel=1e-15)
    np.testing.assert_allclose(mp.center_of_mass, [0.25] * 3, rtol=1e-15)
    expected = np.full((3, 3), rho / 480)
    np.fill_diagonal(expected, rho / 80)
    np.testing.assert_allclose(mp.inertia, expected, rtol=1e-13)


def test_rotated_box_inertia_is_R_I_RT():
    """The inertia tensor is in the mesh axes: a box turned by R has R diag(I) R^T."""
    a, b, c, rho = 0.8, 0.4, 0.2, 7850.0
    R = Rotation.from_rotvec(0.7 * np.array([1.0, 2.0, 2.0]) / 3).as_matrix()
    box = TetMesh.box((a, b, c), (2, 2, 1), origin=(-a / 2, -b / 2, -c / 2))
    offset = np.array([0.3, -0.2, 1.1])
    mesh = TetMesh(box.points @ R.T + offset, box.tets)
    mp = mass_properties(mesh, rho)
    m = rho * a * b * c
    assert mp.mass == pytest.approx(m, rel=1e-13)
    np.testing.assert_allclose(mp.center_of_mass, offset, atol=1e-14)
    I0 = m / 12 * np.diag([b**2 + c**2, a**2 + c**2, a**2 + b**2])
    np.testing.assert_allclose(mp.inertia, R @ I0 @ R.T, atol=1e-12 * I0.max())


def test_tet10_uses_its_corner_tetrahedra():
    base = TetMesh.box((1.0, 0.5, 0.25), (2, 2, 1))
    a, b = mass_properties(base, 1000.0), mass_properties(base.to_tet10(), 1000.0)
    assert a.mass == b.mass
    np.testing.assert_array_equal(a.center_of_mass, b.center_of_mass)
    np.testing.assert_array_equal(a.inertia, b.inertia)


def test_scaling_laws_and_translation_invariance():
    mesh = TetMesh.box((0.3, 0.2, 0.1), (3, 2, 1))
    mp = mass_properties(mesh, 2000.0)
    big = mass_properties(mesh.scaled(2.0), 2000.0)
    assert big.mass == pytest.approx(8 * mp.mass, rel=1e-13)
    np.testing.assert_allclose(big.inertia, 32 * mp.inertia, rtol=1e-12, atol=1e-15)
    moved = mass_properties(mesh.translated([5.0, -3.0, 2.0]), 2000.0)
    np.testing.assert_allclose(moved.center_of_mass, mp.center_of_mass + [5.0, -3.0, 2.0])
    np.testing.assert_allclose(moved.inertia, mp.inertia, rtol=1e-9, atol=1e-12)
    assert mass_properties(mesh, 4000.0).mass == pytest.approx(2 * mp.mass, rel=1e-15)


def test_inertia_about_a_point_of_a_point_mass():
    """A point mass (zero own inertia): I_p = m (|d|^2 I - d d^T), d = c - p."""
    mp = MassProperties(3.0, np.array([1.0, 2.0, -1.0]), np.zeros((3, 3)))
    p = np.array([0.5, 0.0, 1.0])
    d = mp.center_of_mass - p
    np.testing.assert_allclose(mp.inertia_about(p), 3.0 * (d @ d * np.eye(3) - np.outer(d, d)))
    np.testing.assert_array_equal(mp.inertia_about(mp.center_of_mass), np.zeros((3, 3)))


def test_rigid_body_mass_matrix_is_the_kinetic_energy():
    """x^T M x = m |u + theta x r|^2 + theta^T I_c theta for the motion x of the reference."""
    rng = np.random.default_rng(3)
    A = rng.normal(size=(3, 3))
    mp = MassProperties(4.5, np.array([0.2, -0.4, 0.9]), A @ A.T)
    ref = np.array([1.0, 0.5, -0.3])
    M = rigid_body_mass_matrix(mp, ref)
    np.testing.assert_allclose(M, M.T, atol=1e-14)
    r = mp.center_of_mass - ref
    for x in rng.normal(size=(5, 6)):
        u, th = x[:3], x[3:]
        v = u + np.cross(th, r)
        assert x @ M @ x == pytest.approx(mp.mass * v @ v + th @ mp.inertia @ th, rel=1e-12)
    np.testing.assert_allclose(M[3:, 3:], mp.inertia_about(ref), rtol=1e-13)
    np.testing.assert_allclose(M[:3, :3], mp.mass * np.eye(3))
