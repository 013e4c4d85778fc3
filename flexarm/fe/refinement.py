"""Double-precision solves through a single-precision factor (mixed-precision refinement).

A single-precision factor of a matrix ``A`` holds half the bytes of the double one and
moves half the bytes per solve, but its solution is only accurate to about
``cond(A) * 6e-8``.  Classical iterative refinement recovers double accuracy: the
residual ``r = b - A x`` is computed in double with the double ``A`` (a sparse product,
cheap next to a solve), and the correction ``A^-1 r`` comes from the single factor.  Each
step multiplies the error by about ``cond(A) * eps_single``; stiffness matrices of
meshed links (``cond`` 1e6-1e9) need two to four steps.  Columns stop separately, when
their normwise backward error ``||r|| / (||A|| ||x|| + ||b||)`` (infinity norms) reaches
:attr:`~flexarm.fe.tolerances.Tolerances.refinement` or stops falling (rounding level).
When it does not fall below :attr:`~flexarm.fe.tolerances.Tolerances.refinement_fail` the
single factor is too inaccurate for the matrix and :class:`RefinementError` says so.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

import numpy as np
import scipy.sparse as sp

from .errors import FlexarmError
from .tolerances import tol

__all__ = ["RefinementError", "RefinementStats", "refined_solver", "backward_error"]

#: Most refinement steps per solve; a factor this poor is rejected anyway.
MAX_STEPS = 30
#: A step that does not shrink the backward error by this factor has reached rounding.
STAGNATION = 0.5


class RefinementError(FlexarmError):
    """Iterative refinement through the single-precision factor did not converge."""


@dataclass(eq=False)
class RefinementStats:
    """Counters of the refined solves of one factor (mutable, updated by every solve).

    Attributes
    ----------
    solves : int
        Right-hand-side columns solved.
    corrections : int
        Extra single-precision column solves spent on refinement.
    worst_error : float
        Largest final backward error of any column.
    """

    solves: int = 0
    corrections: int = 0
    worst_error: float = 0.0

    @property
    def steps_per_solve(self) -> float:
        """Mean refinement steps per column (0 when the first solve was enough)."""
        return self.corrections / max(self.solves, 1)


def backward_error(A, x: np.ndarray, b: np.ndarray, norm_A: float | None = None) -> np.ndarray:
    """Normwise backward error of each column of ``x`` as a solution of ``A x = b``.

    ``||b - A x|| / (||A|| ||x|| + ||b||)`` in the infinity norm.

    >>> A = sp.diags([2.0, 4.0]).tocsr()
    >>> float(backward_error(A, np.array([1.0, 1.0]), np.array([2.0, 4.0])))
    0.0
    >>> float(backward_error(A, np.array([1.0, 1.5]), np.array([2.0, 4.0])))  # 2 / (4 * 1.5 + 4)
    0.2
    """
    norm_A = _norm_inf(A) if norm_A is None else norm_A
    r = b - A @ x
    return _colmax(r) / (norm_A * _colmax(x) + _colmax(b))


def _norm_inf(A) -> float:
    return float(abs(A).sum(axis=1).max())


def _colmax(a: np.ndarray) -> np.ndarray:
    return np.abs(a).max(axis=0)


def refined_solver(A: sp.csr_matrix, solve_low: Callable[[np.ndarray], np.ndarray],
                   stats: RefinementStats | None = None):
    """``solve(b)`` for (n,) or (n, k) ``b``: double accuracy from a low-precision solve.

    Parameters
    ----------
    A : (n, n) sparse, float64
        The matrix in double precision (kept by reference for the residuals).
    solve_low : callable
        ``solve_low(b) -> x`` with the single-precision factor; takes and returns float64.
    stats : RefinementStats, optional
        Counters to update (a fresh one otherwise); the solver's ``.stats`` attribute.

    Examples
    --------
    >>> A = sp.diags([[-1.0] * 9, [4.0] * 10, [-1.0] * 9], [-1, 0, 1]).tocsr()
    >>> lu = sp.linalg.splu(A.astype(np.float32).tocsc())
    >>> solve = refined_solver(A, lambda b: lu.solve(b.astype(np.float32)).astype(float))
    >>> b = np.arange(10.0)
    >>> float(backward_error(A, solve(b), b)) < 1e-15
    True
    """
    stats = stats or RefinementStats()
    norm_A = _norm_inf(A)

    def solve(b: np.ndarray) -> np.ndarray:
        one = b.ndim == 1
        B = b[:, None] if one else b
        X = np.asarray(solve_low(B), dtype=np.float64).reshape(B.shape)
        scale_b = _colmax(B)
        err = np.full(B.shape[1], np.inf)
        active = np.arange(B.shape[1])
        steps = 0
        while active.size:
            Xa = X[:, active]
            R = B[:, active] - A @ Xa
            denom = norm_A * _colmax(Xa) + scale_b[active]
            new = _colmax(R) / np.where(denom > 0.0, denom, 1.0)  # b = 0 gives x = 0
            # stop a column once accurate, or once a step no longer helps (rounding)
            done = (new <= tol.refinement) | (new > STAGNATION * err[active])
            err[active] = np.minimum(new, err[active])
            keep = ~done
            if not keep.any() or steps >= MAX_STEPS:
                break
            active, R = active[keep], R[:, keep]
            X[:, active] += np.asarray(solve_low(R), dtype=np.float64).reshape(R.shape)
            stats.corrections += int(active.size)
            steps += 1
        stats.solves += B.shape[1]
        worst = float(err.max()) if err.size else 0.0
        stats.worst_error = max(stats.worst_error, worst)
        if worst > tol.refinement_fail:
            raise RefinementError(
                f"single-precision factor too inaccurate for this matrix: refinement stalled "
                f"at backward error {worst:.2g} after {steps} steps (the matrix is nearly "
                "singular for single precision); use double precision")
        return X[:, 0] if one else X

    solve.stats = stats
    return solve
