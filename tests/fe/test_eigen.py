"""The block shift-invert Lanczos against ARPACK and dense LAPACK, on small parts."""

from __future__ import annotations

import numpy as np
import pytest
import scipy.linalg as sla
import scipy.sparse as sp

from flexarm.fe import (
    ConvergenceError,
    TetMesh,
    assemble,
    auto_shift,
    dof_split,
    factorize,
    modes,
    node_dofs,
    select_nodes,
    shift_invert,
)
from flexarm.fe.block_eigen import block_shift_invert
from flexarm.fe.eigen import DENSE_LIMIT
from flexarm.fe.refinement import RefinementError


@pytest.fixture(scope="module")
def bar(tet10_bar, steel):
    """The 1.0 x 0.1 x 0.1 m Tet10 bar: full K, M (free) and the clamped K_ff, M_ff."""
    K, M = assemble(tet10_bar, steel)
    split = dof_split(tet10_bar.n_dofs, node_dofs(tet10_bar.node_sets["fixed"]))
    return K.tocsr(), M.tocsr(), split.condense(K).tocsr(), split.condense(M).tocsr()


def _dense(K, M, n):
    return sla.eigh(K.toarray(), M.toarray(), subset_by_index=[0, n - 1])


def _overlap(A, B, M):
    """|A^T M B| for M-normalised columns: the identity when the shapes agree."""
    return np.abs(A.T @ (M @ B))


def test_clamped_block_matches_arpack_and_dense(bar):
    *_, Kf, Mf = bar
    assert Kf.shape[0] > DENSE_LIMIT  # the factorise + Krylov path
    n = 12
    blk = modes(Kf, Mf, n, eigensolver=shift_invert(0.0, method="block"))
    arp = modes(Kf, Mf, n, eigensolver=shift_invert(0.0, method="arpack"))
    w, v = _dense(Kf, Mf, n)
    assert blk.omega2.shape == (n,) and blk.vectors.shape == (Kf.shape[0], n)
    assert np.all(np.diff(blk.omega2) >= 0)
    # ARPACK and the block solver agree far below the dense solver's own error on the
    # lowest mode (LAPACK's Cholesky-based reduction: ~1e-9 relative here)
    np.testing.assert_allclose(blk.omega2, arp.omega2, rtol=1e-12)
    np.testing.assert_allclose(blk.omega2, w, rtol=1e-8)
    # same shapes and the same signs (the fixed-probe convention) as ARPACK
    ov = blk.vectors.T @ (Mf @ arp.vectors)
    assert np.abs(np.diag(ov) - 1.0).max() < 1e-10
    # modes 1-2, 3-4, ... of the square section are bending pairs split by ~2e-4 only
    assert np.abs(ov - np.diag(np.diag(ov))).max() < 1e-7
    # and against LAPACK's vectors, up to sign
    assert np.abs(np.diag(_overlap(blk.vectors, v, Mf)) - 1.0).max() < 1e-7
    # M-orthonormal, and each pair is an eigenpair to round-off
    np.testing.assert_allclose(blk.vectors.T @ (Mf @ blk.vectors), np.eye(n), atol=1e-12)
    R = Kf @ blk.vectors - (Mf @ blk.vectors) * blk.omega2
    rel = np.linalg.norm(R, axis=0) / np.linalg.norm(Kf @ blk.vectors, axis=0)
    assert rel.max() < 1e-8


def test_square_section_pairs_are_both_found(bar):
    """The bending pairs of the square bar (omega^2 split by ~1e-3 by the tets): every
    block size finds both members, and their 2-D subspaces agree with LAPACK's."""
    *_, Kf, Mf = bar
    w, v = _dense(Kf, Mf, 4)
    assert (w[1] - w[0]) / w[0] < 1e-2 and (w[3] - w[2]) / w[2] < 1e-2  # they are pairs
    for p in (1, 2, 3):
        m = modes(Kf, Mf, 4, eigensolver=shift_invert(0.0, block_size=p))
        np.testing.assert_allclose(m.omega2, w, rtol=1e-8)
        for pair in (slice(0, 2), slice(2, 4)):
            # cosines of the principal angles between the two pair subspaces
            cos = sla.svdvals(m.vectors[:, pair].T @ (Mf @ v[:, pair]))
            assert cos.min() > 1 - 1e-10


def test_exactly_repeated_eigenvalues_need_a_block(bar, steel):
    """Two identical, unconnected bars: every eigenvalue is exactly double.  A block of 2
    finds both copies; they are distinct M-orthonormal vectors."""
    *_, Kf, Mf = bar
    K2, M2 = sp.block_diag([Kf, Kf], format="csr"), sp.block_diag([Mf, Mf], format="csr")
    n = 6
    w = _dense(Kf, Mf, n // 2)[0]
    m = modes(K2, M2, n, eigensolver=shift_invert(0.0, block_size=2))
    np.testing.assert_allclose(m.omega2, np.repeat(w, 2), rtol=1e-8)
    np.testing.assert_allclose(m.vectors.T @ (M2 @ m.vectors), np.eye(n), atol=1e-12)
    R = K2 @ m.vectors - (M2 @ m.vectors) * m.omega2
    assert np.abs(R).max() < 1e-8 * np.abs(K2 @ m.vectors).max()


def test_free_part_six_rigid_modes(bar):
    K, M, *_ = bar
    n = 12
    blk = modes(K, M, n, eigensolver=shift_invert(None))
    arp = modes(K, M, n, eigensolver=shift_invert(None, method="arpack"))
    w = _dense(K, M, n)[0]
    assert blk.n_rigid == 6 and arp.n_rigid == 6
    assert np.all(blk.is_rigid[:6]) and not np.any(blk.is_rigid[6:])
    # the elastic eigenvalues come from a final Rayleigh-Ritz step (see block_eigen):
    # 5e-12 from LAPACK's, ARPACK's are 7e-11 off (their theta carry the rigid ones'
    # rounding)
    np.testing.assert_allclose(blk.omega2[6:], w[6:], rtol=5e-11)
    np.testing.assert_allclose(blk.omega2[6:], arp.omega2[6:], rtol=3e-10)
    # the six rigid vectors span the rigid-body motions: a unit x-translation lies in
    # their span (M-projection keeps all of its M-norm)
    t = np.zeros(K.shape[0])
    t[0::3] = 1.0
    coef = blk.vectors[:, :6].T @ (M @ t)
    assert coef @ coef == pytest.approx(t @ (M @ t), rel=1e-10)
    assert np.abs(K @ blk.vectors[:, :6]).max() < 1e-8 * np.abs(K @ blk.vectors[:, 6:]).max()


def test_block_is_deterministic(bar):
    K, M, Kf, Mf = bar
    for A, B, sigma in ((Kf, Mf, 0.0), (K, M, None)):
        a = modes(A, B, 8, eigensolver=shift_invert(sigma, block_size=2))
        b = modes(A, B, 8, eigensolver=shift_invert(sigma, block_size=2))
        assert np.array_equal(a.omega2, b.omega2)
        assert np.array_equal(a.vectors, b.vectors)


def test_block_sizes_agree(bar):
    *_, Kf, Mf = bar
    ref = modes(Kf, Mf, 10, eigensolver=shift_invert(0.0, block_size=1))
    for p in (4, 6):
        m = modes(Kf, Mf, 10, eigensolver=shift_invert(0.0, block_size=p))
        np.testing.assert_allclose(m.omega2, ref.omega2, rtol=1e-12)
        assert np.abs(np.diag(ref.vectors.T @ (Mf @ m.vectors)) - 1.0).max() < 1e-10


def test_nonconvergence_raises_with_what_converged(bar):
    *_, Kf, Mf = bar
    f = factorize(Kf)
    with pytest.raises(ConvergenceError, match=r"converged \d+ of 10 modes after 0 restarts") as e:
        block_shift_invert(Mf, 10, f.solve, 0.0, basis_size=12, max_restarts=0)
    done = e.value.eigenvalues
    assert len(done) < 10 and e.value.eigenvectors.shape == (Kf.shape[0], len(done))
    # what did converge is right (the lowest modes converge first)
    w = _dense(Kf, Mf, 10)[0]
    assert np.all(np.min(np.abs(done[:, None] / w[None, :] - 1), axis=1) < 1e-8)


@pytest.mark.parametrize("method", ["block", "arpack"])
def test_residual_check_rejects_a_foreign_factor(bar, method):
    """A factor of 2 K has the same eigenvectors as K's, so the Krylov estimates converge,
    but every eigenvalue comes out doubled: only the residual check sees it."""
    *_, Kf, Mf = bar
    with pytest.raises(ConvergenceError, match="residual check"):
        modes(Kf, Mf, 4, eigensolver=shift_invert(0.0, method=method), factor=factorize(2 * Kf))


def test_unknown_method_is_refused():
    with pytest.raises(ValueError, match="block, arpack"):
        shift_invert(0.0, method="lobpcg")


def test_thin_plate_free_modes(steel):
    """A free thin plate: the rigid |theta| are ~1e6 times the elastic ones, which
    exercises locking (the elastic pairs converge only after the rigid ones lock)."""
    from flexarm.fe import MATERIALS

    mesh = TetMesh.box((1.0, 1.0, 0.02), (6, 6, 1), order=2)
    K, M = assemble(mesh, MATERIALS["nafems"])
    K, M = K.tocsr(), M.tocsr()
    assert abs(auto_shift(K, M)) > 0
    m = modes(K, M, 10)
    w = _dense(K, M, 10)[0]
    assert m.n_rigid == 6
    np.testing.assert_allclose(m.omega2[6:], w[6:], rtol=1e-8)


def test_clamped_thin_plate_matches_dense(steel):
    """Clamped along one edge: the shift-invert path on an anisotropic spectrum."""
    mesh = TetMesh.box((1.0, 0.5, 0.02), (8, 4, 1), order=2)
    K, M = assemble(mesh, steel)
    split = dof_split(mesh.n_dofs, node_dofs(select_nodes(mesh, "x=min")))
    Kf, Mf = split.condense(K).tocsr(), split.condense(M).tocsr()
    m = modes(Kf, Mf, 8, eigensolver=shift_invert(0.0))
    arp = modes(Kf, Mf, 8, eigensolver=shift_invert(0.0, method="arpack"))
    np.testing.assert_allclose(m.omega2, arp.omega2, rtol=1e-11)
    # LAPACK loses ~eps * omega_max^2 / omega_1^2 on the first mode of a thin plate
    np.testing.assert_allclose(m.omega2, _dense(Kf, Mf, 8)[0], rtol=1e-7)


@pytest.mark.parametrize("p", [1, 2, 3])
def test_invariant_subspaces_and_the_full_space(p):
    """K = diag(1, 1, 1, 2, 2, 2, ..., 10, 10, 10), M = I: a single start vector sees one
    copy of each triple eigenvalue, its Krylov space turns invariant after 10 steps and
    must be refilled with fresh directions; asking for all 30 fills the whole space."""
    d = np.repeat(np.arange(1.0, 11.0), 3)
    M = sp.identity(d.size, format="csr")

    def solve(B):
        return B / d[:, None] if B.ndim == 2 else B / d

    for n in (9, d.size):
        lam, X, _ = block_shift_invert(M, n, solve, 0.0, block_size=p)
        np.testing.assert_allclose(np.sort(lam), d[:n], rtol=1e-13)
        np.testing.assert_allclose(X.T @ X, np.eye(n), atol=1e-13)
        np.testing.assert_allclose(X * d[:, None], X * lam, atol=1e-12)


def test_single_precision_factor_gives_the_double_modes(bar):
    *_, Kf, Mf = bar
    ref = modes(Kf, Mf, 12, eigensolver=shift_invert(0.0, backend="splu"))
    got = modes(Kf, Mf, 12, eigensolver=shift_invert(0.0, backend="splu", precision="single"))
    # this slender bar's lowest eigenvalue is only defined to ~eps * ||K|| / omega2_1 (two
    # double backends, or dense LAPACK, differ by 3e-11..9e-10 in omega2): the single
    # path agrees to that level
    assert np.max(np.abs(got.freq_hz / ref.freq_hz - 1)) < 1e-9
    assert np.allclose(np.diag(_overlap(got.vectors, ref.vectors, Mf)), 1.0, atol=1e-8)


def test_single_precision_refuses_a_nearly_singular_shift(bar):
    # a free part shifted just below its rigid modes: K - sigma M has cond ~1e11, far
    # beyond what refinement through a single-precision factor can recover
    K, M, *_ = bar
    with pytest.raises(RefinementError, match="single-precision factor too inaccurate"):
        modes(K, M, 8, eigensolver=shift_invert(None, backend="splu", precision="single"))
