"""Structured tetrahedral boxes and Tet4 -> Tet10 promotion (vectorised)."""

from __future__ import annotations

from itertools import permutations

import numpy as np

from .topology import TET10_EDGES

__all__ = ["box_tets", "promote_tet10"]


def box_tets(size, divisions, origin=(0.0, 0.0, 0.0)) -> tuple[np.ndarray, np.ndarray]:
    """Points and positively oriented Tet4 connectivity of a structured box.

    Every hexahedron is cut into the 6 Kuhn tetrahedra along its (0,0,0)-(1,1,1)
    diagonal; the split is conforming because all cells use the same diagonal.

    Returns
    -------
    points : (n, 3) float
        [m]
    tets : (6*nx*ny*nz, 4) int
    """
    nx, ny, nz = (int(d) for d in divisions)
    if min(nx, ny, nz) < 1:
        raise ValueError(f"divisions must be >= 1, got {divisions}")
    lx, ly, lz = (float(s) for s in size)
    xs = np.linspace(0.0, lx, nx + 1) + origin[0]
    ys = np.linspace(0.0, ly, ny + 1) + origin[1]
    zs = np.linspace(0.0, lz, nz + 1) + origin[2]
    X, Y, Z = np.meshgrid(xs, ys, zs, indexing="ij")
    points = np.column_stack([X.ravel(), Y.ravel(), Z.ravel()])

    def nid(i, j, k):
        return (i * (ny + 1) + j) * (nz + 1) + k

    i, j, k = np.meshgrid(np.arange(nx), np.arange(ny), np.arange(nz), indexing="ij")
    i, j, k = i.ravel(), j.ravel(), k.ravel()
    unit = np.eye(3, dtype=np.int64)
    tets = []
    for perm in permutations(range(3)):
        path = [np.zeros(3, dtype=np.int64)]
        for axis in perm:
            path.append(path[-1] + unit[axis])
        tets.append(np.column_stack([nid(i + p[0], j + p[1], k + p[2]) for p in path]))
    tets = np.stack(tets, axis=1).reshape(-1, 4)
    d = points[tets[:, 1:]] - points[tets[:, :1]]
    neg = np.einsum("ij,ij->i", d[:, 0], np.cross(d[:, 1], d[:, 2])) < 0
    tets[neg] = tets[neg][:, [0, 2, 1, 3]]
    return points, tets


def promote_tet10(points: np.ndarray, tets: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Add one straight mid-edge node per unique edge (VTK Tet10 order).

    Parameters
    ----------
    points : (n, 3) float
    tets : (m, 4) int

    Returns
    -------
    points : (n + n_edges, 3) float
        Original points first, then edge midpoints.
    tets : (m, 10) int
    """
    tets = np.asarray(tets, dtype=np.int64)
    edges = np.sort(tets[:, TET10_EDGES].reshape(-1, 2), axis=1)
    uniq, inverse = np.unique(edges, axis=0, return_inverse=True)
    mids = 0.5 * (points[uniq[:, 0]] + points[uniq[:, 1]])
    new_points = np.vstack([points, mids])
    mid_ids = len(points) + inverse.reshape(-1, 6)
    return new_points, np.hstack([tets, mid_ids])
