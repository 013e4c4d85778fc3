"""Solver backends, factor reuse and the modal solve's guarantees."""

from __future__ import annotations

import numpy as np
import pytest
import scipy.linalg as sla

import flexarm.fe.solvers as solvers
from flexarm.fe import (
    SingularMatrixError,
    assemble,
    available_backends,
    dof_split,
    factorize,
    gravity_load,
    modes,
    nodal_load,
    node_dofs,
    shift_invert,
    static_solve,
)
from flexarm.fe.eigen import DENSE_LIMIT

needs_pardiso = pytest.mark.skipif("pardiso" not in available_backends(),
                                   reason="pypardiso not installed")


@pytest.fixture(scope="module")
def bar(tet10_bar, steel):
    """Clamped Tet10 bar (1575 DOF): mesh, K, M, split, free K and M, load vector."""
    K, M = assemble(tet10_bar, steel)
    split = dof_split(tet10_bar.n_dofs, node_dofs(tet10_bar.node_sets["fixed"]))
    f = gravity_load(M) + nodal_load(tet10_bar.n_nodes, tet10_bar.node_sets["tip"], [0, 500.0, 0])
    Kf, Mf = split.condense(K), split.condense(M)
    assert Kf.shape[0] > DENSE_LIMIT  # the factorise + ARPACK path, not the dense one
    return tet10_bar, K, M, split, Kf, Mf, f


@pytest.fixture
def count_factorisations(monkeypatch):
    """Wrap every backend so each factorisation is counted (whoever calls it)."""
    calls = []
    for name in ("pardiso_factor", "_splu", "_cholmod"):
        original = getattr(solvers, name)

        def wrapped(*args, _original=original, _name=name, **kwargs):
            calls.append(_name)
            return _original(*args, **kwargs)

        monkeypatch.setattr(solvers, name, wrapped)
    return calls


@needs_pardiso
def test_backends_agree_on_static_solution(bar):
    _, K, _, split, _, _, f = bar
    u_p = static_solve(K, f, split, backend="pardiso")
    u_s = static_solve(K, f, split, backend="splu")
    assert np.abs(u_p).max() > 1e-6  # a real deflection [m]
    assert np.abs(u_p - u_s).max() <= 1e-9 * np.abs(u_s).max()
    assert np.all(u_p[split.fixed] == 0.0)


@needs_pardiso
def test_backends_agree_on_ten_modes(bar):
    *_, Kf, Mf, _ = bar
    m_p = modes(Kf, Mf, n=10, eigensolver=shift_invert(0.0, backend="pardiso"))
    m_s = modes(Kf, Mf, n=10, eigensolver=shift_invert(0.0, backend="splu"))
    np.testing.assert_allclose(m_p.omega2, m_s.omega2, rtol=1e-9)
    # the same mass-normalised shapes: M-inner products of matching modes are +-1
    # (modes 1-2, 3-4 are near-degenerate bending pairs of the square section, split
    # by 2e-4 only, so within a pair the shapes agree to ~1e-8, to 1e-16 in |overlap|)
    overlap = m_p.vectors.T @ (Mf @ m_s.vectors)
    assert np.abs(np.abs(np.diag(overlap)) - 1.0).max() <= 1e-9
    assert np.abs(overlap - np.diag(np.diag(overlap))).max() <= 1e-7


@needs_pardiso
def test_mode_signs_agree_across_backends(bar):
    """The sign convention must not depend on round-off.

    ``eigen._normalise`` makes the largest-magnitude component positive; on a symmetric
    part mirror-image DOFs tie for the largest to 1e-9..1e-15, so the two backends pick
    different components and flip the sign of half the modes.
    """
    *_, Kf, Mf, _ = bar
    m_p = modes(Kf, Mf, n=10, eigensolver=shift_invert(0.0, backend="pardiso"))
    m_s = modes(Kf, Mf, n=10, eigensolver=shift_invert(0.0, backend="splu"))
    signs = np.sign(np.diag(m_p.vectors.T @ (Mf @ m_s.vectors)))
    assert np.all(signs > 0), f"modes with flipped sign: {np.flatnonzero(signs < 0) + 1}"


def test_arpack_path_matches_dense_eigh(steel):
    """Just above DENSE_LIMIT free DOFs: the shift-invert Krylov path vs LAPACK's dense eigh."""
    from flexarm.fe import TetMesh, select_nodes

    mesh = TetMesh.box((1.0, 0.1, 0.1), (8, 1, 1), order=2)
    K, M = assemble(mesh, steel)
    split = dof_split(mesh.n_dofs, node_dofs(select_nodes(mesh, "x=min")))
    Kf, Mf = split.condense(K), split.condense(M)
    assert DENSE_LIMIT < Kf.shape[0] < 2 * DENSE_LIMIT
    m = modes(Kf, Mf, n=10, eigensolver=shift_invert(0.0))
    dense = sla.eigh(Kf.toarray(), Mf.toarray(), subset_by_index=[0, 9], eigvals_only=True)
    np.testing.assert_allclose(m.omega2, dense, rtol=1e-9)


def test_modes_are_mass_normalised_and_k_orthogonal(bar):
    *_, Kf, Mf, _ = bar
    m = modes(Kf, Mf, n=10, eigensolver=shift_invert(0.0))
    V = m.vectors
    np.testing.assert_allclose(V.T @ (Mf @ V), np.eye(10), atol=1e-10)
    np.testing.assert_allclose(V.T @ (Kf @ V), np.diag(m.omega2), atol=1e-9 * m.omega2.max())
    # each pair really is an eigenpair: residual K v - omega^2 M v at round-off level
    R = Kf @ V - (Mf @ V) * m.omega2
    assert np.abs(R).max() <= 1e-8 * np.abs(Kf @ V).max()


def test_modes_deterministic_and_sorted(bar):
    *_, Kf, Mf, _ = bar
    a = modes(Kf, Mf, n=10, eigensolver=shift_invert(0.0))
    b = modes(Kf, Mf, n=10, eigensolver=shift_invert(0.0))
    assert np.array_equal(a.omega2, b.omega2)
    assert np.array_equal(a.vectors, b.vectors)
    assert np.all(np.diff(a.omega2) >= 0)
    assert np.all(np.diff(a.freq_hz) >= 0)


def test_factor_is_reused_by_modes(bar, count_factorisations):
    *_, Kf, Mf, _ = bar
    solver = shift_invert(0.0)
    fresh = modes(Kf, Mf, n=6, eigensolver=solver)
    assert len(count_factorisations) == 1
    factor = factorize(Kf)  # K - sigma M with sigma = 0
    assert len(count_factorisations) == 2
    reused = modes(Kf, Mf, n=6, eigensolver=solver, factor=factor)
    again = modes(Kf, Mf, n=6, eigensolver=solver, factor=factor)
    assert len(count_factorisations) == 2  # no new factorisation
    np.testing.assert_allclose(reused.omega2, fresh.omega2, rtol=1e-12)
    assert np.array_equal(reused.omega2, again.omega2)


def test_factor_is_reused_by_static_solve_and_modes(bar, count_factorisations):
    """One factorisation of K_ff serves two load cases and the eigen-solve."""
    _, K, _, split, Kf, Mf, f = bar
    factor = factorize(Kf)
    u1 = static_solve(K, f, split, factor=factor)
    u2 = static_solve(K, np.column_stack([f, 2 * f]), split, factor=factor)
    m = modes(Kf, Mf, n=4, eigensolver=shift_invert(0.0), factor=factor)
    assert len(count_factorisations) == 1
    np.testing.assert_allclose(u2[:, 1], 2 * u1, rtol=0, atol=1e-12 * np.abs(u1).max())
    assert m.n_rigid == 0


def test_n_rigid_free_partly_supported_and_clamped(bar):
    mesh, K, M, split, Kf, Mf, _ = bar
    assert modes(K, M, n=8).n_rigid == 6  # free
    # u_x = 0 on the end face: translation y, z and the rotation about x remain
    partial = dof_split(mesh.n_dofs, node_dofs(mesh.node_sets["fixed"], components=(0,)))
    m = modes(partial.condense(K), partial.condense(M), n=6)
    assert m.n_rigid == 3
    assert np.all(m.is_rigid[:3]) and not np.any(m.is_rigid[3:])
    assert modes(Kf, Mf, n=4).n_rigid == 0  # clamped


@needs_pardiso
def test_zero_shift_on_a_free_part_is_singular(bar):
    _, K, M, *_ = bar
    with pytest.raises(SingularMatrixError):
        modes(K, M, n=8, eigensolver=shift_invert(0.0, backend="pardiso"))


def test_n_rigid_does_not_depend_on_the_users_shift(bar):
    """A free part has 6 rigid modes whatever (sensible) shift the user picks.

    ``Modes.is_rigid`` compares |omega^2| with ``tol.rigid_mode * |shift|``; with
    ``shift_invert(-1.0)`` that threshold is 1e-6 rad^2/s^2, below the round-off level
    of the rigid eigenvalues (~1e-6..1e-5 here), so they count as elastic.
    """
    _, K, M, *_ = bar
    m = modes(K, M, n=8, eigensolver=shift_invert(-1.0))
    assert m.freq_hz[6] > 50.0  # the first elastic mode is far from zero
    assert m.n_rigid == 6


def test_auto_shift_lies_below_the_first_elastic_mode(steel):
    """``auto_shift`` promises a shift "far below the first elastic mode of any reasonable
    mesh". A thin plate (10 x 10 x 0.05 m, the FV12 geometry, coarse) breaks it: the
    median K_ii/M_ii is set by the thickness, so |shift| is ~700x the first elastic
    omega^2 and the shift-invert Lanczos needs 7x more solves (FV12 30x30x1: 57 s).
    """
    from flexarm.fe import MATERIALS, TetMesh, auto_shift

    mesh = TetMesh.box((10.0, 10.0, 0.05), (6, 6, 1), order=2)
    K, M = assemble(mesh, MATERIALS["nafems"])
    m = modes(K, M, n=7, eigensolver=shift_invert(-1.0e-2))
    first_elastic = m.omega2[6]
    assert m.freq_hz[6] == pytest.approx(1.62, rel=0.1)  # FV12 mode 1
    assert abs(auto_shift(K, M)) < 0.1 * first_elastic
