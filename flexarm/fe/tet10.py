"""Quadratic tetrahedron (Tet10, VTK node order): reference shape functions."""

from __future__ import annotations

import numpy as np

from .topology import TET10_EDGES

__all__ = ["Tet10"]

# Gradient of the barycentric coordinates (L0 = 1 - x - y - z, L1 = x, L2 = y, L3 = z).
_DL = np.array([[-1.0, -1.0, -1.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]])


def _barycentric(xi: np.ndarray) -> np.ndarray:
    xi = np.atleast_2d(xi)
    return np.column_stack([1.0 - xi.sum(axis=1), xi])


class Tet10:
    """Ten-node tetrahedron: corners L_i (2 L_i - 1), mid-edges 4 L_a L_b.

    Examples
    --------
    >>> N = Tet10.shape(np.array([[0.2, 0.3, 0.1]]))
    >>> round(float(N.sum()), 15)  # partition of unity
    1.0
    """

    n_nodes = 10
    #: curved (non-affine) elements: grad N ~ degree 1 over det J ~ degree 2 -> cubic
    curved_stiffness_degree = 3
    stiffness_degree = 2
    mass_degree = 4

    @staticmethod
    def shape(xi: np.ndarray) -> np.ndarray:
        """(q, 10) shape functions at reference points ``xi`` (q, 3)."""
        L = _barycentric(xi)
        corners = L * (2.0 * L - 1.0)
        mids = 4.0 * L[:, TET10_EDGES[:, 0]] * L[:, TET10_EDGES[:, 1]]
        return np.hstack([corners, mids])

    @staticmethod
    def shape_grad(xi: np.ndarray) -> np.ndarray:
        """(q, 10, 3) reference gradients dN_a/dxi_j."""
        L = _barycentric(xi)
        corners = (4.0 * L - 1.0)[:, :, None] * _DL[None]
        a, b = TET10_EDGES[:, 0], TET10_EDGES[:, 1]
        mids = 4.0 * (L[:, a, None] * _DL[None, b] + L[:, b, None] * _DL[None, a])
        return np.concatenate([corners, mids], axis=1)
