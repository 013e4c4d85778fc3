"""Craig-Bampton: constraint modes plus fixed-interface normal modes.

One factorisation of the interior stiffness ``K_ii`` serves both the constraint modes
(one multi-RHS solve) and the shift-invert eigen-solve at ``sigma = 0`` (it is passed to
:func:`flexarm.fe.eigen.modes` as ``factor``), so the expensive step happens once.

:func:`craig_bampton_blocks` works on the matrices already split at the boundary
(:class:`BlockSystem`) and projects block by block, so a caller can free the full
matrices before the factor, the largest allocation, is made.
"""

from __future__ import annotations

import logging
import time
from dataclasses import dataclass

import numpy as np
import scipy.sparse as sp

from ..fe.eigen import modes, shift_invert
from ..fe.solvers import Factor, factorize
from .guyan import Reduction, constraint_modes, guyan, split_blocks
from .projection import symmetric

__all__ = ["craig_bampton", "craig_bampton_basis", "craig_bampton_blocks", "BlockSystem",
           "split_system"]

log = logging.getLogger(__name__)


def craig_bampton_basis(Psi: np.ndarray, Phi: np.ndarray) -> np.ndarray:
    """(n_i + n_b, n_b + n_m) basis ``[[Psi, Phi], [I, 0]]`` (boundary DOFs last).

    Reduced coordinates: boundary DOFs first, then modal coordinates.
    """
    n_b, n_m = Psi.shape[1], Phi.shape[1]
    top = np.hstack([Psi, Phi])
    bottom = np.hstack([np.eye(n_b), np.zeros((n_b, n_m))])
    return np.vstack([top, bottom])


@dataclass(frozen=True, eq=False)
class BlockSystem:
    """Stiffness [N/m] and mass [kg] split at the boundary (boundary DOFs last).

    Attributes
    ----------
    K_ii, M_ii : (n_i, n_i) sparse CSR
        Interior blocks.
    K_ib, M_ib : (n_i, n_b) sparse CSR
        Interior-boundary couplings.
    K_bb, M_bb : (n_b, n_b) float
        Boundary blocks (dense: a few DOFs per interface).
    """

    K_ii: sp.csr_matrix
    K_ib: sp.csr_matrix
    K_bb: np.ndarray
    M_ii: sp.csr_matrix
    M_ib: sp.csr_matrix
    M_bb: np.ndarray

    @property
    def n_boundary(self) -> int:
        return int(self.K_bb.shape[0])


def split_system(K, M, n_boundary: int) -> BlockSystem:
    """``K, M`` (boundary DOFs last) as a :class:`BlockSystem`."""
    K_ii, K_ib = split_blocks(K, n_boundary)
    M_ii, M_ib = split_blocks(M, n_boundary)
    n_i = K_ii.shape[0]
    bb = [np.asarray(sp.csr_matrix(A)[n_i:, n_i:].toarray()) for A in (K, M)]
    return BlockSystem(K_ii, K_ib, bb[0], M_ii, M_ib, bb[1])


def _project_blocks(S: BlockSystem, T_i: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """``T^T A T`` for ``A`` = K and M and ``T = [[T_i], [I, 0]]``, block by block."""
    b = S.n_boundary
    out = []
    for A_ii, A_ib, A_bb in ((S.K_ii, S.K_ib, S.K_bb), (S.M_ii, S.M_ib, S.M_bb)):
        A_r = T_i.T @ (A_ii @ T_i)
        C = np.asarray(A_ib.T @ T_i).T  # (r, b): T_i^T A_ib
        A_r[:, :b] += C
        A_r[:b, :] += C.T
        A_r[:b, :b] += A_bb
        out.append(symmetric(A_r))
    return out[0], out[1]


def craig_bampton(K, M, n_boundary: int, n_modes: int, diagonal: bool = False,
                  factor: Factor | None = None, backend: str | None = None,
                  precision: str = "double") -> Reduction:
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
    precision : {"double", "single"}
        Precision of the factor of ``K_ii`` made here: ``"single"`` halves its memory,
        and the constraint modes and shift-invert solves are refined to double accuracy.

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
        return guyan(K, M, n_boundary, factor=factor, backend=backend, precision=precision)
    return craig_bampton_blocks(split_system(K, M, n_boundary), n_modes, diagonal, factor,
                                backend, precision)


def craig_bampton_blocks(S: BlockSystem, n_modes: int, diagonal: bool = False,
                         factor: Factor | None = None, backend: str | None = None,
                         precision: str = "double") -> Reduction:
    """:func:`craig_bampton` (``n_modes >= 1``) of a system already split at the boundary.

    Examples
    --------
    >>> K = sp.csr_matrix([[2.0, -1.0], [-1.0, 1.0]]); M = sp.identity(2, format="csr")
    >>> craig_bampton_blocks(split_system(K, M, 1), 1, backend="splu").K  # Guyan, then omega^2
    array([[0.5, 0. ],
           [0. , 2. ]])
    """
    t0 = time.perf_counter()
    n_boundary = S.n_boundary
    K_ii, K_ib, M_ii = S.K_ii, S.K_ib, S.M_ii
    n_i = K_ii.shape[0]
    if n_modes > n_i:
        raise ValueError(f"asked for {n_modes} fixed-interface modes but there are only "
                         f"{n_i} interior DOFs")
    factor = factor or factorize(K_ii, backend=backend, precision=precision)
    t1 = time.perf_counter()
    Psi = constraint_modes(factor, K_ib)
    t2 = time.perf_counter()
    fixed = modes(K_ii, M_ii, n_modes, eigensolver=shift_invert(0.0), factor=factor)
    t3 = time.perf_counter()
    T = craig_bampton_basis(Psi, fixed.vectors)
    K_r, M_r = _project_blocks(S, T[:n_i])
    if diagonal:
        b = n_boundary
        K_r[b:, b:] = np.diag(fixed.omega2)
        M_r[b:, b:] = np.eye(n_modes)
        K_r[:b, b:] = 0.0
        K_r[b:, :b] = 0.0
    t4 = time.perf_counter()
    log.info("Craig-Bampton: %d -> %d + %d DOF in %.2f s", n_i + n_boundary, n_boundary,
             n_modes, t4 - t0)
    return Reduction(K_r, M_r, T, n_boundary, fixed.omega2, {
        "factorise": t1 - t0, "constraint_modes": t2 - t1, "eigen": t3 - t2,
        "projection": t4 - t3})
