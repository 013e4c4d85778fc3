"""Thick-restart block Lanczos in shift-invert mode for ``K x = lam M x``.

The ``n`` eigenpairs nearest a shift ``sigma`` from one factorisation of
``K - sigma M``, built as a Krylov-Schur method:

* operator ``OP = (K - sigma M)^{-1} M``, self-adjoint in the M-inner product, with
  eigenvalues ``theta = 1 / (lam - sigma)``; the wanted pairs are the largest ``|theta|``
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
  the huge ``|theta|`` of the rigid modes of a free part does not limit its elastic ones.

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
from typing import NoReturn

import numpy as np

from .block_lanczos import Expansion, KrylovState, append, expand, start, sym
from .errors import ConvergenceError

__all__ = ["BlockLanczosInfo", "block_shift_invert", "default_block_size", "default_basis_size"]

log = logging.getLogger(__name__)

_EPS = np.finfo(np.float64).eps
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


@dataclass(frozen=True, eq=False)
class _Ritz:
    """Rayleigh-Ritz pairs of the active part of H, largest |theta| first.

    Attributes
    ----------
    theta : (a,) float
        Ritz values [s^2/rad^2] (``1 / (lam - sigma)``).
    S : (a, a) float
        Their eigenvectors in the active columns ``V[:, nl:kb]``.
    conv, resolved : (a,) bool
        Converged; far enough from the largest |theta| to be locked (see ``_LOCK_SPREAD``).
    wanted : (n,) int
        The ``n`` largest |theta| among ``[theta_l, theta]``, locked ones first.
    wa : int array
        The active ones among ``wanted``, indices into ``theta``.
    lockable : int array
        Those of ``wa`` that are converged and resolved.
    """

    theta: np.ndarray
    S: np.ndarray
    conv: np.ndarray
    resolved: np.ndarray
    wanted: np.ndarray
    wa: np.ndarray
    lockable: np.ndarray


def _rayleigh_ritz(st: KrylovState, blk: Expansion, n: int, tol: float) -> _Ritz:
    """Ritz pairs of the active part of H with their convergence and locking state."""
    nl, kb = st.nl, blk.kb
    theta, S = np.linalg.eigh(sym(st.H[nl:kb, nl:kb]))
    order = np.argsort(-np.abs(theta), kind="stable")
    theta, S = theta[order], S[:, order]
    if blk.grow > 0:
        resid = np.linalg.norm(blk.B @ S[st.k - nl:kb - nl, :], axis=0)
    else:  # the basis spans the whole space: the Ritz pairs are exact
        resid = np.zeros(theta.size)
    # ARPACK's test resid <= tol |theta_i|, floored at _FLOOR * max |theta| over
    # the active pairs: these residuals are true projections (they include the
    # rounding of the solves), which settle near that level instead of falling on
    # like ARPACK's recurrence-based estimates.
    big = np.abs(theta[0])
    rel = resid / np.maximum(np.abs(theta), np.finfo(np.float64).tiny)
    conv = resid <= np.maximum(tol * np.abs(theta), _FLOOR * big)
    wanted = np.argsort(-np.abs(np.concatenate([st.theta_l, theta])), kind="stable")[:n]
    wa = wanted[wanted >= nl] - nl
    # A pair whose |theta| is far below the largest active one is limited by that
    # floor (the rigid modes of a free part against its elastic ones): it is only
    # accepted once the large pairs are locked, which lowers the floor.
    resolved = np.abs(theta) * _LOCK_SPREAD >= big
    _accept_stalled(st.history, wa[~conv[wa]], rel, resid, big, conv)
    lockable = wa[conv[wa] & resolved[wa]]
    return _Ritz(theta, S, conv, resolved, wanted, wa, lockable)


def _accept_stalled(history: list[float], todo: np.ndarray, rel: np.ndarray,
                    resid: np.ndarray, big: float, conv: np.ndarray) -> None:
    """Mark the unconverged wanted pairs ``todo`` converged (in ``conv``) once stalled.

    Where the solves are noisier than the floor (a nearly singular K - sigma M), the
    residuals stall: they are accepted once the worst wanted one (``rel``, relative to
    |theta|) has not halved in _STALL Ritz steps, if ``resid`` is below _STALL_CAP times
    ``big``, the largest active |theta|.
    """
    history.append(float(rel[todo].max()) if todo.size else 0.0)
    if (todo.size and len(history) > _STALL and history[-1] > 0.5 * history[-1 - _STALL]
            and np.all(resid[todo] <= _STALL_CAP * big)):
        log.debug("block Lanczos: residuals stall at %.1e relative, accepted", history[-1])
        conv[todo] = True


def _give_up(st: KrylovState, blk: Expansion, rr: _Ritz, n: int, sigma: float) -> NoReturn:
    """Raise :class:`ConvergenceError` carrying the pairs converged so far."""
    wl = rr.wanted[rr.wanted < st.nl]
    X = np.hstack([st.V[:, wl], st.V[:, st.nl:blk.kb] @ rr.S[:, rr.lockable]])
    done = np.concatenate([st.theta_l[wl], rr.theta[rr.lockable]])
    raise ConvergenceError(
        f"block shift-invert Lanczos converged {done.size} of {n} modes after "
        f"{st.restarts} restarts ({st.n_solves} solves, block {st.p}, basis {st.m}); "
        "try a shift nearer the wanted modes or a larger basis (ncv)",
        sigma + 1.0 / done, X,
    )


def _thick_restart(st: KrylovState, blk: Expansion, rr: _Ritz, n: int, keep: int) -> None:
    """Lock the converged wanted pairs, keep the best other Ritz vectors (up to ``keep``
    columns in all) with their coupling to the next block, and grow again from it."""
    st.restarts += 1
    nl, kb, grow, theta = st.nl, blk.kb, blk.grow, rr.theta
    new_lock = rr.lockable
    rest = np.setdiff1d(np.arange(theta.size), new_lock)
    rest = rest[np.argsort(-np.abs(theta[rest]), kind="stable")]
    n_active = min(rest.size, max(keep - nl - new_lock.size,
                                  np.setdiff1d(rr.wa, new_lock).size))
    rest = rest[:n_active]
    if nl + new_lock.size + n_active + grow > st.m:
        raise ConvergenceError(f"block shift-invert Lanczos: basis {st.m} too small for {n} "
                               "modes; give a larger basis (ncv)")
    cols = np.concatenate([new_lock, rest])
    Y = st.V[:, nl:kb] @ rr.S[:, cols]
    MY = st.MV[:, nl:kb] @ rr.S[:, cols]
    nk = cols.size
    st.V[:, nl:nl + nk], st.MV[:, nl:nl + nk] = Y, MY
    st.theta_l = np.concatenate([st.theta_l, theta[new_lock]])
    nl_new = nl + new_lock.size
    ka = nl_new + n_active  # end of the kept active Ritz vectors
    H = st.H
    H[:] = 0.0
    H[nl_new:ka, nl_new:ka] = np.diag(theta[rest])
    coupling = blk.B @ rr.S[st.k - nl:kb - nl, rest]
    H[ka:ka + grow, nl_new:ka] = coupling  # residual block of the kept vectors
    H[nl_new:ka, ka:ka + grow] = coupling.T
    st.V[:, ka:ka + grow], st.MV[:, ka:ka + grow] = blk.Q, blk.MQ
    st.nl, st.prev, st.k, st.pb = nl_new, nl_new, ka, grow


def _refine_small(st: KrylovState, X: np.ndarray, theta_w: np.ndarray) -> None:
    """Recompute, in place, the pairs whose |theta| is far below the largest.

    With a spread of |theta| (free part: rigid ~1/|sigma|, elastic ~1/lam) the small
    theta from H carry the rounding of the large ones (measured on the free Tet10 bar:
    8e-10 relative, ARPACK's 6e-11), while the vectors are accurate.  One more solve on
    them and a Rayleigh-Ritz step gives theta to ~1e-12.
    """
    small = np.abs(theta_w) * _LOCK_SPREAD < np.abs(theta_w).max()
    if small.any():
        Xs = X[:, small]
        Y = st.solve(np.asfortranarray(st.M @ Xs))
        st.n_solves += Xs.shape[1]
        st.n_blocks += 1
        t, U = np.linalg.eigh(sym(Xs.T @ (st.M @ Y)))
        X[:, small], theta_w[small] = Xs @ U, t


def _result(st: KrylovState, blk: Expansion, rr: _Ritz, sigma: float):
    """``(lam, X, info)`` of the wanted pairs, locked and active, nearest the shift first."""
    # (a locked pair can drop out of the wanted set when copies of a multiple
    # eigenvalue nearer the shift appear late)
    wl = rr.wanted[rr.wanted < st.nl]
    X = np.hstack([st.V[:, wl], st.V[:, st.nl:blk.kb] @ rr.S[:, rr.wa]])
    theta_w = np.concatenate([st.theta_l[wl], rr.theta[rr.wa]])
    _refine_small(st, X, theta_w)
    order = np.argsort(-np.abs(theta_w), kind="stable")
    info = BlockLanczosInfo(st.p, st.m, st.n_solves, st.n_blocks, st.restarts)
    log.debug("block Lanczos: %s", info)
    return sigma + 1.0 / theta_w[order], X[:, order], info


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

    st = start(M, solve, size, p, m, seed)
    while True:
        blk = expand(st)
        rr = _rayleigh_ritz(st, blk, n, tol)
        if rr.conv[rr.wa].all():
            if rr.resolved[rr.wa].all() or blk.grow == 0:  # (a full space: pairs are exact)
                return _result(st, blk, rr, sigma)
            # lock the resolved pairs now: that lowers the floor of the small ones
        elif blk.kb + blk.grow <= m:  # room left: append the new block
            append(st, blk)
            continue
        elif st.restarts >= max_restarts:
            _give_up(st, blk, rr, n, sigma)
        _thick_restart(st, blk, rr, n, keep)
