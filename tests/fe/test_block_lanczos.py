"""Block Lanczos basis: M-orthonormal blocks (Q^T M Q = I, V^T M Q = 0, same span), rank-deficient
blocks refilled, seeded start, and the Krylov relation OP V = V H + Q B with OP = K^-1 M."""

from __future__ import annotations

import numpy as np
import pytest
import scipy.sparse as sp

from flexarm.fe.block_lanczos import append, expand, orthonormal_block, project_out, start, sym

N = 40
RNG = np.random.default_rng(11)
M = sp.diags(RNG.uniform(0.5, 2.0, N)).tocsr()
K_DIAG = np.arange(1.0, N + 1) ** 2


def solve(B):
    return B / (K_DIAG[:, None] if B.ndim == 2 else K_DIAG)


def _m_orthonormal(p, rng):
    V, _ = np.linalg.qr(rng.normal(size=(N, p)))
    d = np.sqrt(M.diagonal())
    return V / d[:, None]  # V^T M V = I for diagonal M


def test_sym_and_project_out():
    A = np.arange(9.0).reshape(3, 3)
    np.testing.assert_array_equal(sym(A), (A + A.T) / 2)
    rng = np.random.default_rng(0)
    V = _m_orthonormal(3, rng)
    W = rng.normal(size=(N, 2))
    W0 = W.copy()
    C = project_out(W, V, M @ V)
    np.testing.assert_allclose(V.T @ (M @ W), 0.0, atol=1e-13)
    np.testing.assert_allclose(V @ C + W, W0, atol=1e-14)


@pytest.mark.parametrize("rank", [3, 2])
def test_orthonormal_block(rank):
    """A block of 3 columns of rank 3 or 2: Q is M-orthonormal, M-orthogonal to V, M Q is
    right, and Q spans W (plus a fresh direction where W had none)."""
    rng = np.random.default_rng(rank)
    V = _m_orthonormal(4, rng)
    W = rng.normal(size=(N, 3))
    if rank == 2:
        W[:, 2] = W[:, 0] - 2 * W[:, 1]
    project_out(W, V, M @ V)
    ref = float(np.sqrt(np.einsum("ij,ij->j", W, M @ W)).max())
    Q, MQ = orthonormal_block(W.copy(), M @ W, ref, V, M @ V, M, rng)
    assert Q.shape == (N, 3)
    np.testing.assert_allclose(Q.T @ (M @ Q), np.eye(3), atol=1e-12)
    np.testing.assert_allclose(V.T @ (M @ Q), 0.0, atol=1e-12)
    np.testing.assert_allclose(MQ, M @ Q, atol=1e-12)
    coef = Q.T @ (M @ W)  # W is in span(Q)
    np.testing.assert_allclose(Q @ coef, W, atol=1e-11 * np.abs(W).max())


def test_start_is_seeded_and_m_orthonormal():
    a = start(M, solve, N, p=3, m=12, seed=7)
    b = start(M, solve, N, p=3, m=12, seed=7)
    c = start(M, solve, N, p=3, m=12, seed=8)
    V = a.V[:, :3]
    np.testing.assert_array_equal(V, b.V[:, :3])
    assert not np.allclose(V, c.V[:, :3])
    np.testing.assert_allclose(V.T @ (M @ V), np.eye(3), atol=1e-13)
    np.testing.assert_allclose(a.MV[:, :3], M @ V, atol=1e-13)
    assert (a.p, a.m, a.pb, a.n_solves, a.k, a.nl) == (3, 12, 3, 3, 0, 0)


def test_krylov_relation_after_expansions():
    st = start(M, solve, N, p=2, m=10, seed=1)
    for _ in range(3):
        blk = expand(st)
        assert blk.grow == 2
        append(st, blk)
    kb = st.k  # columns whose OP-image is in H
    assert (kb, st.pb, st.n_solves, st.n_blocks) == (6, 2, 8, 4)
    V = st.V[:, :kb + st.pb]
    np.testing.assert_allclose(V.T @ (M @ V), np.eye(kb + st.pb), atol=1e-12)
    OPV = solve(M @ st.V[:, :kb])
    np.testing.assert_allclose(V @ st.H[:kb + st.pb, :kb], OPV, atol=1e-12 * np.abs(OPV).max())
    # OP is M-symmetric: the projected matrix is symmetric and block tridiagonal
    H = st.H[:kb, :kb]
    np.testing.assert_allclose(H, H.T, atol=1e-13 * np.abs(H).max())
    np.testing.assert_allclose(H[:2, 4:6], 0.0, atol=1e-13 * np.abs(H).max())


def test_expansion_stops_when_the_basis_spans_the_space():
    n = 4
    Mn = sp.identity(n, format="csr")
    st = start(Mn, lambda B: B / np.arange(1.0, n + 1)[:, None], n, p=2, m=4, seed=0)
    append(st, expand(st))
    last = expand(st)
    assert (last.kb, last.grow, last.Q.shape, last.B.shape) == (4, 0, (4, 0), (0, 2))
    H = st.H
    np.testing.assert_allclose(np.sort(np.linalg.eigvalsh(sym(H))), 1 / np.arange(4.0, 0, -1),
                               rtol=1e-12)
