"""The block Lanczos basis behind :func:`flexarm.fe.block_eigen.block_shift_invert`.

The state of one run (:class:`KrylovState`), its start block, and the expansion by one
block: ``W = OP V_new`` projected against the basis by block classical Gram-Schmidt,
its coefficients stored in the projected matrix ``H``, and what is left orthonormalised
by the eigen-decomposition of its Gram matrix (SVQB), all in the M-inner product.
Directions that vanish to rounding level are replaced by random ones from the run's
seeded generator, so results stay reproducible bit for bit.  The Rayleigh-Ritz steps,
locking and thick restarts that use this basis are in :mod:`flexarm.fe.block_eigen`.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, field

import numpy as np

from .errors import ConvergenceError

__all__ = ["KrylovState", "Expansion", "start", "expand", "append", "sym", "project_out",
           "orthonormal_block"]

_EPS = np.finfo(np.float64).eps
#: A block direction whose M-norm after orthogonalisation is below this fraction of the
#: block's norm before it is rounding noise (the Krylov space is invariant there): it is
#: replaced by a fresh random direction, as ARPACK restarts on an invariant subspace.
_NOISE = 1e3 * _EPS
#: Orthonormalising a block that lost more than this factor of its norm in the projection
#: magnifies its rounding-level components along the basis: project once more.
_REPROJECT = 1e2
#: A block whose Gram matrix has a condition number below this is orthonormalised in one
#: pass (the error is ~eps * cond); otherwise twice, like CholeskyQR2.
_WELL_CONDITIONED = 1e2


def sym(A: np.ndarray) -> np.ndarray:
    """The symmetric part of A (a projected matrix carries rounding asymmetry)."""
    return 0.5 * (A + A.T)


def project_out(W: np.ndarray, V: np.ndarray, MV: np.ndarray) -> np.ndarray:
    """Remove span(V) from W in place by one block classical Gram-Schmidt pass (two
    matrix products); return the coefficients C with W_in = V C + W_out."""
    C = MV.T @ W
    W -= V @ C
    return C


def orthonormal_block(W: np.ndarray, MW: np.ndarray, ref: float, V, MV, M, rng):
    """An M-orthonormal basis Q of span(W), M-orthogonal to V, and ``M @ Q``.

    ``W`` (n, p) is already M-orthogonal to V up to ``eps * ref``, where ``ref`` is its
    largest M-norm before the projection; ``MW = M @ W``.  Orthonormalisation by the
    eigen-decomposition of the Gram matrix (SVQB, Stathopoulos & Wu 2002), repeated until
    the Gram matrix is the identity (two passes as a rule, like CholeskyQR2).  Scaling by
    1/sqrt(s) magnifies the rounding along V by ``ref / sqrt(s_min)``: only then is Q
    projected against V again (one extra pass over the basis).  Directions whose norm
    fell to rounding level (the Krylov space is invariant there) are replaced by random
    ones, as ARPACK restarts on an invariant subspace.
    """
    Q, MQ = W, MW
    for it in range(4):
        s, U = np.linalg.eigh(sym(Q.T @ MQ))
        well_conditioned = s.min() > 0 and (
            np.abs(s - 1.0).max() < 1e-6 if it > 0
            else s.max() < _WELL_CONDITIONED * s.min() and ref / np.sqrt(s.min()) <= _REPROJECT)
        if well_conditioned:
            # one more scaling is accurate to eps * cond: M Q follows linearly (no further
            # product with M) and Q stays M-orthogonal to V.  A single vector (p = 1)
            # always ends here after one pass.
            T = U / np.sqrt(s)
            return np.asfortranarray(Q @ T), np.asfortranarray(MQ @ T)
        noise = s <= (_NOISE * ref) ** 2
        s_ok = np.where(noise, 1.0, s)
        Q = np.asfortranarray(Q @ (U / np.sqrt(s_ok)))
        if np.any(noise):
            Q[:, noise] = rng.standard_normal((Q.shape[0], int(noise.sum())))
        if np.any(noise) or ref / np.sqrt(s_ok.min()) > _REPROJECT:
            project_out(Q, V, MV)
            project_out(Q, V, MV)
        MQ = M @ Q
        ref = 1.0
    raise ConvergenceError("block Lanczos: could not M-orthonormalise a block (is M positive "
                           "definite on the free DOFs?)")


@dataclass(eq=False)
class KrylovState:
    """Mutable state of one thick-restart block Lanczos run.

    Attributes
    ----------
    M : (N, N) sparse
        Mass [kg].
    solve : callable
        ``solve(B) -> (K - sigma M)^{-1} B``.
    rng : numpy.random.Generator
        Seeded source of the start block and of replacement directions.
    p, m : int
        Vectors per block and the largest basis.
    V, MV : (N, m) float, Fortran order
        The basis and ``M V``; ``V[:, :k + pb]`` is ``[locked | active | newest block]``.
    H : (m, m) float
        ``V^T M OP V`` [s^2/rad^2] on the active columns.
    theta_l : (nl,) float
        Eigenvalues ``1 / (lam - sigma)`` [s^2/rad^2] of the locked eigenvectors
        ``V[:, :nl]``.
    pb : int
        Width of the newest block ``V[:, k:k + pb]``.
    nl, k, prev : int
        Locked columns; columns whose OP-image is in H; start of the block before the
        newest (``nl`` after a restart: the kept Ritz vectors).
    n_solves, n_blocks, restarts : int
        Counters of :class:`~flexarm.fe.block_eigen.BlockLanczosInfo`.
    history : list of float
        Worst relative residual of the unconverged wanted pairs, one per Ritz step.
    """

    M: object
    solve: Callable[[np.ndarray], np.ndarray]
    rng: np.random.Generator
    p: int
    m: int
    V: np.ndarray
    MV: np.ndarray
    H: np.ndarray
    theta_l: np.ndarray
    pb: int
    n_solves: int
    nl: int = 0
    k: int = 0
    prev: int = 0
    n_blocks: int = 1
    restarts: int = 0
    history: list[float] = field(default_factory=list)


@dataclass(frozen=True, eq=False)
class Expansion:
    """One block-Lanczos expansion: ``OP V[:, :kb] = V H + Q B`` to rounding.

    Attributes
    ----------
    kb : int
        Columns of V whose OP-image is now in H.
    grow : int
        Width of the next block: ``p``, less where the space runs out, 0 once the basis
        spans it all.
    Q, MQ : (N, grow) float
        The next block, M-orthonormal and M-orthogonal to ``V[:, :kb]``, and ``M Q``.
    B : (grow, pb) float
        Its coupling ``Q^T M OP V_new`` [s^2/rad^2].
    """

    kb: int
    grow: int
    Q: np.ndarray
    MQ: np.ndarray
    B: np.ndarray


def start(M, solve, size: int, p: int, m: int, seed: int) -> KrylovState:
    """The state holding the M-orthonormal start block ``V[:, :p]``."""
    rng = np.random.default_rng(seed)
    V = np.empty((size, m), order="F")
    MV = np.empty((size, m), order="F")
    H = np.zeros((m, m))
    # OP applied to a random block, M-orthonormalised.  Like ARPACK's generalised mode,
    # this puts it in the range of OP, so a singular M (massless DOFs) cannot leave a
    # component the M-inner product does not see.
    W = np.asfortranarray(solve(np.asfortranarray(M @ rng.standard_normal((size, p)))))
    MW = M @ W
    Q, MQ = orthonormal_block(W, MW, float(np.sqrt(np.einsum("ij,ij->j", W, MW)).max()),
                              V[:, :0], MV[:, :0], M, rng)
    V[:, :p], MV[:, :p] = Q, MQ
    return KrylovState(M, solve, rng, p, m, V, MV, H, theta_l=np.zeros(0), pb=p, n_solves=p)


def expand(st: KrylovState) -> Expansion:
    """``W = OP V_new`` with its coefficients against the whole basis put into H, and
    the next block M-orthonormalised from what is left of W."""
    k, kb, nl = st.k, st.k + st.pb, st.nl
    size = st.V.shape[0]
    W = np.asfortranarray(st.solve(np.asfortranarray(st.MV[:, k:kb])))
    st.n_solves += st.pb
    st.n_blocks += 1
    # In exact arithmetic W couples only to the newest and the previous block (block
    # Lanczos' three-term recurrence; after a restart, to the kept Ritz vectors):
    # remove those large components first, then one pass over the whole basis takes
    # out the rounding-level rest, which keeps the basis orthogonal to machine
    # precision with two passes over V instead of the four of plain CGS2.
    C = np.zeros((kb, st.pb))
    C[st.prev:kb] = project_out(W, st.V[:, st.prev:kb], st.MV[:, st.prev:kb])
    C += project_out(W, st.V[:, :kb], st.MV[:, :kb])
    # components along locked eigenvectors are at their residual level: dropped
    st.H[nl:kb, k:kb] = C[nl:]
    grow = min(st.p, size - kb)
    if grow == 0:  # the basis spans the whole space
        empty = np.empty((size, 0), order="F")
        return Expansion(kb, 0, empty, empty, np.zeros((0, st.pb)))
    MW = st.M @ W
    Wq, MWq = W, MW
    if grow < st.pb:  # keep the largest directions of what is left
        _, U = np.linalg.eigh(sym(W.T @ MW))
        Wq, MWq = W @ U[:, -grow:], MW @ U[:, -grow:]
    ref = float(np.sqrt((C * C).sum(axis=0) + np.einsum("ij,ij->j", W, MW)).max())
    Q, MQ = orthonormal_block(Wq, MWq, ref, st.V[:, :kb], st.MV[:, :kb], st.M, st.rng)
    # the coupling by projection, so that OP V = V H + Q B holds to rounding however
    # ill-conditioned W was
    return Expansion(kb, grow, Q, MQ, MQ.T @ W)


def append(st: KrylovState, blk: Expansion) -> None:
    """Grow the basis by the next block (there is room for it)."""
    kb, grow = blk.kb, blk.grow
    st.V[:, kb:kb + grow], st.MV[:, kb:kb + grow] = blk.Q, blk.MQ
    st.H[kb:kb + grow, st.k:kb] = blk.B
    st.prev, st.k, st.pb = st.k, kb, grow
