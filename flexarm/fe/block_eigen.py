"""Thick-restart block Lanczos in shift-invert mode for ``K x = lam M x``.

The ``n`` eigenpairs nearest a shift ``sigma`` from one factorisation of
``K - sigma M``, built as a Krylov-Schur method:

* operator ``OP = (K - sigma M)^{-1} M``, self-adjoint in the M-inner product, with
  eigenvalues ``theta = 1 / (lam - sigma)``; the wanted pairs are the largest |theta|
  (those nearest the shift), as ARPACK's ``which="LM"``;
* the Krylov space grows a block of ``p`` vectors at a time (one ``p``-column solve),
  with full M-reorthogonalisation: the block's large components along the previous two
  blocks first, then one block Gram-Schmidt pass over the whole basis, then an
  eigenvalue-based orthonormalisation of the block;
* the projected matrix ``H = V^T M OP V`` is assembled from the projection
  coefficients (not only the three-term recurrence), so its Ritz residuals
  ``||B s_last||_M`` are true residuals of the computed operator;
* Rayleigh-Ritz on ``H`` after every block; a pair has converged when its residual is
  below ``tol * |theta|`` (ARPACK's test) or below the rounding level of ``H``;
* thick restart when the basis is full: the best Ritz vectors are kept with their
  coupling to the next block; converged pairs are locked (kept, no longer iterated), so
  the huge |theta| of the rigid modes of a free part does not limit its elastic ones.

Why blocks, and why the default block is still 1: a p-column PARDISO solve costs much
less than p single solves (20 columns: ~0.25-0.35 of 20 single solves), which is what
made block methods attractive.  But on the 66k-DOF benchmark link the blocks needed to
reach machine precision hardly fall as the block widens, so the total solve work is
about the same for p = 1..8 and the orthogonalisation grows with the basis; see
:func:`default_block_size` and ``benchmarks/README.md``.  With p = 1 this is a
thick-restart Lanczos that needs fewer solves than ARPACK (54 against 64 for 20 modes
of that link) and less vector work.

The start block comes from a seeded generator, so a given matrix pair and parameters
give bit-identical results.
"""

from __future__ import annotations

import logging
from dataclasses import dataclass

import numpy as np

from .errors import ConvergenceError

__all__ = ["BlockLanczosInfo", "block_shift_invert", "default_block_size", "default_basis_size"]

log = logging.getLogger(__name__)

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
#: Lock converged pairs early when the largest active |theta| exceeds a wanted pair's by
#: more than this: H's rounding (eps * max |theta|) would otherwise limit that pair.
_LOCK_SPREAD = 1e3
#: Residual floor as a fraction of the largest active |theta| (see the convergence test).
_FLOOR = _EPS
#: Residuals that have not halved in this many Ritz steps have stalled at the solves'
#: rounding level; they are accepted if below _STALL_CAP * max |theta| (sqrt(eps): the
#: eigenvalues are then still exact to rounding, the residual being squared in them).
_STALL = 4
_STALL_CAP = np.sqrt(_EPS)


@dataclass(frozen=True)
class BlockLanczosInfo:
    """What one block solve did (for logging and benchmarks).

    Attributes
    ----------
    block_size, basis_size : int
        Vectors per block ``p`` and the largest basis ``m`` before a restart.
    n_solves : int
        Right-hand sides solved (columns, not calls).
    n_blocks : int
        Multi-right-hand-side solve calls.
    restarts : int
        Thick restarts.
    """

    block_size: int
    basis_size: int
    n_solves: int
    n_blocks: int
    restarts: int


def default_block_size(n: int) -> int:
    """Vectors per block for ``n`` wanted modes: 1.

    Measured on the 66k-DOF clamped link (20 modes to machine precision, PARDISO): the
    number of blocks needed hardly falls as the block widens (54 solves with p = 1, 74
    with 2, 108 with 4, 144 with 6), while a p-column solve costs 0.82 / 0.52 / 0.47 p
    single solves; with the orthogonalisation included p = 1 is the fastest (CPU 1.6 s
    against 2.5 s for p = 2 and 4, and 2.3 s for ARPACK).  Wider blocks remain useful
    for eigenvalues of known multiplicity above 1 (pass ``block_size``).
    """
    return 1


def default_basis_size(n: int, p: int) -> int:
    """Largest basis before a thick restart: room for ``n`` wanted vectors, the same
    again as a buffer that speeds convergence (at least 20, like SciPy's ``ncv``), and
    two blocks."""
    return int(max(2 * n, n + 2 * p, 20) + 2 * p)


def _keep(n: int, m: int, p: int) -> int:
    """Ritz vectors kept at a thick restart: the n wanted plus half the remaining room (as
    ARPACK's implicit restart does), always leaving room for at least one block."""
    return min(max(n, (m + n) // 2 - p // 2), m - p)


def _sym(A: np.ndarray) -> np.ndarray:
    return 0.5 * (A + A.T)


def _project_out(W: np.ndarray, V: np.ndarray, MV: np.ndarray) -> np.ndarray:
    """Remove span(V) from W in place by one block classical Gram-Schmidt pass (two
    matrix products); return the coefficients C with W_in = V C + W_out."""
    C = MV.T @ W
    W -= V @ C
    return C


def _orthonormal_block(W: np.ndarray, MW: np.ndarray, ref: float, V, MV, M, rng):
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
        s, U = np.linalg.eigh(_sym(Q.T @ MQ))
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
            _project_out(Q, V, MV)
            _project_out(Q, V, MV)
        MQ = M @ Q
        ref = 1.0
    raise ConvergenceError("block Lanczos: could not M-orthonormalise a block (is M positive "
                           "definite on the free DOFs?)")


def block_shift_invert(M, n: int, solve, sigma: float, *, block_size: int | None = None,
                       basis_size: int | None = None, tol: float = 0.0, max_restarts: int = 300,
                       seed: int = 0):
    """The ``n`` eigenpairs of ``K x = lam M x`` nearest ``sigma`` [rad^2/s^2].

    Parameters
    ----------
    M : (N, N) sparse
        Mass [kg] (``M @ X`` is all that is used; K enters through ``solve``).
    n : int
        Number of wanted eigenpairs.
    solve : callable
        ``solve(B) -> (K - sigma M)^{-1} B`` for an (N, p) array (a :class:`Factor`'s
        ``solve``); called once per block.
    sigma : float
        Shift [rad^2/s^2] that ``solve`` factorised.
    block_size, basis_size : int, optional
        Vectors per block ``p`` and the largest basis ``m`` (defaults:
        :func:`default_block_size`, :func:`default_basis_size`).
    tol : float
        Relative accuracy of the shift-inverted eigenvalues: a Ritz pair is converged
        when its residual ``||OP x - theta x||_M <= tol * |theta|`` (ARPACK's test);
        0 means machine precision.  The residual is also accepted below the rounding
        level of H, ``eps * max |theta|`` over the pairs not yet locked, and, where the
        solves are noisier than that, when it has stopped falling below
        ``sqrt(eps) * max |theta|``.
    max_restarts : int
        Thick restarts before giving up with :class:`ConvergenceError`.
    seed : int
        Seed of the start block (fixed: results are reproducible bit for bit).

    Returns
    -------
    lam : (n,) float
        Eigenvalues [rad^2/s^2], nearest the shift first.
    X : (N, n) float
        M-orthonormal eigenvectors.
    info : BlockLanczosInfo
    """
    size = M.shape[0]
    if not 1 <= n <= size:
        raise ValueError(f"number of modes must be in 1..{size}, got {n}")
    p = int(block_size or default_block_size(n))
    m = int(basis_size or default_basis_size(n, p))
    p = max(1, min(p, size))
    m = min(max(m, n + p), size)
    tol = max(float(tol), _EPS)
    keep = _keep(n, m, p) if m < size else m

    rng = np.random.default_rng(seed)
    V = np.empty((size, m), order="F")  # [locked | active basis | newest block]
    MV = np.empty((size, m), order="F")
    H = np.zeros((m, m))  # V^T M OP V on the active columns
    # start block: OP applied to a random block, M-orthonormalised.  Like ARPACK's
    # generalised mode, this puts it in the range of OP, so a singular M (massless DOFs)
    # cannot leave a component the M-inner product does not see.
    W = np.asfortranarray(solve(np.asfortranarray(M @ rng.standard_normal((size, p)))))
    MW = M @ W
    Q, MQ = _orthonormal_block(W, MW, float(np.sqrt(np.einsum("ij,ij->j", W, MW)).max()),
                               V[:, :0], MV[:, :0], M, rng)
    V[:, :p], MV[:, :p] = Q, MQ
    nl = 0  # locked (converged) eigenvectors V[:, :nl], eigenvalues theta_l
    theta_l = np.zeros(0)
    k = 0  # columns of V whose OP-image is in H (the basis is V[:, :k + pb])
    pb = p  # width of the newest block V[:, k:k + pb]
    prev = 0  # start of the block before it (nl after a restart: the kept Ritz vectors)
    n_solves, n_blocks, restarts = p, 1, 0
    history: list[float] = []  # worst relative residual of the unconverged wanted pairs
    while True:
        # ---- expand: W = OP V_new, coefficients against the whole basis
        kb = k + pb
        W = np.asfortranarray(solve(np.asfortranarray(MV[:, k:kb])))
        n_solves += pb
        n_blocks += 1
        # In exact arithmetic W couples only to the newest and the previous block (block
        # Lanczos' three-term recurrence; after a restart, to the kept Ritz vectors):
        # remove those large components first, then one pass over the whole basis takes
        # out the rounding-level rest, which keeps the basis orthogonal to machine
        # precision with two passes over V instead of the four of plain CGS2.
        C = np.zeros((kb, pb))
        C[prev:kb] = _project_out(W, V[:, prev:kb], MV[:, prev:kb])
        C += _project_out(W, V[:, :kb], MV[:, :kb])
        # components along locked eigenvectors are at their residual level: dropped
        H[nl:kb, k:kb] = C[nl:]
        grow = min(p, size - kb)  # the next block (narrower only when the space runs out)
        if grow > 0:
            MW = M @ W
            Wq, MWq = W, MW
            if grow < pb:  # keep the largest directions of what is left
                _, U = np.linalg.eigh(_sym(W.T @ MW))
                Wq, MWq = W @ U[:, -grow:], MW @ U[:, -grow:]
            ref = float(np.sqrt((C * C).sum(axis=0) + np.einsum("ij,ij->j", W, MW)).max())
            Q, MQ = _orthonormal_block(Wq, MWq, ref, V[:, :kb], MV[:, :kb], M, rng)
            # the coupling by projection, so that OP V = V H + Q B holds to rounding
            # however ill-conditioned W was
            B = MQ.T @ W
        else:
            B = np.zeros((0, pb))
        # ---- Rayleigh-Ritz on the active part of the projected matrix
        theta, S = np.linalg.eigh(_sym(H[nl:kb, nl:kb]))
        order = np.argsort(-np.abs(theta), kind="stable")
        theta, S = theta[order], S[:, order]
        if grow > 0:
            resid = np.linalg.norm(B @ S[k - nl:kb - nl, :], axis=0)
        else:  # the basis spans the whole space: the Ritz pairs are exact
            resid = np.zeros(theta.size)
        # ARPACK's test resid <= tol |theta_i|, floored at _FLOOR * max |theta| over
        # the active pairs: these residuals are true projections (they include the
        # rounding of the solves), which settle near that level instead of falling on
        # like ARPACK's recurrence-based estimates.
        big = np.abs(theta[0])
        rel = resid / np.maximum(np.abs(theta), np.finfo(np.float64).tiny)
        conv = resid <= np.maximum(tol * np.abs(theta), _FLOOR * big)
        # the wanted pairs: the n largest |theta| among locked and active
        wanted = np.argsort(-np.abs(np.concatenate([theta_l, theta])), kind="stable")[:n]
        wa = wanted[wanted >= nl] - nl
        # A pair whose |theta| is far below the largest active one is limited by that
        # floor (the rigid modes of a free part against its elastic ones): it is only
        # accepted once the large pairs are locked, which lowers the floor.
        resolved = np.abs(theta) * _LOCK_SPREAD >= big
        # Where the solves are noisier than that floor (a nearly singular K - sigma M),
        # the residuals stall: accept them once the worst wanted one has not halved in
        # _STALL Ritz steps, if it is below the cap.
        todo = wa[~conv[wa]]
        history.append(float(rel[todo].max()) if todo.size else 0.0)
        if (todo.size and len(history) > _STALL and history[-1] > 0.5 * history[-1 - _STALL]
                and np.all(resid[todo] <= _STALL_CAP * big)):
            log.debug("block Lanczos: residuals stall at %.1e relative, accepted", history[-1])
            conv[todo] = True
        lockable = wa[conv[wa] & resolved[wa]]
        if conv[wa].all():
            if resolved[wa].all() or grow == 0:  # (a full space: the pairs are exact)
                break
            lock_now = True
        elif kb + grow <= m:  # room left: append the new block
            V[:, kb:kb + grow], MV[:, kb:kb + grow] = Q, MQ
            H[kb:kb + grow, k:kb] = B
            prev, k, pb = k, kb, grow
            continue
        else:
            lock_now = False
        if not lock_now and restarts >= max_restarts:
            wl = wanted[wanted < nl]
            X = np.hstack([V[:, wl], V[:, nl:kb] @ S[:, lockable]])
            done = np.concatenate([theta_l[wl], theta[lockable]])
            raise ConvergenceError(
                f"block shift-invert Lanczos converged {done.size} of {n} modes after "
                f"{restarts} restarts ({n_solves} solves, block {p}, basis {m}); "
                "try a shift nearer the wanted modes or a larger basis (ncv)",
                sigma + 1.0 / done, X,
            )
        # ---- thick restart: lock the converged wanted pairs, keep the best other
        # Ritz vectors with their coupling to Q, and grow again from Q
        restarts += 1
        new_lock = lockable
        rest = np.setdiff1d(np.arange(theta.size), new_lock)
        rest = rest[np.argsort(-np.abs(theta[rest]), kind="stable")]
        n_active = min(rest.size, max(keep - nl - new_lock.size, np.setdiff1d(wa, new_lock).size))
        rest = rest[:n_active]
        if nl + new_lock.size + n_active + grow > m:
            raise ConvergenceError(f"block shift-invert Lanczos: basis {m} too small for {n} "
                                   "modes; give a larger basis (ncv)")
        cols = np.concatenate([new_lock, rest])
        Y = V[:, nl:kb] @ S[:, cols]
        MY = MV[:, nl:kb] @ S[:, cols]
        nk = cols.size
        V[:, nl:nl + nk], MV[:, nl:nl + nk] = Y, MY
        theta_l = np.concatenate([theta_l, theta[new_lock]])
        nl += new_lock.size
        ka = nl + n_active  # end of the kept active Ritz vectors
        H[:] = 0.0
        H[nl:ka, nl:ka] = np.diag(theta[rest])
        coupling = B @ S[k - (nl - new_lock.size):kb - (nl - new_lock.size), rest]
        H[ka:ka + grow, nl:ka] = coupling  # residual block of the kept vectors
        H[nl:ka, ka:ka + grow] = coupling.T
        V[:, ka:ka + grow], MV[:, ka:ka + grow] = Q, MQ
        prev, k, pb = nl, ka, grow
    # (a locked pair can drop out of the wanted set when copies of a multiple
    # eigenvalue nearer the shift appear late)
    wl = wanted[wanted < nl]
    X = np.hstack([V[:, wl], V[:, nl:kb] @ S[:, wa]])
    theta_w = np.concatenate([theta_l[wl], theta[wa]])
    small = np.abs(theta_w) * _LOCK_SPREAD < np.abs(theta_w).max()
    if small.any():
        # With a spread of |theta| (free part: rigid ~1/|sigma|, elastic ~1/lam) the
        # small theta from H carry the rounding of the large ones (measured on the free
        # Tet10 bar: 8e-10 relative, ARPACK's 6e-11), while the vectors are accurate.
        # One more solve on them and a Rayleigh-Ritz step gives theta to ~1e-12.
        Xs = X[:, small]
        Y = solve(np.asfortranarray(M @ Xs))
        n_solves += Xs.shape[1]
        n_blocks += 1
        t, U = np.linalg.eigh(_sym(Xs.T @ (M @ Y)))
        X[:, small], theta_w[small] = Xs @ U, t
    # locked and active wanted pairs, nearest the shift first
    order = np.argsort(-np.abs(theta_w), kind="stable")
    info = BlockLanczosInfo(p, m, n_solves, n_blocks, restarts)
    log.debug("block Lanczos: %s", info)
    return sigma + 1.0 / theta_w[order], X[:, order], info
