"""Dirichlet conditions by DOF elimination (no penalty numbers)."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import scipy.sparse as sp

__all__ = ["DofSplit", "node_dofs", "dof_split"]


def node_dofs(nodes, components=(0, 1, 2)) -> np.ndarray:
    """(k * len(components),) int: global DOFs ``3*node + c`` of ``nodes``, sorted.

    Examples
    --------
    >>> node_dofs([0, 2], components=(0, 2))
    array([0, 2, 6, 8])
    """
    nodes = np.asarray(nodes, dtype=np.int64).ravel()
    comps = np.asarray(components, dtype=np.int64)
    return np.unique((3 * nodes[:, None] + comps[None, :]).ravel())


@dataclass(frozen=True, eq=False)
class DofSplit:
    """Partition of ``n`` DOFs into free and fixed ones.

    Attributes
    ----------
    n : int
    free, fixed : (k,) int, sorted, disjoint, together ``range(n)``.
    """

    n: int
    free: np.ndarray
    fixed: np.ndarray

    def condense(self, A: sp.spmatrix) -> sp.csr_matrix:
        """The free-free block ``A[free][:, free]`` (CSR)."""
        A = sp.csr_matrix(A)
        return A[self.free][:, self.free].tocsr()

    def coupling(self, A: sp.spmatrix) -> sp.csr_matrix:
        """The free-fixed block ``A[free][:, fixed]`` (for prescribed displacements)."""
        return sp.csr_matrix(A)[self.free][:, self.fixed].tocsr()

    def expand(self, u_free: np.ndarray, u_fixed=0.0) -> np.ndarray:
        """Full vector(s) (n,) or (n, k) from free values and prescribed fixed values."""
        u_free = np.asarray(u_free)
        shape = (self.n,) + u_free.shape[1:]
        u = np.zeros(shape, dtype=np.result_type(u_free, float))
        u[self.free] = u_free
        u[self.fixed] = u_fixed
        return u


def dof_split(n_dofs: int, fixed_dofs) -> DofSplit:
    """Split ``range(n_dofs)`` into free and fixed DOFs.

    Examples
    --------
    >>> s = dof_split(6, [0, 1, 2])
    >>> s.free
    array([3, 4, 5])
    """
    fixed = np.unique(np.asarray(fixed_dofs, dtype=np.int64).ravel())
    if fixed.size and (fixed[0] < 0 or fixed[-1] >= n_dofs):
        raise ValueError(f"fixed DOFs must lie in [0, {n_dofs}), got {fixed[0]}..{fixed[-1]}")
    mask = np.ones(n_dofs, dtype=bool)
    mask[fixed] = False
    return DofSplit(n_dofs, np.flatnonzero(mask), fixed)
