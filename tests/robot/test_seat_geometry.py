"""Rings, bores and end faces about one axis, on samples of a tube and a solid cylinder."""

from __future__ import annotations

import numpy as np
import pytest

from flexarm.meshes.tolerances import tol as mesh_tol
from flexarm.robot.seat_geometry import (
    MESH_MARGIN,
    SECTORS,
    Polar,
    SeatFinder,
    coupling_rank,
    seat_margin,
)
from flexarm.robot.seat_sample import surface_sample

H = 0.01  # [m] mesh size


@pytest.fixture(scope="module")
def tube():
    """Bore r 20 mm, outer r 45 mm, z -30..30 mm."""
    import trimesh

    mesh = trimesh.creation.annulus(0.02, 0.045, 0.06, sections=48)
    return surface_sample(mesh.vertices, mesh.faces)


@pytest.fixture(scope="module")
def cylinder():
    """Solid, r 50 mm, z -50..50 mm."""
    import trimesh

    mesh = trimesh.creation.cylinder(0.05, 0.1, sections=64)
    return surface_sample(mesh.vertices, mesh.faces)


def test_polar_coordinates_about_an_axis():
    pts = np.array([[1.0, 0.0, 2.0], [0.0, -2.0, 0.0]])
    normals = np.array([[-1.0, 0.0, 0.0], [0.0, 0.0, 1.0]])
    p = Polar.of(pts, normals, (0.0, 0.0, 0.0), (0.0, 0.0, 1.0))
    np.testing.assert_allclose(p.t, [2.0, 0.0])
    np.testing.assert_allclose(p.r, [1.0, 2.0])
    np.testing.assert_allclose(p.na, [0.0, 1.0])
    np.testing.assert_allclose(p.nr, [-1.0, 0.0])  # the first faces the axis
    assert ((p.sector >= 0) & (p.sector < SECTORS)).all() and p.sector[0] != p.sector[1]


def test_the_tube_is_a_bore_through_its_length(tube):
    f = SeatFinder.of(tube, (0.0, 0.0, 0.0), (0.0, 0.0, 1.0), H)
    lo, hi = f.rings.extent()
    b = f.rings.b  # rings come to a bin; the top one reaches up to 3 bins
    assert lo == pytest.approx(-0.03, abs=b) and hi == pytest.approx(0.03, abs=3 * b)
    for s in (1, -1):
        r, u = f.bore_end(s, None)
        assert r == pytest.approx(0.02, abs=tube.spacing) and u == pytest.approx(0.03, abs=1e-3)
    bore = f.bore(1, *f.bore_end(1, None))
    assert bore.kind == "bore" and bore.r_min < 0.02 < bore.r_max < 0.045
    np.testing.assert_allclose([bore.u_lo, bore.u_hi], [-0.03, 0.03], atol=1e-3)
    # the end face is the annulus outside the bore
    face = f.face(1, 0.7, 0.0, f.r_probe)
    assert face.kind == "face" and face.u_lo == face.u_hi == pytest.approx(0.03)
    assert 0.018 < face.r_min < 0.02 < face.r_max < 0.045


def test_the_solid_cylinder_seats_on_its_end_discs(cylinder):
    f = SeatFinder.of(cylinder, (0.0, 0.0, 0.0), (0.0, 0.0, 1.0), H)
    assert f.bore_end(1, None) is None and f.bore_end(-1, None) is None
    for s in (1, -1):
        face = f.face(s, 0.7, 0.0, f.r_probe)
        assert face.u_lo == face.u_hi == pytest.approx(0.05)
        assert face.r_min == 0.0 and 0.7 * 0.05 <= face.r_max < 0.05
        assert (s * cylinder.normals[face.mask, 2] > 0.99).all()  # on that end only


def test_coupling_rank():
    assert coupling_rank(np.zeros((0, 3))) == 0
    assert coupling_rank(np.zeros((3, 3))) == 3  # one point
    assert coupling_rank(np.c_[np.arange(4.0), np.zeros(4), np.zeros(4)]) == 5  # collinear
    assert coupling_rank(np.eye(3)) == 6


def test_seat_margin_is_the_envelope_or_a_tenth_of_the_mesh(cylinder):
    envelope = 3.0 * mesh_tol.tet_envelope * cylinder.diagonal
    assert seat_margin(cylinder, 1e-6) == pytest.approx(envelope)
    assert seat_margin(cylinder, H) == pytest.approx(MESH_MARGIN * H)
