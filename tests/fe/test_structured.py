"""Structured boxes: Kuhn split (6 positive tets of h_x h_y h_z / 6 per cell), conformity (each
interior face shared by two tets, Euler characteristic V - E + F - T = 1) and Tet10 promotion
(one midpoint per unique edge)."""

from __future__ import annotations

import numpy as np
import pytest

from flexarm.fe.structured import box_tets, promote_tet10
from flexarm.fe.topology import TET10_EDGES, TET_FACES

DIVS = [(1, 1, 1), (2, 1, 3), (3, 3, 2)]


def _signed_volumes(points, tets):
    d = points[tets[:, 1:4]] - points[tets[:, :1]]
    return np.einsum("ij,ij->i", d[:, 0], np.cross(d[:, 1], d[:, 2])) / 6


@pytest.mark.parametrize("divs", DIVS)
def test_kuhn_split_volumes_and_grid(divs):
    size, origin = np.array([1.2, 0.5, 0.9]), np.array([-1.0, 0.5, 2.0])
    points, tets = box_tets(size, divs, origin)
    nx, ny, nz = divs
    assert points.shape == ((nx + 1) * (ny + 1) * (nz + 1), 3)
    assert tets.shape == (6 * nx * ny * nz, 4)
    np.testing.assert_allclose(_signed_volumes(points, tets), np.prod(size / divs) / 6, rtol=1e-12)
    np.testing.assert_allclose(points.min(axis=0), origin)
    np.testing.assert_allclose(points.max(axis=0), origin + size)
    for axis, n in enumerate(divs):  # grid planes, equally spaced
        np.testing.assert_allclose(np.unique(points[:, axis]),
                                   np.linspace(origin[axis], origin[axis] + size[axis], n + 1))
    # each cell's 6 tets share its main diagonal (0,0,0)-(1,1,1): corners 0 and 3 of every tet
    d = points[tets[:, 3]] - points[tets[:, 0]]
    np.testing.assert_allclose(np.abs(d), np.broadcast_to(size / divs, d.shape), rtol=1e-12)


@pytest.mark.parametrize("divs", DIVS)
def test_conforming_faces_and_euler_characteristic(divs):
    points, tets = box_tets((1.0, 1.0, 1.0), divs)
    nx, ny, nz = divs
    faces = np.sort(tets[:, TET_FACES].reshape(-1, 3), axis=1)
    _, counts = np.unique(faces, axis=0, return_counts=True)
    assert set(counts.tolist()) <= {1, 2}  # no face shared by three tets
    n_boundary = 4 * (nx * ny + ny * nz + nx * nz)  # two triangles per boundary quad
    assert int((counts == 1).sum()) == n_boundary
    edges = np.unique(np.sort(tets[:, TET10_EDGES].reshape(-1, 2), axis=1), axis=0)
    assert len(points) - len(edges) + len(counts) - len(tets) == 1  # a ball


@pytest.mark.parametrize("divs", DIVS)
def test_promotion_adds_one_midpoint_per_edge(divs):
    points, tets = box_tets((1.0, 2.0, 0.5), divs)
    p10, t10 = promote_tet10(points, tets)
    n_edges = len(np.unique(np.sort(tets[:, TET10_EDGES].reshape(-1, 2), axis=1), axis=0))
    assert p10.shape == (len(points) + n_edges, 3) and t10.shape == (len(tets), 10)
    np.testing.assert_array_equal(p10[: len(points)], points)
    np.testing.assert_array_equal(t10[:, :4], tets)
    mids = 0.5 * (p10[t10[:, TET10_EDGES[:, 0]]] + p10[t10[:, TET10_EDGES[:, 1]]])
    np.testing.assert_array_equal(p10[t10[:, 4:]], mids)
    # every new node is used, and no two share a position (shared edges share the node)
    np.testing.assert_array_equal(np.unique(t10[:, 4:]), np.arange(len(points), len(p10)))
    assert len(np.unique(p10.round(12), axis=0)) == len(p10)


def test_divisions_must_be_positive():
    with pytest.raises(ValueError, match=r"divisions must be >= 1, got \(2, 0, 1\)"):
        box_tets((1.0, 1.0, 1.0), (2, 0, 1))
