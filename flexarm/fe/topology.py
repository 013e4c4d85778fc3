"""Local node numbering of the tetrahedron (VTK order), shared by meshes and elements."""

from __future__ import annotations

import numpy as np

__all__ = ["TET10_EDGES", "TET_FACES", "outer_faces", "single_rows"]

#: Local corner pairs of the six Tet10 mid-edge nodes 4..9 (VTK order).
TET10_EDGES = np.array([[0, 1], [1, 2], [0, 2], [0, 3], [1, 3], [2, 3]], dtype=np.int64)
#: Local corner triples of the four faces, each oriented outward for a positive tet.
TET_FACES = np.array([[0, 2, 1], [0, 1, 3], [1, 2, 3], [0, 3, 2]], dtype=np.int64)


def single_rows(cells, n_nodes: int) -> np.ndarray:
    """(f,) bool: which rows of ``cells`` (f, k) hold a set of nodes no other row holds.

    Faces of tetrahedra owned by one element are the boundary; edges of triangles used
    once are the rim of a hole.  The node order within a row does not matter.  Each
    sorted row is packed into one int64 (base ``n_nodes``) where that fits, and equal
    keys are found after one sort: some 50 times faster than ``np.unique(..., axis=0)``,
    which compares rows as raw bytes.

    Examples
    --------
    >>> single_rows([[0, 1, 2], [2, 1, 0], [1, 2, 3]], 4).tolist()
    [False, False, True]
    """
    rows = np.sort(np.asarray(cells, dtype=np.int64), axis=1)
    f, k = rows.shape
    if not f:
        return np.zeros(0, dtype=bool)
    if float(max(n_nodes, 2)) ** k < 2.0 ** 62:
        key = rows[:, 0].copy()
        for j in range(1, k):
            key = key * n_nodes + rows[:, j]
        order = np.argsort(key, kind="stable")
        same = key[order][1:] == key[order][:-1]
    else:  # too many nodes to pack a row into one integer
        order = np.lexsort(rows.T[::-1])
        same = (rows[order][1:] == rows[order][:-1]).all(axis=1)
    shared = np.zeros(f, dtype=bool)
    shared[1:] |= same
    shared[:-1] |= same
    single = np.empty(f, dtype=bool)
    single[order] = ~shared
    return single


def outer_faces(points, faces) -> np.ndarray:
    """(k,) bool: which of the outward-oriented boundary ``faces`` (f, 3) lie on an outer
    skin, not on the wall of an inner cavity.

    The boundary of a solid splits into closed surfaces that share no node.  Oriented
    outward from the solid, an outer skin encloses positive volume (divergence theorem:
    V = sum over faces of p0 . (p1 x p2) / 6), and the wall of a cavity encloses
    negative volume: its normals point into the hole.

    Examples
    --------
    >>> import trimesh
    >>> outer, inner = trimesh.creation.box((2, 2, 2)), trimesh.creation.box((1, 1, 1))
    >>> points = np.vstack([outer.vertices, inner.vertices])
    >>> faces = np.vstack([outer.faces, inner.faces[:, ::-1] + 8])   # the cavity's wall
    >>> outer_faces(points, faces).reshape(2, 12).all(axis=1).tolist()
    [True, False]
    """
    import scipy.sparse as sp
    from scipy.sparse.csgraph import connected_components

    P = np.asarray(points, dtype=float)
    F = np.asarray(faces, dtype=np.int64)
    if not len(F):
        return np.zeros(0, dtype=bool)
    incidence = sp.csr_matrix((np.ones(F.size), (np.repeat(np.arange(len(F)), 3), F.ravel())),
                              shape=(len(F), len(P)))
    n, label = connected_components(incidence @ incidence.T, directed=False)
    if n == 1:
        return np.ones(len(F), dtype=bool)
    # about the centroid: the volume of a closed surface does not depend on the origin,
    # and the terms stay small
    Q = P - P[np.unique(F)].mean(axis=0)
    six_v = np.einsum("ij,ij->i", Q[F[:, 0]], np.cross(Q[F[:, 1]], Q[F[:, 2]]))
    return np.bincount(label, six_v, minlength=n)[label] > 0
