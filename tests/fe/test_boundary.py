"""DOF elimination: node_dofs, dof_split and DofSplit.condense/coupling/expand against dense
indexing, a hand-solved spring chain and the exact uniaxial-stress bar (reaction E A d / L)."""

from __future__ import annotations

import numpy as np
import pytest
import scipy.sparse as sp
from scipy.sparse.linalg import spsolve

from flexarm.fe import TetMesh, dof_split, node_dofs, select_nodes, stiffness_matrix


def test_node_dofs_are_three_per_node_sorted_and_unique():
    np.testing.assert_array_equal(node_dofs([2, 0]), [0, 1, 2, 6, 7, 8])
    np.testing.assert_array_equal(node_dofs([[4], [1], [4]], components=(1,)), [4, 13])
    np.testing.assert_array_equal(node_dofs([3], components=(2, 0)), [9, 11])
    assert node_dofs([]).size == 0


@pytest.mark.parametrize("fixed", [[5, 0, 5, 3], [], list(range(7))])
def test_split_partitions_the_range(fixed):
    s = dof_split(7, fixed)
    assert s.n == 7
    np.testing.assert_array_equal(np.sort(np.r_[s.free, s.fixed]), np.arange(7))
    assert np.intersect1d(s.free, s.fixed).size == 0
    assert np.all(np.diff(s.free) > 0) and np.all(np.diff(s.fixed) > 0)
    np.testing.assert_array_equal(s.fixed, np.unique(fixed).astype(int))


def test_condense_and_coupling_are_the_dense_blocks():
    rng = np.random.default_rng(0)
    A = rng.normal(size=(9, 9))
    A[np.abs(A) < 0.8] = 0.0
    s = dof_split(9, [1, 4, 8])
    Kc, Kfc = s.condense(sp.csc_matrix(A)), s.coupling(sp.coo_matrix(A))
    assert sp.isspmatrix_csr(Kc) and sp.isspmatrix_csr(Kfc)
    np.testing.assert_array_equal(Kc.toarray(), A[np.ix_(s.free, s.free)])
    np.testing.assert_array_equal(Kfc.toarray(), A[np.ix_(s.free, s.fixed)])


def test_expand_puts_free_and_prescribed_values_in_place():
    s = dof_split(5, [0, 3])
    np.testing.assert_array_equal(s.expand([1.0, 2.0, 3.0]), [0, 1, 2, 0, 3])
    np.testing.assert_array_equal(s.expand([1.0, 2.0, 3.0], [7.0, 8.0]), [7, 1, 2, 8, 3])
    U = s.expand(np.arange(6.0).reshape(3, 2), -1.0)  # several vectors at once
    assert U.shape == (5, 2)
    np.testing.assert_array_equal(U[[0, 3]], -1.0)
    np.testing.assert_array_equal(U[[1, 2, 4]], np.arange(6.0).reshape(3, 2))
    assert s.expand(np.array([1j, 0, 0])).dtype == complex


def test_spring_chain_with_prescribed_ends():
    """Four equal springs in a row, ends at 0 and d: the inner nodes sit at d/4, d/2, 3d/4."""
    k, d, n = 3.0e5, 0.02, 5
    K = np.zeros((n, n))
    for i in range(n - 1):
        K[i:i + 2, i:i + 2] += k * np.array([[1, -1], [-1, 1]])
    s = dof_split(n, [0, n - 1])
    u_fixed = np.array([0.0, d])
    u_free = np.linalg.solve(s.condense(K).toarray(), -s.coupling(K) @ u_fixed)
    u = s.expand(u_free, u_fixed)
    np.testing.assert_allclose(u, d * np.linspace(0, 1, n), rtol=1e-13)
    # the reaction at the moved end is the spring force of the chain, k d / 4
    assert (K @ u)[-1] == pytest.approx(k * d / 4, rel=1e-12)


def test_uniaxial_bar_reaction_is_E_A_d_over_L(steel):
    """Rollers on x=min, y=min, z=min, u_x = d on x=max: uniaxial stress, exact for Tet4."""
    L, b, c, d = 2.0, 0.2, 0.1, 1e-4
    mesh = TetMesh.box((L, b, c), (4, 2, 1))
    K = stiffness_matrix(mesh, steel)
    x0, y0, z0, x1 = (select_nodes(mesh, e) for e in ("x=min", "y=min", "z=min", "x=max"))
    fixed = np.r_[node_dofs(x0, (0,)), node_dofs(y0, (1,)), node_dofs(z0, (2,)),
                  node_dofs(x1, (0,))]
    s = dof_split(mesh.n_dofs, fixed)
    u_fixed = np.zeros(s.fixed.size)
    u_fixed[np.isin(s.fixed, node_dofs(x1, (0,)))] = d
    u_free = spsolve(s.condense(K).tocsc(), -s.coupling(K) @ u_fixed)
    u = s.expand(u_free, u_fixed).reshape(-1, 3)
    p = mesh.points
    eps = d / L
    np.testing.assert_allclose(u, np.column_stack([eps * p[:, 0], -steel.nu * eps * p[:, 1],
                                                   -steel.nu * eps * p[:, 2]]),
                               atol=1e-12 * d)
    reaction = (K @ u.ravel())[node_dofs(x1, (0,))].sum()
    assert reaction == pytest.approx(steel.E * b * c * eps, rel=1e-10)
