"""Double-accurate solves through a single-precision factor: refinement converges to the
double solution, counts its steps, halves PARDISO's factor, and rejects a factor too
poor for the matrix."""

from __future__ import annotations

import numpy as np
import pytest
import scipy.linalg as sla
import scipy.sparse as sp

from flexarm.fe import assemble, available_backends, dof_split, factorize, node_dofs
from flexarm.fe.refinement import RefinementError, backward_error, refined_solver
from flexarm.fe.tolerances import tol

needs_pardiso = pytest.mark.skipif("pardiso" not in available_backends(),
                                   reason="pypardiso not installed")
SINGLE_BACKENDS = [pytest.param("splu"), pytest.param("pardiso", marks=needs_pardiso)]


@pytest.fixture(scope="module")
def clamped(tet10_bar, steel):
    """Free-free stiffness of the clamped Tet10 bar and a block of 7 load columns."""
    K, _ = assemble(tet10_bar, steel)
    split = dof_split(tet10_bar.n_dofs, node_dofs(tet10_bar.node_sets["fixed"]))
    Kf = split.condense(K)
    B = np.random.default_rng(3).standard_normal((Kf.shape[0], 7)) * 1e3
    return Kf, B


@pytest.mark.parametrize("backend", SINGLE_BACKENDS)
def test_single_factor_solves_to_double_accuracy(clamped, backend):
    Kf, B = clamped
    ref = factorize(Kf, backend=backend).solve(B)
    f = factorize(Kf, backend=backend, precision="single")
    X = f.solve(B)
    assert f.precision == "single"
    assert backward_error(Kf, X, B).max() <= tol.refinement
    # the forward error follows from the backward errors and the condition number
    # (Higham, Accuracy and Stability, Thm 7.2): |dx| / |x| <= 2 cond(K) * eta / (1 - ...)
    # for each solution, a bound set by the problem, not by the machine's rounding; and
    # far from the ~1e-4 of an unrefined single solve
    cond = np.linalg.cond(Kf.toarray(), p=np.inf)
    eta = backward_error(Kf, X, B).max() + backward_error(Kf, ref, B).max()
    assert np.abs(X - ref).max() <= 2 * cond * eta * np.abs(ref).max()
    assert np.abs(X - ref).max() <= 1e-9 * np.abs(ref).max()
    st = f.refinement
    assert st.solves == 7 and 1.0 <= st.steps_per_solve <= 6.0
    # one column on its own gives the same answer as within the block
    assert np.allclose(f.solve(B[:, 3]), X[:, 3], rtol=0, atol=1e-9 * np.abs(X).max())


def test_unrefined_single_solve_is_not_double_accurate(clamped):
    # what the refinement buys: the plain single-precision solve is ~1e-7 off
    Kf, B = clamped
    lu = sp.linalg.splu(Kf.astype(np.float32).tocsc(), permc_spec="MMD_AT_PLUS_A")
    X1 = lu.solve(B.astype(np.float32)).astype(float)
    assert backward_error(Kf, X1, B).max() > 1e3 * tol.refinement


@needs_pardiso
def test_pardiso_single_factor_takes_about_half_the_memory(clamped):
    Kf, _ = clamped
    double = factorize(Kf, backend="pardiso").memory_bytes
    single = factorize(Kf, backend="pardiso", precision="single").memory_bytes
    # PARDISO's own figure: values halve, its integer structure does not
    assert 0.45 * double <= single <= 0.75 * double


def test_too_ill_conditioned_for_single_precision_is_refused():
    # Hilbert matrix of order 9: cond 5e11 > 1 / eps_single, refinement cannot converge
    H = sp.csr_matrix(sla.hilbert(9))
    lu = sp.linalg.splu(H.astype(np.float32).tocsc())
    solve = refined_solver(H, lambda b: lu.solve(b.astype(np.float32)).astype(float))
    with pytest.raises(RefinementError, match="too inaccurate.*double precision"):
        solve(np.ones(9))


def test_zero_right_hand_side_and_bad_precision(clamped):
    Kf, B = clamped
    f = factorize(Kf, backend="splu", precision="single")
    assert not f.solve(np.zeros_like(B[:, :2])).any()
    with pytest.raises(ValueError, match="precision must be one of double, single"):
        factorize(Kf, backend="splu", precision="half")
    if "cholmod" in available_backends():
        with pytest.raises(ValueError, match="pardiso or splu"):
            factorize(Kf, backend="cholmod", precision="single")
