"""Load vectors: body force (gravity) and nodal forces [N]."""

from __future__ import annotations

import numpy as np
import scipy.sparse as sp

__all__ = ["gravity_load", "nodal_load", "STANDARD_GRAVITY"]

#: Standard gravity [m/s^2], pointing along -z of the base frame.
STANDARD_GRAVITY = np.array([0.0, 0.0, -9.80665])


def gravity_load(M: sp.spmatrix, g=STANDARD_GRAVITY) -> np.ndarray:
    """(3n,) consistent body-force vector ``M @ g`` [N] for acceleration ``g`` [m/s^2].

    Examples
    --------
    >>> from flexarm.fe.mesh import TetMesh
    >>> from flexarm.fe.assembly import mass_matrix
    >>> M = mass_matrix(TetMesh.box(divisions=(1, 1, 1), order=2), rho=1000.0)
    >>> round(float(gravity_load(M).reshape(-1, 3)[:, 2].sum()), 6)  # -m g
    -9806.65
    """
    g = np.asarray(g, dtype=float)
    if g.shape != (3,):
        raise ValueError(f"gravity must be a (3,) vector, got shape {g.shape}")
    return M @ np.tile(g, M.shape[0] // 3)


def nodal_load(n_nodes: int, nodes, force, distribute: bool = True) -> np.ndarray:
    """(3n,) vector with ``force`` (3,) [N] on ``nodes``.

    With ``distribute`` the force is the total, split equally over the nodes;
    otherwise every node gets ``force``.
    """
    nodes = np.asarray(nodes, dtype=np.int64).ravel()
    if nodes.size == 0:
        raise ValueError("nodal_load got an empty node selection")
    force = np.asarray(force, dtype=float)
    if force.shape != (3,):
        raise ValueError(f"force must be a (3,) vector, got shape {force.shape}")
    f = np.zeros((n_nodes, 3))
    np.add.at(f, nodes, force / len(nodes) if distribute else force)
    return f.ravel()
