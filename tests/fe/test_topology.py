"""Local tet numbering: the six Tet10 edges are all corner pairs; the four faces each omit one
corner, point away from it on a positive tet and form a closed, consistently oriented surface."""

from __future__ import annotations

from itertools import combinations

import numpy as np

import pytest

from flexarm.fe.structured import box_tets
from flexarm.fe.topology import TET10_EDGES, TET_FACES, single_rows

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


def _unique_once(rows):
    """The reference: rows whose sorted node set occurs once, by NumPy's row-wise unique."""
    _, inverse, counts = np.unique(np.sort(rows, axis=1), axis=0, return_inverse=True,
                                   return_counts=True)
    return counts[inverse.ravel()] == 1


@pytest.mark.parametrize("seed", range(10))
@pytest.mark.parametrize("k", [2, 3])
def test_single_rows_equals_numpys_row_unique(seed, k):
    rows = np.random.default_rng(seed).integers(0, 12, (300, k))
    assert np.array_equal(single_rows(rows, 12), _unique_once(rows))


def test_single_rows_past_the_packed_key_and_on_a_box_boundary():
    """A node count too large to pack a face into one int64 takes the lexsort path; both
    find the boundary triangles of a structured 2x2x2 box: 6 sides of 2x2 squares, two
    triangles each."""
    points, tets = box_tets((1.0, 1.0, 1.0), (2, 2, 2))
    faces = tets[:, TET_FACES].reshape(-1, 3)
    packed, lexsorted = single_rows(faces, len(points)), single_rows(faces, 2 ** 40)
    assert np.array_equal(packed, lexsorted) and np.array_equal(packed, _unique_once(faces))
    assert packed.sum() == 6 * 2 * 2 * 2     # 6 sides, 2x2 squares, 2 triangles each
    assert single_rows(np.zeros((0, 3), int), 5).shape == (0,)
