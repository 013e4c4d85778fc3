"""Element kernels: strain energy of a uniform strain = V (lambda tr(eps)^2 + 2 mu eps:eps), six
rigid modes per element, K ~ L and M ~ L^3, rotation covariance, the Tet4 mass V (1 + delta)/20,
affinity detection, scatter layout and chunks."""

from __future__ import annotations

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

from flexarm.fe import MATERIALS, Tet4, Tet10, TetMesh
from flexarm.fe.kernels import (
    element_mass,
    element_stiffness,
    element_type,
    is_affine,
    mass_kernel,
    stiffness_blocks,
    stiffness_kernel,
)

STEEL = MATERIALS["steel"]


def _distorted_tet(order: int) -> TetMesh:
    pts = np.array([[0.1, 0.0, 0.05], [1.2, 0.1, -0.1], [0.3, 0.9, 0.2], [0.2, 0.3, 1.1]])
    mesh = TetMesh(pts, [[0, 1, 2, 3]])
    if order == 1:
        return mesh
    t10 = mesh.to_tet10()  # renumbered so that node a of the element is point a
    return TetMesh(t10.points[t10.tets[0]], [np.arange(10)])


def _rigid_modes(points):
    out = np.zeros((len(points), 3, 6))
    for i in range(3):
        out[:, i, i] = 1.0
        out[:, :, 3 + i] = np.cross(np.eye(3)[i], points)
    return out.reshape(-1, 6)


@pytest.mark.parametrize("order", [1, 2])
@pytest.mark.parametrize("affine", [True, False])
def test_uniform_strain_energy(order, affine):
    """u = eps x: u^T K u = V (lambda tr(eps)^2 + 2 mu eps:eps), on both code paths."""
    mesh = _distorted_tet(order)
    rng = np.random.default_rng(order)
    A = rng.normal(size=(3, 3)) * 1e-3
    eps = 0.5 * (A + A.T)
    u = (mesh.points @ A.T).ravel()  # the skew part of A is a rigid rotation: no energy
    K = stiffness_blocks(mesh, STEEL, affine=affine)[0].transpose(0, 2, 1, 3).reshape(
        3 * mesh.n_nodes, 3 * mesh.n_nodes)
    V = mesh.volumes()[0]
    lam, mu = STEEL.lame_lambda, STEEL.lame_mu
    expected = V * (lam * np.trace(eps) ** 2 + 2 * mu * np.sum(eps * eps))
    assert u @ K @ u == pytest.approx(expected, rel=1e-11)


@pytest.mark.parametrize("order, rank", [(1, 6), (2, 24)])
def test_element_stiffness_symmetric_with_six_rigid_modes(order, rank):
    mesh = _distorted_tet(order)
    K = element_stiffness(mesh, STEEL)[0]
    assert K.shape == (3 * mesh.n_nodes,) * 2
    np.testing.assert_allclose(K, K.T, rtol=0, atol=1e-12 * np.abs(K).max())
    np.testing.assert_allclose(K @ _rigid_modes(mesh.points), 0.0, atol=1e-9 * np.abs(K).max())
    lam = np.linalg.eigvalsh(K)
    assert np.all(lam > -1e-9 * lam[-1])
    assert int((lam > 1e-9 * lam[-1]).sum()) == rank


@pytest.mark.parametrize("order", [1, 2])
def test_size_scaling_and_rotation_covariance(order):
    """K scales with length, M with length^3; turning the element turns K: Q K Q^T."""
    mesh = _distorted_tet(order)
    K, M = element_stiffness(mesh, STEEL)[0], element_mass(mesh, STEEL.rho)[0]
    np.testing.assert_allclose(element_stiffness(mesh.scaled(2.5), STEEL)[0], 2.5 * K,
                               rtol=1e-12, atol=1e-12 * np.abs(K).max())
    np.testing.assert_allclose(element_mass(mesh.scaled(2.5), STEEL.rho)[0], 2.5**3 * M,
                               rtol=1e-12)
    R = Rotation.from_rotvec([0.3, -1.1, 0.6]).as_matrix()
    turned = TetMesh(mesh.points @ R.T + [1.0, 2.0, 3.0], mesh.tets)
    Q = np.kron(np.eye(mesh.n_nodes), R)
    np.testing.assert_allclose(element_stiffness(turned, STEEL)[0], Q @ K @ Q.T,
                               rtol=0, atol=1e-11 * np.abs(K).max())
    np.testing.assert_allclose(element_mass(turned, STEEL.rho)[0], M, rtol=1e-12)


def test_tet4_consistent_mass_by_hand():
    mesh = _distorted_tet(1)
    V = mesh.volumes()[0]
    np.testing.assert_allclose(element_mass(mesh, 7850.0)[0], 7850.0 * V * (1 + np.eye(4)) / 20,
                               rtol=1e-13)


def test_tet10_mass_lumps_negative_at_corners():
    """Row sums of the Tet10 consistent mass: rho int N_a = -rho V/20 (corner), rho V/5 (mid)."""
    mesh = _distorted_tet(2)
    V = mesh.volumes()[0]
    np.testing.assert_allclose(element_mass(mesh, 1000.0)[0].sum(axis=1),
                               1000.0 * V * np.r_[[-1 / 20] * 4, [1 / 5] * 6], rtol=1e-12)


def test_affinity_and_element_type():
    straight = _distorted_tet(2)
    assert is_affine(straight) and is_affine(_distorted_tet(1))
    pts = straight.points.copy()
    pts[7] += [0.0, 0.0, 1e-3]  # move one mid-edge node off its edge
    curved = TetMesh(pts, straight.tets)
    assert not is_affine(curved)
    assert element_type(straight) is Tet10 and element_type(_distorted_tet(1)) is Tet4
    # the curved element still has its six rigid modes
    K = element_stiffness(curved, STEEL)[0]
    np.testing.assert_allclose(K @ _rigid_modes(curved.points), 0.0, atol=1e-9 * np.abs(K).max())


@pytest.mark.parametrize("order", [1, 2])
def test_scatter_layout_chunks_and_buffer(order):
    mesh = TetMesh.box((1.0, 0.5, 0.5), (2, 1, 1), order=order)
    nn = mesh.tets.shape[1]
    kern = stiffness_kernel(mesh, STEEL)
    assert kern.shape == (nn, nn, mesh.n_tets, 3, 3) and kern.flags.c_contiguous
    blocks = stiffness_blocks(mesh, STEEL)
    np.testing.assert_array_equal(kern.transpose(2, 0, 1, 3, 4), blocks)
    np.testing.assert_allclose(stiffness_blocks(mesh, STEEL, slice(3, 8)), blocks[3:8],
                               rtol=1e-14, atol=1e-14 * np.abs(blocks).max())
    buffer = np.full(nn * nn * mesh.n_tets * 9 + 5, np.nan)  # reused, larger than needed
    np.testing.assert_array_equal(stiffness_kernel(mesh, STEEL, out=buffer), kern)
    m = mass_kernel(mesh, 3.0)
    assert m.shape == (nn, nn, mesh.n_tets)
    np.testing.assert_array_equal(m.transpose(2, 0, 1), element_mass(mesh, 3.0))
    assert element_mass(mesh, 3.0).sum() == pytest.approx(3.0 * 0.25, rel=1e-13)
