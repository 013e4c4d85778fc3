"""Linear tetrahedron (Tet4): reference shape functions and their gradients."""

from __future__ import annotations

import numpy as np

__all__ = ["Tet4"]

_DL = np.array([[-1.0, -1.0, -1.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]])


class Tet4:
    """Four-node tetrahedron, barycentric shape functions.

    Examples
    --------
    >>> Tet4.shape(np.array([[0.25, 0.25, 0.25]]))
    array([[0.25, 0.25, 0.25, 0.25]])
    """

    n_nodes = 4
    #: quadrature degree that integrates K and M exactly on straight elements
    #: curved (non-affine) elements: grad N ~ degree 1 over det J ~ degree 2 -> cubic
    curved_stiffness_degree = 1
    stiffness_degree = 1
    mass_degree = 2

    @staticmethod
    def shape(xi: np.ndarray) -> np.ndarray:
        """(q, 4) shape functions at reference points ``xi`` (q, 3)."""
        xi = np.atleast_2d(xi)
        return np.column_stack([1.0 - xi.sum(axis=1), xi])

    @staticmethod
    def shape_grad(xi: np.ndarray) -> np.ndarray:
        """(q, 4, 3) reference gradients dN_a/dxi_j."""
        xi = np.atleast_2d(xi)
        return np.broadcast_to(_DL, (xi.shape[0], 4, 3)).copy()
