"""Local tet numbering: the six Tet10 edges are all corner pairs; the four faces each omit one
corner, point away from it on a positive tet and form a closed, consistently oriented surface."""

from __future__ import annotations

from itertools import combinations

import numpy as np

from flexarm.fe.topology import TET10_EDGES, TET_FACES

CORNERS = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]], dtype=float)


def test_edges_are_the_six_corner_pairs():
    assert sorted(map(tuple, np.sort(TET10_EDGES, axis=1).tolist())) == list(
        combinations(range(4), 2))


def test_faces_point_away_from_the_omitted_corner():
    for face in TET_FACES:
        (omitted,) = set(range(4)) - set(face.tolist())
        a, b, c = CORNERS[face]
        n = np.cross(b - a, c - a)
        assert n @ (a - CORNERS[omitted]) > 0
    p = CORNERS[TET_FACES]
    area_normals = 0.5 * np.cross(p[:, 1] - p[:, 0], p[:, 2] - p[:, 0])
    np.testing.assert_allclose(area_normals.sum(axis=0), 0.0, atol=1e-15)  # closed
    # divergence theorem: the faces enclose the volume 1/6
    assert np.sum(area_normals * p.mean(axis=1)) / 3 == 1 / 6


def test_each_edge_is_used_once_in_each_direction():
    directed = [(f[i], f[(i + 1) % 3]) for f in TET_FACES.tolist() for i in range(3)]
    assert len(set(directed)) == 12
    assert all((b, a) in directed for a, b in directed)
