"""The one projection step every reduction shares (like pyMOR's ``project``)."""

from __future__ import annotations

import logging
import time

import numpy as np
import scipy.sparse as sp

from ..fe.typing import FloatArray

__all__ = ["project", "symmetric"]

log = logging.getLogger(__name__)


def symmetric(A: FloatArray) -> FloatArray:
    """``(A + A^T) / 2``: removes round-off asymmetry of a projected matrix."""
    return 0.5 * (A + A.T)


def project(K, M, T) -> tuple[FloatArray, FloatArray]:
    """Galerkin projection ``(T^T K T, T^T M T)`` as dense symmetric matrices.

    Parameters
    ----------
    K, M : (n, n) sparse or dense
        Stiffness [N/m] and mass [kg] in the full coordinates.
    T : (n, r) dense or sparse
        Reduction basis: full DOFs from reduced ones.

    Returns
    -------
    K_r, M_r : (r, r) float
        Exactly symmetric.

    Examples
    --------
    >>> K = sp.diags([2.0, 2.0]).tocsr(); M = sp.identity(2, format="csr")
    >>> project(K, M, np.array([[1.0], [1.0]]))[0]
    array([[4.]])
    """
    t0 = time.perf_counter()
    Td = T.toarray() if sp.issparse(T) else np.asarray(T, dtype=float)
    K_r = symmetric(np.asarray(Td.T @ (K @ Td)))
    M_r = symmetric(np.asarray(Td.T @ (M @ Td)))
    log.info("projected %d -> %d DOF in %.2f s", T.shape[0], T.shape[1], time.perf_counter() - t0)
    return K_r, M_r
