"""MKL PARDISO through ctypes: the factorisation behind the ``pardiso`` backend, and its
analysis phase alone (the factor's fill before any numerical work).

The library is the one pypardiso ships with (``mkl_rt``), loaded once per process; the
matrix goes in as the 1-based upper triangle PARDISO's symmetric types read.
"""

from __future__ import annotations

import ctypes
import functools
import os
import time
from dataclasses import dataclass

import numpy as np
import scipy.sparse as sp

from .errors import FlexarmError, SingularMatrixError, require

__all__ = ["FactorSize", "factor_size", "pardiso_factor"]


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
    require("pypardiso", "the factor-size analysis")
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



# ------------------------------------------------------------------ MKL binding
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
        require("pypardiso", "the PARDISO backend")
        from pypardiso import PyPardisoSolver

        lib = PyPardisoSolver().libmkl
    fn = lib.pardiso
    i32p = ctypes.POINTER(ctypes.c_int32)
    fn.argtypes = [ctypes.POINTER(ctypes.c_int64)] + [i32p] * 5 + [ctypes.c_void_p] + [i32p] * 5 \
        + [i32p, ctypes.c_void_p, ctypes.c_void_p, i32p]
    fn.restype = None
    return fn


def pardiso_factor(A: sp.csr_matrix, spd: bool, single: bool = False):
    """Factorise ``A`` with MKL PARDISO; return ``solve(b)`` for (n,) or (n, k) arrays
    and the factor's memory [bytes] as PARDISO reports it.

    ``single``: the factor (and the right-hand sides PARDISO sees) in float32, as
    ``iparm[27] = 1`` asks; ``solve`` still takes and returns float64.  MKL's memory for
    the factor is released when ``solve`` is garbage-collected.
    """
    require("pypardiso", "the PARDISO backend")
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
