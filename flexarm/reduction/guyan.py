"""Guyan (static) condensation onto the boundary DOFs."""

from __future__ import annotations

import logging
import time
from dataclasses import dataclass, field

import numpy as np
import scipy.sparse as sp

from ..fe.solvers import Factor, factorize
from ..fe.typing import FloatArray
from .projection import project

__all__ = ["Reduction", "split_blocks", "constraint_modes", "guyan_basis", "guyan"]

log = logging.getLogger(__name__)


@dataclass(frozen=True, eq=False)
class Reduction:
    """Reduced matrices of a model whose boundary DOFs come last.

    Attributes
    ----------
    K, M : (r, r) float
        Reduced stiffness and mass; DOFs = boundary DOFs, then modal coordinates.
    T : (n, r) float
        Basis in the input coordinates (``u = T q``).
    n_boundary : int
    omega2 : (n_modes,) float
        Fixed-interface eigenvalues [rad^2/s^2] (empty for Guyan).
    seconds : dict of str to float
        Wall time per step.
    """

    K: FloatArray
    M: FloatArray
    T: FloatArray
    n_boundary: int
    omega2: FloatArray = field(default_factory=lambda: np.zeros(0))
    seconds: dict = field(default_factory=dict)

    @property
    def n_modes(self) -> int:
        return int(self.omega2.size)

    @property
    def freq_hz(self) -> FloatArray:
        """(n_modes,) fixed-interface frequencies [Hz]."""
        return np.sqrt(np.clip(self.omega2, 0.0, None)) / (2 * np.pi)


def split_blocks(A, n_boundary: int):
    """Interior-interior and interior-boundary blocks (CSR) of ``A`` (boundary last)."""
    A = sp.csr_matrix(A)
    n_i = A.shape[0] - n_boundary
    return A[:n_i, :n_i].tocsr(), A[:n_i, n_i:].tocsr()


def constraint_modes(factor: Factor, K_ib) -> FloatArray:
    """(n_i, n_b) interior response to unit boundary motions: ``-K_ii^-1 K_ib``.

    One multi-right-hand-side solve with the factor of ``K_ii``.
    """
    rhs = K_ib.toarray() if sp.issparse(K_ib) else np.asarray(K_ib)
    return -factor.solve(rhs)


def guyan_basis(Psi: FloatArray) -> FloatArray:
    """(n_i + n_b, n_b) Guyan basis ``[Psi; I]`` (boundary last)."""
    return np.vstack([Psi, np.eye(Psi.shape[1])])


def guyan(K, M, n_boundary: int, factor: Factor | None = None,
          backend: str | None = None, precision: str = "double") -> Reduction:
    """Static condensation onto the last ``n_boundary`` DOFs.

    Parameters
    ----------
    K, M : (n, n) sparse
        Stiffness and mass with the boundary (master) DOFs last.
    n_boundary : int
    factor : Factor, optional
        Factor of the interior block ``K_ii`` to reuse.
    precision : {"double", "single"}
        Precision of the factor made here (``"single"``: half the memory, solves
        refined to double accuracy).

    Examples
    --------
    >>> K = sp.csr_matrix([[2.0, -1.0], [-1.0, 1.0]]); M = sp.identity(2, format="csr")
    >>> guyan(K, M, 1, backend="splu").K  # two unit springs in series
    array([[0.5]])
    """
    t0 = time.perf_counter()
    K_ii, K_ib = split_blocks(K, n_boundary)
    factor = factor or factorize(K_ii, backend=backend, precision=precision)
    t1 = time.perf_counter()
    Psi = constraint_modes(factor, K_ib)
    t2 = time.perf_counter()
    T = guyan_basis(Psi)
    K_r, M_r = project(K, M, T)
    t3 = time.perf_counter()
    log.info("Guyan: %d -> %d DOF in %.2f s", K.shape[0], n_boundary, t3 - t0)
    return Reduction(K_r, M_r, T, n_boundary, np.zeros(0), {
        "factorise": t1 - t0, "constraint_modes": t2 - t1, "projection": t3 - t2})
