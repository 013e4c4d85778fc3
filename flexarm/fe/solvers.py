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

import ctypes
import functools
import logging
import os
import time
from dataclasses import dataclass

import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as spla

from .errors import FlexarmError, MissingDependencyError
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


class SingularMatrixError(FlexarmError):
    """The matrix is singular (for a stiffness: the part is not fully supported)."""


def _has(module: str) -> bool:
    import importlib.util

    return importlib.util.find_spec(module) is not None


def available_backends() -> list[str]:
    """Backends importable on this machine, fastest first."""
    out = []
    if _has("pypardiso"):
        out.append("pardiso")
    if _has("sksparse"):
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
        solve, memory = _pardiso(A, spd, single)
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


@dataclass(frozen=True)
class FactorSize:
    """What a Cholesky-type factor of a matrix will take, from the analysis phase only.

    Attributes
    ----------
    n : int
        Size of the matrix.
    factor_entries : int
        Values PARDISO stores for the factor ``L``: its fill plus the upper halves of
        the dense diagonal blocks of its supernodes (what the memory holds).
    peak_bytes : int
        PARDISO's peak memory for factorisation and solves [bytes]: the larger of the
        analysis peak and the permanent plus numerical-phase memory.
    seconds : float
        Wall time of the analysis [s].
    """

    n: int
    factor_entries: int
    peak_bytes: int
    seconds: float


def factor_size(A) -> FactorSize:
    """Fill of the factor of the symmetric positive definite pattern of ``A``.

    Runs PARDISO's analysis phase alone (METIS ordering and symbolic factorisation, the
    same settings as the ``pardiso`` backend): seconds where the numerical
    factorisation takes minutes, and nothing of the factor is allocated.  Only the
    sparsity pattern of ``A`` matters.

    Examples
    --------
    >>> grid = sp.diags([-1.0, 4.0, -1.0], [-1, 0, 1], shape=(50, 50)).tocsr()
    >>> fs = factor_size(grid)  # a chain: no fill beyond the band
    >>> fs.n, 99 <= fs.factor_entries < 50 * 51 // 2  # at least L's band, far below dense
    (50, True)
    """
    if not _has("pypardiso"):
        raise MissingDependencyError("pypardiso", "the factor-size analysis")
    t0 = time.perf_counter()
    A = sp.csr_matrix(A, dtype=np.float64)
    ia, ja, _ = _pardiso_upper(A)
    # Values do not enter the analysis; a diagonally dominant fill keeps PARDISO's
    # checks quiet.
    data = np.where(ja - 1 == np.repeat(np.arange(A.shape[0]), np.diff(ia)), 1e3, -1.0)
    pt = np.zeros(64, dtype=np.int64)
    iparm = _pardiso_iparm(True)
    iparm[17] = -1  # report the factor's entries
    call = _pardiso_caller(_mkl_pardiso(), 2, True, A.shape[0],
                           (pt, iparm, np.zeros(0, dtype=np.int32), data, ia, ja))
    call(11, None)
    entries, kb = int(iparm[17]), max(int(iparm[14]), int(iparm[15]) + int(iparm[16]))
    call(-1, None)
    return FactorSize(A.shape[0], entries, 1024 * kb, time.perf_counter() - t0)


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


@functools.lru_cache(maxsize=1)
def _mkl_pardiso():
    """MKL's ``pardiso`` entry point, loaded once per process.

    pypardiso locates ``mkl_rt`` anew in every ``PyPardisoSolver()`` (a recursive glob
    over ``sys.prefix``: ~0.7 s each here) and builds one such solver when imported
    (~1 s).  We ask the ``mkl`` distribution's file list first (milliseconds), honour
    ``PYPARDISO_MKL_RT`` like pypardiso, and fall back to pypardiso's own search.
    """
    path = os.environ.get("PYPARDISO_MKL_RT")
    if path is None:
        import importlib.metadata as md

        try:
            found = [f for f in md.files("mkl") or () if f.name.startswith("libmkl_rt")
                     or f.name.startswith("mkl_rt")]
            path = str(found[0].locate().resolve()) if found else None
        except md.PackageNotFoundError:
            path = None
    lib = None
    if path is not None:
        try:
            lib = ctypes.CDLL(path)
        except OSError:
            lib = None
    if lib is None:
        if not _has("pypardiso"):
            raise MissingDependencyError("pypardiso", "the PARDISO backend")
        from pypardiso import PyPardisoSolver

        lib = PyPardisoSolver().libmkl
    fn = lib.pardiso
    i32p = ctypes.POINTER(ctypes.c_int32)
    fn.argtypes = [ctypes.POINTER(ctypes.c_int64)] + [i32p] * 5 + [ctypes.c_void_p] + [i32p] * 5 \
        + [i32p, ctypes.c_void_p, ctypes.c_void_p, i32p]
    fn.restype = None
    return fn


def _pardiso(A: sp.csr_matrix, spd: bool, single: bool = False):
    """Factorise ``A`` with MKL PARDISO; return ``solve(b)`` for (n,) or (n, k) arrays
    and the factor's memory [bytes] as PARDISO reports it.

    ``single``: the factor (and the right-hand sides PARDISO sees) in float32, as
    ``iparm[27] = 1`` asks; ``solve`` still takes and returns float64.  MKL's memory for
    the factor is released when ``solve`` is garbage-collected.
    """
    if not _has("pypardiso"):
        raise MissingDependencyError("pypardiso", "the PARDISO backend")
    pardiso = _mkl_pardiso()
    ia, ja, data = _pardiso_upper(A)
    mtype = 2 if spd else -2  # PARDISO matrix types: real SPD, real symmetric indefinite
    pt = np.zeros(64, dtype=np.int64)  # PARDISO's opaque handle (64-bit pointers)
    iparm = _pardiso_iparm(spd)
    if single:
        iparm[27] = 1  # single precision: matrix, right-hand sides and factor in float32
        data = data.astype(np.float32)
    perm = np.zeros(0, dtype=np.int32)
    call = _pardiso_caller(pardiso, mtype, spd, A.shape[0], (pt, iparm, perm, data, ia, ja))
    call(12, None)  # analysis + numerical factorisation
    if spd and iparm[29] > 0:  # number of zero or negative pivots
        raise SingularMatrixError("matrix is not positive definite: is the part fully supported?")
    memory = 1024 * (int(iparm[15]) + int(iparm[16]))  # permanent + numerical phase [KB]

    def solve(b: np.ndarray) -> np.ndarray:
        x = call(33, b)
        return x.astype(np.float64) if single else x

    # Keep the handle alive as long as the solve closure lives; release MKL memory after.
    import weakref

    def release(arrays=(pt, iparm, perm, data, ia, ja)):  # keep them alive until then
        try:
            call(-1, None)
        except Exception:  # noqa: BLE001 - best effort at interpreter shutdown
            pass

    weakref.finalize(solve, release)
    return solve, memory


def _pardiso_upper(A: sp.csr_matrix) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The upper triangle of ``A`` as PARDISO's CSR arrays ``(ia, ja, data)``.

    Symmetric matrix types read the upper triangle only, as 1-based int32 CSR with sorted
    columns.
    """
    U = sp.triu(A, format="csr")
    U.sort_indices()
    if np.any(np.diff(U.indptr) == 0):
        raise SingularMatrixError("matrix has an empty row (a DOF with no stiffness)")
    ia = (U.indptr + 1).astype(np.int32)
    ja = (U.indices + 1).astype(np.int32)
    return ia, ja, np.ascontiguousarray(U.data)


def _pardiso_iparm(spd: bool) -> np.ndarray:
    """PARDISO's ``iparm`` (64,) int32 for a positive definite or an indefinite matrix."""
    iparm = np.zeros(64, dtype=np.int32)
    iparm[0] = 1  # user-set parameters below, defaults elsewhere
    # METIS nested dissection.  Minimum degree (iparm[1] = 0) analyses faster but fills
    # more; measured (CPU s, analysis + numeric): 66k-DOF Tet4 link 0.89 vs 0.91 METIS,
    # L 13.0M vs 11.9M entries; 410k-DOF Tet10 link 28.6 vs 19.6 METIS, L 205M vs 161M,
    # 342 vs 185 GFlop.  No gain on the small matrix, a loss on the large one, and the
    # larger L slows every solve of an eigen-solve: METIS for all sizes.
    iparm[1] = 2
    iparm[9] = 13 if not spd else 8  # pivot perturbation 1e-13 / 1e-8
    iparm[10] = 0 if spd else 1  # scaling only for indefinite
    iparm[12] = 0 if spd else 1  # matching only for indefinite
    iparm[34] = 0  # 1-based indices
    return iparm


def _pardiso_caller(pardiso, mtype: int, spd: bool, n: int, arrays: tuple):
    """``call(phase, b)``: one PARDISO call on the factor held by ``arrays``.

    ``arrays`` is ``(pt, iparm, perm, data, ia, ja)``; ``b`` is None for phases without
    a right-hand side.  Returns the solution (C-contiguous), or raises
    :class:`SingularMatrixError` / :class:`FlexarmError` on PARDISO's error codes.
    """
    pt, iparm, perm, data, ia, ja = arrays

    def call(phase: int, b: np.ndarray | None):
        nrhs = 1 if b is None or b.ndim == 1 else b.shape[1]
        rhs = np.zeros(n, dtype=data.dtype) if b is None else np.asfortranarray(b, data.dtype)
        x = np.zeros_like(rhs)
        err = ctypes.c_int32(0)
        i32p = ctypes.POINTER(ctypes.c_int32)
        one = ctypes.byref(ctypes.c_int32(1))
        pardiso(
            pt.ctypes.data_as(ctypes.POINTER(ctypes.c_int64)),
            one,  # maxfct
            one,  # mnum
            ctypes.byref(ctypes.c_int32(mtype)),
            ctypes.byref(ctypes.c_int32(phase)),
            ctypes.byref(ctypes.c_int32(n)),
            data.ctypes.data,
            ia.ctypes.data_as(i32p),
            ja.ctypes.data_as(i32p),
            perm.ctypes.data_as(i32p),
            ctypes.byref(ctypes.c_int32(nrhs)),
            iparm.ctypes.data_as(i32p),
            ctypes.byref(ctypes.c_int32(0)),  # msglvl
            rhs.ctypes.data,
            x.ctypes.data,
            ctypes.byref(err),
        )
        if err.value == -4 or (spd and err.value == -3):
            raise SingularMatrixError(
                "matrix is singular or not positive definite (PARDISO zero pivot): "
                "is the part fully supported?"
            )
        if err.value != 0:
            raise FlexarmError(f"PARDISO failed with error code {err.value}")
        return np.ascontiguousarray(x)

    return call
