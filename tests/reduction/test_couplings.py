import numpy as np
import pytest
import scipy.linalg as sla
from reduction_helpers import STEEL

from flexarm.fe import TetMesh
from flexarm.reduction.couplings import (
    couple,
    farthest_points,
    rbe3_weights_matrix,
    rigid_transport,
    tributary_areas,
)
from flexarm.reduction.interfaces import interfaces
from flexarm.reduction.reduce import coupled_model


def test_tributary_areas_tet4_and_tet10():
    for order in (1, 2):
        mesh = TetMesh.box((1.0, 2.0, 3.0), (2, 2, 3), order=order)
        a = tributary_areas(mesh)
        assert np.isclose(a.sum(), 2 * (2 + 3 + 6))
        assert np.all(a[mesh.boundary_nodes()] > 0)
        interior = np.setdiff1d(np.arange(mesh.n_nodes), mesh.boundary_nodes())
        assert np.all(a[interior] == 0)


def test_farthest_points_spread_and_deterministic():
    pts = np.random.default_rng(1).random((50, 3))
    a, b = farthest_points(pts, 8), farthest_points(pts, 8)
    assert np.array_equal(a, b) and len(set(a.tolist())) == 8


def test_rbe3_fit_reproduces_rigid_motion():
    pts = np.random.default_rng(2).random((7, 3))
    w = np.random.default_rng(3).random(7) + 0.1
    ref = np.array([0.3, -0.2, 0.5])
    q = np.array([1e-3, -2e-3, 3e-4, 0.01, -0.02, 0.005])
    u = rigid_transport(pts - ref) @ q
    assert np.allclose(rbe3_weights_matrix(pts, w, ref) @ u.ravel(), q, rtol=1e-12)


@pytest.mark.parametrize("kind", ["rbe2", "rbe3"])
def test_rigid_master_motion_is_rigid_body(bar, kind):
    mesh, regions, _ = bar
    c = couple(mesh, interfaces(mesh, regions[:1]), kind)
    ref = c.node_positions[0]
    q = np.array([1e-3, 2e-3, -1e-3, 0.02, -0.01, 0.03])
    u_rigid = (rigid_transport(mesh.points - ref) @ q).ravel()
    # Coupled coordinates of the rigid motion: interior FE DOFs keep their values.
    x = np.linalg.lstsq(c.T.toarray(), u_rigid, rcond=None)[0]
    assert np.allclose(x[-6:], q, rtol=1e-10, atol=1e-14)
    assert np.allclose(c.T @ x, u_rigid, atol=1e-14)


def test_rbe3_adds_no_stiffness(tiny_bar):
    """RBE3 is only a change of variables: the coupled free spectrum is the FE one."""
    mesh, regions, (K, M) = tiny_bar
    model = coupled_model(mesh, STEEL, regions, "rbe3", matrices=(K, M))
    assert model.K.shape == K.shape  # 6 dependent slave DOFs traded for 6 master DOFs
    w_fe = sla.eigh(K.toarray(), M.toarray(), eigvals_only=True)
    w_c = sla.eigh(model.K.toarray(), model.M.toarray(), eigvals_only=True)
    assert np.allclose(w_c[6:], w_fe[6:], rtol=1e-9)


def test_rbe3_master_is_weighted_average(bar):
    mesh, regions, _ = bar
    ifs = interfaces(mesh, regions[:1])
    c = couple(mesh, ifs, "rbe3")
    x = np.random.default_rng(4).standard_normal(c.n_coupled)
    u = (c.T @ x).reshape(-1, 3)
    nodes = ifs[0].nodes
    W = rbe3_weights_matrix(mesh.points[nodes], tributary_areas(mesh)[nodes], ifs[0].position)
    assert np.allclose(W @ u[nodes].ravel(), x[-6:], rtol=1e-10)


def test_rbe2_eliminates_all_slaves_and_nodes_keep_masters(bar):
    mesh, regions, _ = bar
    ifs = interfaces(mesh, regions)
    c2 = couple(mesh, ifs, "rbe2")
    assert c2.n_coupled == mesh.n_dofs - 3 * 18 + 12 and c2.n_boundary == 12
    ck = couple(mesh, ifs, "nodes", n_masters=4)
    assert ck.n_boundary == 2 * 4 * 3 and ck.dofs_per_node == 3
    assert np.array_equal(ck.node_interface, [0] * 4 + [1] * 4)
    call = couple(mesh, ifs, "nodes")
    assert call.n_boundary == 3 * 18 and call.n_coupled == mesh.n_dofs
    with pytest.raises(ValueError, match="coupling must be one of"):
        couple(mesh, ifs, "rbe9")
