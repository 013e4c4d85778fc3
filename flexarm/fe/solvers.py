"""Sparse direct solver backends behind one small interface.

``factorize(A)`` returns a :class:`Factor` whose ``solve(b)`` serves every right-hand
side (and the shift-invert eigen-solve) that shares ``A``.  Backends:

``pardiso``  Intel MKL PARDISO through pypardiso's library loader (fast default).
``cholmod``  SuiteSparse CHOLMOD through scikit-sparse, when installed.
``splu``     SciPy SuperLU (always available, slow on 3-D meshes).

``precision="single"`` factorises in single precision (PARDISO, SuperLU): half the
factor's memory, with every solve refined to double accuracy against the double matrix
(:mod:`flexarm.fe.refinement`).

The default is the first available of the list, overridable with the environment
variable ``FLEXARM_SOLVER`` or :func:`set_default_backend`.
"""

from __future__ import annotations

import logging
import os
import time
from dataclasses import dataclass

import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as spla

from .errors import MissingDependencyError, SingularMatrixError, has_module
from .pardiso import FactorSize, factor_size, pardiso_factor
from .refinement import RefinementStats, refined_solver
from .tolerances import tol

__all__ = [
    "Factor",
    "factorize",
    "available_backends",
    "default_backend",
    "set_default_backend",
    "SingularMatrixError",
    "FactorSize",
    "factor_size",
    "PRECISIONS",
]

log = logging.getLogger(__name__)

BACKENDS = ("pardiso", "cholmod", "splu")
#: Precisions of the factor: ``single`` is refined to double accuracy on every solve.
PRECISIONS = ("double", "single")
_default: str | None = None


def available_backends() -> list[str]:
    """Backends importable on this machine, fastest first."""
    out = []
    if has_module("pypardiso"):
        out.append("pardiso")
    if has_module("sksparse"):
        out.append("cholmod")
    out.append("splu")
    return out


def set_default_backend(name: str | None) -> None:
    """Choose the backend used when ``factorize`` gets none (``None``: automatic)."""
    global _default
    if name is not None and name not in BACKENDS:
        raise ValueError(f"solver backend must be one of {', '.join(BACKENDS)}, got '{name}'")
    _default = name


def default_backend() -> str:
    """The backend ``factorize`` uses by default."""
    name = _default or os.environ.get("FLEXARM_SOLVER") or available_backends()[0]
    if name not in BACKENDS:
        raise ValueError(f"FLEXARM_SOLVER must be one of {', '.join(BACKENDS)}, got '{name}'")
    return name


@dataclass(eq=False)
class Factor:
    """A factorised square sparse matrix; ``solve`` accepts (n,) or (n, k) arrays.

    Attributes
    ----------
    n : int
        Size of the matrix.
    backend : str
    seconds : float
        Wall time of the factorisation.
    precision : {"double", "single"}
        Precision of the stored factor (solves are double-accurate either way).
    memory_bytes : int or None
        The factor's memory as the backend reports it (PARDISO's permanent plus
        numerical-phase memory) [bytes]; None when the backend does not say.
    refinement : RefinementStats or None
        Refinement counters of a single-precision factor.
    """

    n: int
    backend: str
    seconds: float
    _solve: object
    precision: str = "double"
    memory_bytes: int | None = None
    refinement: RefinementStats | None = None

    def solve(self, b: np.ndarray) -> np.ndarray:
        b = np.asarray(b, dtype=np.float64)
        if b.shape[0] != self.n:
            raise ValueError(f"right-hand side must have {self.n} rows, got shape {b.shape}")
        return self._solve(b)

    def as_operator(self) -> spla.LinearOperator:
        """The inverse as a LinearOperator (for ARPACK's ``OPinv``)."""
        return spla.LinearOperator((self.n, self.n), matvec=self.solve, dtype=np.float64)


def factorize(A, backend: str | None = None, spd: bool = True,
              precision: str = "double") -> Factor:
    """Factorise a symmetric sparse matrix once for many solves.

    Parameters
    ----------
    A : (n, n) sparse
        Symmetric matrix (stiffness, or ``K - sigma M``).
    backend : {"pardiso", "cholmod", "splu"}, optional
        Defaults to :func:`default_backend`.
    spd : bool
        True when ``A`` is positive definite (Cholesky-type factorisation);
        False for indefinite shifted matrices.
    precision : {"double", "single"}
        ``"single"`` stores the factor in single precision (half the memory; PARDISO and
        SuperLU only) and refines every solve to double accuracy with ``A`` itself.

    Examples
    --------
    >>> A = sp.diags([4.0, 5.0, 6.0]).tocsr()
    >>> factorize(A, backend="splu").solve(np.array([4.0, 10.0, 18.0]))
    array([1., 2., 3.])
    >>> factorize(A, backend="splu", precision="single").solve(np.array([4.0, 10.0, 18.0]))
    array([1., 2., 3.])
    """
    backend = backend or default_backend()
    A = sp.csr_matrix(A, dtype=np.float64)
    if A.shape[0] != A.shape[1]:
        raise ValueError(f"matrix must be square, got shape {A.shape}")
    if precision not in PRECISIONS:
        raise ValueError(f"precision must be one of {', '.join(PRECISIONS)}, got '{precision}'")
    single = precision == "single"
    if single and backend not in ("pardiso", "splu"):
        raise ValueError(f"a single-precision factor needs the pardiso or splu backend, "
                         f"got '{backend}'")
    t0 = time.perf_counter()
    memory = None
    if backend == "pardiso":
        solve, memory = pardiso_factor(A, spd, single)
    elif backend == "cholmod":
        solve = _cholmod(A, spd)
    elif backend == "splu":
        solve = _splu(A, spd, single)
    else:
        raise ValueError(f"solver backend must be one of {', '.join(BACKENDS)}, got '{backend}'")
    stats = None
    if single:
        solve = refined_solver(A, solve)
        stats = solve.stats
    dt = time.perf_counter() - t0
    log.info("factorised %d x %d (nnz %d) with %s (%s) in %.2f s", *A.shape, A.nnz, backend,
             precision, dt)
    return Factor(A.shape[0], backend, dt, solve, precision, memory, stats)


# ------------------------------------------------------------------------- backends
def _splu(A: sp.csr_matrix, spd: bool = True, single: bool = False):
    # Symmetric mode: order A + A^T (minimum degree) and pivot on the diagonal, as a
    # Cholesky would.  Without it SuperLU's partial pivoting leaves the symmetric order
    # and the fill explodes: on a 66k-DOF Tet4 link 235 s instead of 2.5 s (COLAMD:
    # 7.7 s).  Indefinite (shifted) matrices keep a threshold so a small diagonal still
    # gets a row exchange.
    try:
        lu = spla.splu(
            A.astype(np.float32 if single else np.float64).tocsc(), permc_spec="MMD_AT_PLUS_A",
            diag_pivot_thresh=0.0 if spd else 0.1,
            options={"SymmetricMode": True},
        )
    except RuntimeError as exc:  # "Factor is exactly singular"
        raise SingularMatrixError(f"matrix is singular ({exc})") from None
    # SuperLU stops only on an exactly zero pivot; a free part's rigid modes leave
    # pivots ~1e-15 of the largest instead.
    pivots = np.abs(lu.U.diagonal())
    if spd and pivots.min() <= tol.singular_pivot * pivots.max():
        raise SingularMatrixError(
            "matrix is singular (a pivot ~0): is the part fully supported?"
        )
    if single:
        return lambda b: lu.solve(np.asarray(b, dtype=np.float32)).astype(np.float64)
    return lu.solve


def _cholmod(A: sp.csr_matrix, spd: bool):
    try:
        from sksparse.cholmod import CholmodNotPositiveDefiniteError, cholesky
    except ImportError:
        raise MissingDependencyError("scikit-sparse", "the CHOLMOD backend") from None
    try:
        f = cholesky(A.tocsc()) if spd else cholesky(A.tocsc(), mode="simplicial")
    except CholmodNotPositiveDefiniteError as exc:
        raise SingularMatrixError(f"matrix is not positive definite ({exc})") from None
    return f
