"""Generalised symmetric eigenproblem K phi = omega^2 M phi and static solves.

Eigensolvers are configured callables passed in (as scikit-fem passes
``solver_eigen_scipy_sym``): ``modes(K, M, n=20, eigensolver=shift_invert(0.0))``.
"""

from __future__ import annotations

import logging
import time
from dataclasses import dataclass

import numpy as np
import scipy.linalg as sla
import scipy.sparse as sp
import scipy.sparse.linalg as spla

from .block_eigen import block_shift_invert
from .boundary import DofSplit
from .errors import ConvergenceError
from .solvers import Factor, factorize
from .threads import one_blas_thread
from .tolerances import tol

__all__ = ["Modes", "modes", "shift_invert", "auto_shift", "stiffness_scale", "static_solve"]

log = logging.getLogger(__name__)

#: Below this many DOFs a dense solve is faster and exact.
DENSE_LIMIT = 400


@dataclass(frozen=True, eq=False)
class Modes:
    """Eigenpairs sorted by frequency.

    Attributes
    ----------
    omega2 : (k,) float
        Eigenvalues omega^2 [rad^2/s^2] (tiny negatives for rigid modes are kept).
    vectors : (n, k) float
        Mass-normalised mode shapes (phi^T M phi = I), signed so that their projection
        on a fixed pseudo-random vector is positive: reproducible across backends.
    shift : float
        The spectral shift used [rad^2/s^2].
    scale : float
        Stiffness scale median(K_ii / M_ii) [rad^2/s^2]; rigid modes are those with
        ``|omega^2|`` below ``tol.rigid_mode * scale`` (independent of the shift chosen).
    """

    omega2: np.ndarray
    vectors: np.ndarray
    shift: float = 0.0
    scale: float = 0.0

    @property
    def omega(self) -> np.ndarray:
        """(k,) angular frequencies [rad/s] (0 for rigid modes)."""
        return np.sqrt(np.clip(self.omega2, 0.0, None))

    @property
    def freq_hz(self) -> np.ndarray:
        """(k,) frequencies [Hz]."""
        return self.omega / (2 * np.pi)

    @property
    def is_rigid(self) -> np.ndarray:
        """(k,) bool: near-zero modes (rigid-body motions of an unsupported part)."""
        return np.abs(self.omega2) < tol.rigid_mode * self.scale

    @property
    def n_rigid(self) -> int:
        return int(self.is_rigid.sum())

    def __len__(self) -> int:
        return int(self.omega2.size)

    def __repr__(self) -> str:
        """One line: mode count, rigid modes, elastic frequency range [Hz], shape size.

        Examples
        --------
        >>> Modes(np.array([0.0, (2 * np.pi * 10) ** 2, (2 * np.pi * 25) ** 2]),
        ...       np.zeros((12, 3)), scale=1e6)
        Modes(3 modes, 1 rigid, elastic 10–25 Hz, shapes 12 DOF)
        """
        from .notebook import span

        elastic = self.freq_hz[~self.is_rigid]
        return (f"Modes({len(self)} modes, {self.n_rigid} rigid, elastic "
                f"{span(elastic, 'Hz')}, shapes {self.vectors.shape[0]} DOF)")

    def to_dataframe(self):
        """``pandas.DataFrame``, one row per mode: ``mode`` (from 1), ``f_Hz``,
        ``omega2_rad2_per_s2`` (the eigenvalue) and ``rigid`` (bool).

        Examples
        --------
        >>> m = Modes(np.array([0.0, (2 * np.pi * 10) ** 2]), np.zeros((6, 2)), scale=1e6)
        >>> m.to_dataframe()["f_Hz"].round(6).tolist()
        [0.0, 10.0]
        """
        from .notebook import data_frame

        return data_frame({"mode": np.arange(1, len(self) + 1), "f_Hz": self.freq_hz,
                           "omega2_rad2_per_s2": self.omega2, "rigid": self.is_rigid})


def stiffness_scale(K: sp.spmatrix, M: sp.spmatrix) -> float:
    """median(K_ii / M_ii) [rad^2/s^2]: the squared angular frequency of one element."""
    kd, md = K.diagonal(), M.diagonal()
    return float(np.median(kd[md > 0] / md[md > 0]))


def auto_shift(K: sp.spmatrix, M: sp.spmatrix) -> float:
    """A small negative shift [rad^2/s^2] that makes ``K - shift M`` definite.

    ``-tol.auto_shift * median(K_ii / M_ii)``: far below the first elastic mode of any
    reasonable mesh, so the ordering of the modes nearest the shift is the ordering of
    the lowest modes, rigid ones included.
    """
    return -tol.auto_shift * stiffness_scale(K, M)


def _normalise(omega2, vecs, M):
    order = np.argsort(omega2, kind="stable")
    omega2, vecs = omega2[order], vecs[:, order]
    mnorm = np.sqrt(np.einsum("ik,ik->k", vecs, M @ vecs))
    vecs = vecs / mnorm
    # The largest component often ties on symmetric parts; a projection on a fixed
    # random vector does not, so every backend gives the same signs.
    probe = np.random.default_rng(12345).standard_normal(vecs.shape[0])
    signs = np.sign(probe @ vecs)
    return omega2, vecs * np.where(signs == 0, 1.0, signs)


#: Eigensolver methods of :func:`shift_invert`.
METHODS = ("block", "arpack")


def _check_residuals(K, M, w, v, limit: float) -> None:
    """Raise :class:`ConvergenceError` unless every pair solves ``K x = lam M x``.

    The test is the normwise backward error ``||K x - lam M x|| / ((||K|| + |lam| ||M||)
    ||x||)`` (Frobenius norms): machine precision (~1e-16) for a converged pair whatever
    the conditioning, while ``||K x - lam M x|| / ||K x||`` of the same pair is ~eps times
    omega_max^2 / omega^2 (1e-10..1e-8 on a link).  It catches what the Krylov estimates
    cannot see, such as a ``factor`` of some other matrix than ``K - sigma M``.
    """
    R = K @ v - (M @ v) * w
    norm_k, norm_m = np.linalg.norm(K.data), np.linalg.norm(M.data)
    scale = (norm_k + np.abs(w) * norm_m) * np.linalg.norm(v, axis=0)
    eta = np.linalg.norm(R, axis=0) / np.maximum(scale, np.finfo(np.float64).tiny)
    bad = np.flatnonzero(~(eta <= limit))
    if bad.size:
        raise ConvergenceError(
            f"eigen-solve: {bad.size} of {w.size} modes fail the residual check (backward "
            f"error up to {eta[bad].max():.1e} > {limit:.1e}); does the factor belong to "
            "K - sigma M?", w, v)


def shift_invert(sigma: float | None = None, backend: str | None = None, ncv: int | None = None,
                 method: str = "block", block_size: int | None = None,
                 precision: str = "double"):
    """Eigensolver: shift-invert around ``sigma`` [rad^2/s^2], the modes nearest it.

    ``sigma=None`` uses :func:`auto_shift` (safe for free parts).  The returned callable
    ``solve(K, M, n, factor=None) -> Modes`` factorises ``K - sigma M`` once with the
    chosen backend, or reuses ``factor`` when given (it must factor ``K - sigma M``).
    The start vectors are fixed, so repeated calls give identical results.

    Parameters
    ----------
    method : {"block", "arpack"}
        ``"block"`` (default): our thick-restart block Lanczos
        (:func:`flexarm.fe.block_eigen.block_shift_invert`), a block of ``block_size``
        right-hand sides per solve; ``"arpack"``: SciPy's ``eigsh`` (ARPACK), one solve
        at a time.  Both converge to machine precision (``tol.arpack = 0``) and pass the
        same residual check.
    ncv : int, optional
        Largest Krylov basis (ARPACK's ``ncv``; the block method's ``basis_size``).
    block_size : int, optional
        Right-hand sides per solve of the block method (default
        :func:`flexarm.fe.block_eigen.default_block_size`).
    precision : {"double", "single"}
        Precision of the factor this solver makes (see :func:`flexarm.fe.solvers.factorize`):
        ``"single"`` halves its memory; every solve is refined to double accuracy, so the
        modes pass the same residual check.
    """
    if method not in METHODS:
        raise ValueError(f"eigen method must be one of {', '.join(METHODS)}, got '{method}'")

    def solve(K, M, n: int, factor: Factor | None = None) -> Modes:
        K = sp.csr_matrix(K)
        M = sp.csr_matrix(M)
        size = K.shape[0]
        s = auto_shift(K, M) if sigma is None else float(sigma)
        if n >= size - 1 or size <= DENSE_LIMIT:
            w, v = sla.eigh(K.toarray(), M.toarray())
            w, v = _normalise(w[:n], v[:, :n], M)
            return Modes(w, v, s, stiffness_scale(K, M))
        t0 = time.perf_counter()
        if factor is None:
            A = (K - s * M) if s != 0.0 else K
            factor = factorize(A, backend=backend, spd=s <= 0.0, precision=precision)
        # The Krylov vector work is BLAS on long vectors or thin blocks: on shared cores
        # threads only contend (ARPACK: 5.6 s -> 0.7 s on 14.6k DOF, 20 modes, 2 cores).
        # MKL, which runs PARDISO's solves, is limited with it (see benchmarks/README.md).
        with one_blas_thread():
            if method == "block":
                w, v, info = block_shift_invert(M, n, factor.solve, s, block_size=block_size,
                                                basis_size=ncv, tol=tol.arpack)
                what = f"block {info.block_size}, {info.n_solves} solves, {info.restarts} restarts"
            else:
                w, v = _arpack(K, M, n, s, factor, ncv)
                what = "ARPACK"
        _check_residuals(K, M, w, v, _RESIDUAL_LIMIT)
        w, v = _normalise(w, v, M)
        log.info("%d modes of %d DOF in %.2f s (%s)", n, size, time.perf_counter() - t0, what)
        return Modes(w, v, s, stiffness_scale(K, M))

    return solve


#: Backward error above which a returned pair is rejected (see ``_check_residuals``):
#: far above what converged pairs show (1e-17..1e-15), far below a wrong one's.
_RESIDUAL_LIMIT = float(np.sqrt(np.finfo(np.float64).eps))


def _arpack(K, M, n: int, s: float, factor: Factor, ncv: int | None):
    """``n`` eigenpairs nearest ``s`` by ARPACK's shift-invert mode (one solve per step)."""
    size = K.shape[0]
    v0 = np.random.default_rng(0).standard_normal(size)
    k_ncv = ncv or min(size - 1, max(2 * n + 1, 20))
    try:
        return spla.eigsh(K, k=n, M=M, sigma=s, which="LM", OPinv=factor.as_operator(),
                          v0=v0, ncv=k_ncv, tol=tol.arpack)
    except spla.ArpackNoConvergence as exc:
        raise ConvergenceError(
            f"ARPACK converged {len(exc.eigenvalues)} of {n} modes",
            exc.eigenvalues, exc.eigenvectors,
        ) from None


def modes(K, M, n: int = 10, eigensolver=None, factor: Factor | None = None) -> Modes:
    """The ``n`` lowest modes of ``K phi = omega^2 M phi``.

    Parameters
    ----------
    K, M : (N, N) sparse
        Stiffness [N/m] and mass [kg] (already reduced to the free DOFs).
    n : int
        Number of modes.
    eigensolver : callable, optional
        ``shift_invert(sigma)`` (default: automatic negative shift).
    factor : Factor, optional
        A factorisation of ``K - sigma M`` to reuse.

    Examples
    --------
    >>> from flexarm.fe.mesh import TetMesh
    >>> from flexarm.fe.assembly import assemble
    >>> from flexarm.fe.material import MATERIALS
    >>> K, M = assemble(TetMesh.box((1, 0.2, 0.2), (4, 1, 1)), MATERIALS["steel"])
    >>> modes(K, M, n=8).n_rigid  # a free part
    6
    """
    if n < 1:
        raise ValueError(f"number of modes must be >= 1, got {n}")
    solver = eigensolver or shift_invert()
    return solver(K, M, n, factor=factor)


def static_solve(K, f, split: DofSplit | None = None, u_fixed=0.0, factor: Factor | None = None,
                 backend: str | None = None) -> np.ndarray:
    """Displacements u (N,) or (N, k) [m] solving ``K u = f`` with DOFs eliminated.

    Parameters
    ----------
    K : (N, N) sparse
    f : (N,) or (N, k) float
        Loads [N].
    split : DofSplit, optional
        Free/fixed partition; fixed DOFs get ``u_fixed`` (scalar or array).
    factor : Factor, optional
        Factor of the free-free block to reuse.
    """
    K = sp.csr_matrix(K)
    f = np.asarray(f, dtype=float)
    if split is None:
        factor = factor or factorize(K, backend=backend)
        return factor.solve(f)
    rhs = f[split.free]
    u_fix = np.broadcast_to(np.asarray(u_fixed, dtype=float), (split.fixed.size,) + f.shape[1:])
    if np.any(u_fix):
        rhs = rhs - split.coupling(K) @ u_fix
    factor = factor or factorize(split.condense(K), backend=backend)
    return split.expand(factor.solve(rhs), u_fix)
