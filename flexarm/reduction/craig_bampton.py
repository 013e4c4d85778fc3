"""Craig-Bampton: constraint modes plus fixed-interface normal modes.

One factorisation of the interior stiffness ``K_ii`` serves both the constraint modes
(one multi-RHS solve) and the shift-invert eigen-solve at ``sigma = 0`` (it is passed to
:func:`flexarm.fe.eigen.modes` as ``factor``), so the expensive step happens once.
"""

from __future__ import annotations

import logging
import time

import numpy as np

from ..fe.eigen import modes, shift_invert
from ..fe.solvers import Factor, factorize
from .guyan import Reduction, constraint_modes, guyan, split_blocks
from .projection import project

__all__ = ["craig_bampton", "craig_bampton_basis"]

log = logging.getLogger(__name__)


def craig_bampton_basis(Psi: np.ndarray, Phi: np.ndarray) -> np.ndarray:
    """(n_i + n_b, n_b + n_m) basis ``[[Psi, Phi], [I, 0]]`` (boundary DOFs last).

    Reduced coordinates: boundary DOFs first, then modal coordinates.
    """
    n_b, n_m = Psi.shape[1], Phi.shape[1]
    top = np.hstack([Psi, Phi])
    bottom = np.hstack([np.eye(n_b), np.zeros((n_b, n_m))])
    return np.vstack([top, bottom])


def craig_bampton(K, M, n_boundary: int, n_modes: int, diagonal: bool = False,
                  factor: Factor | None = None, backend: str | None = None) -> Reduction:
    """Craig-Bampton reduction onto the last ``n_boundary`` DOFs plus ``n_modes`` modes.

    Parameters
    ----------
    K, M : (n, n) sparse
        Stiffness and mass with the boundary DOFs last.
    n_boundary : int
    n_modes : int
        Fixed-interface normal modes kept (0 gives Guyan).
    diagonal : bool
        Return the modal block exactly as multibody codes expect: ``M_qq = I``,
        ``K_qq = diag(omega^2)`` and ``K_bq = 0`` (true in exact arithmetic for
        mass-normalised modes; here the round-off is removed explicitly).
    factor : Factor, optional
        Factor of ``K_ii`` to reuse.

    Examples
    --------
    >>> import scipy.sparse as sp
    >>> K = sp.csr_matrix([[2.0, -1.0], [-1.0, 1.0]]); M = sp.identity(2, format="csr")
    >>> r = craig_bampton(K, M, 1, 1, backend="splu")
    >>> r.omega2, r.K.shape
    (array([2.]), (2, 2))
    """
    if n_modes < 0:
        raise ValueError(f"number of modes must be >= 0, got {n_modes}")
    if n_modes == 0:
        return guyan(K, M, n_boundary, factor=factor, backend=backend)
    t0 = time.perf_counter()
    K_ii, K_ib = split_blocks(K, n_boundary)
    M_ii = split_blocks(M, n_boundary)[0]
    n_i = K_ii.shape[0]
    if n_modes > n_i:
        raise ValueError(f"asked for {n_modes} fixed-interface modes but there are only "
                         f"{n_i} interior DOFs")
    factor = factor or factorize(K_ii, backend=backend)
    t1 = time.perf_counter()
    Psi = constraint_modes(factor, K_ib)
    t2 = time.perf_counter()
    fixed = modes(K_ii, M_ii, n_modes, eigensolver=shift_invert(0.0), factor=factor)
    t3 = time.perf_counter()
    T = craig_bampton_basis(Psi, fixed.vectors)
    K_r, M_r = project(K, M, T)
    if diagonal:
        b = n_boundary
        K_r[b:, b:] = np.diag(fixed.omega2)
        M_r[b:, b:] = np.eye(n_modes)
        K_r[:b, b:] = 0.0
        K_r[b:, :b] = 0.0
    t4 = time.perf_counter()
    log.info("Craig-Bampton: %d -> %d + %d DOF in %.2f s", K.shape[0], n_boundary, n_modes,
             t4 - t0)
    return Reduction(K_r, M_r, T, n_boundary, fixed.omega2, {
        "factorise": t1 - t0, "constraint_modes": t2 - t1, "eigen": t3 - t2,
        "projection": t4 - t3})
