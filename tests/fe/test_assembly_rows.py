"""The compiled row assembly (fe/rows.py, fe/_rows.c) against the NumPy path it replaces."""

from __future__ import annotations

import numpy as np
import pytest

from flexarm.fe import TetMesh, assemble, kernels, mass_matrix, rows, stiffness_matrix
from flexarm.fe import assembly as assembly_module
from flexarm.fe.errors import MeshError
from flexarm.fe.sparsity import NodePattern

pytestmark = pytest.mark.skipif(not rows.available(), reason="C extension _rows not built")


def numpy_path(mesh, material):
    """K, M by the chunked NumPy kernels and scatter (the compiled path switched off)."""
    asm = assembly_module._Assembler(mesh)
    asm.__dict__["plan"] = None  # cached_property: the NumPy branch is taken
    return asm.stiffness(material), asm.mass(material.rho)


@pytest.mark.parametrize("name", ["irregular_tet4", "irregular_tet10"])
def test_rows_equal_numpy_path(name, request, steel):
    """Same pattern exactly, values equal to 1e-14 of the largest entry (sum order differs)."""
    mesh = request.getfixturevalue(name)
    assert assembly_module._Assembler(mesh).plan is not None
    K, M = assemble(mesh, steel)
    K0, M0 = numpy_path(mesh, steel)
    for A, A0 in ((K, K0), (M, M0)):
        assert A.has_sorted_indices
        np.testing.assert_array_equal(A.indptr, A0.indptr)
        np.testing.assert_array_equal(A.indices, A0.indices)
        assert np.abs(A.data - A0.data).max() <= 1e-14 * np.abs(A0.data).max()
    # the single-matrix entry points take the same path
    np.testing.assert_array_equal(stiffness_matrix(mesh, steel).data, K.data)
    np.testing.assert_array_equal(mass_matrix(mesh, steel.rho).data, M.data)


def test_rows_deterministic_and_unit_tet_analytic(steel):
    """Bit-identical on a repeat; one element: K rows sum to zero, M sums to rho V."""
    mesh = TetMesh.unit_tet()
    K, M = assemble(mesh, steel)
    K2, M2 = assemble(mesh, steel)
    np.testing.assert_array_equal(K.data, K2.data)
    np.testing.assert_array_equal(M.data, M2.data)
    assert np.abs(K.sum(axis=1)).max() <= 1e-12 * np.abs(K.data).max()  # rigid translation
    assert M.sum() == pytest.approx(3 * steel.rho / 6.0, rel=1e-14)
    # Tet4 consistent mass: rho V / 10 on the diagonal, rho V / 20 off it (per component)
    np.testing.assert_allclose(M.diagonal(), steel.rho / 60.0, rtol=1e-14)
    assert M[0, 3] == pytest.approx(steel.rho / 120.0, rel=1e-14)


@pytest.mark.parametrize("name", ["irregular_tet4", "irregular_tet10"])
def test_row_plan_is_the_node_pattern(name, request):
    mesh = request.getfixturevalue(name)
    plan, pattern = rows.RowPlan.of(mesh), NodePattern.of(mesh)
    np.testing.assert_array_equal(plan.indptr, pattern.indptr)
    np.testing.assert_array_equal(plan.indices, pattern.indices)
    # every element node appears once under its node, in element order
    counts = np.bincount(mesh.tets.reshape(-1), minlength=mesh.n_nodes)
    np.testing.assert_array_equal(np.diff(plan.occ_ptr), counts)
    np.testing.assert_array_equal(mesh.tets.reshape(-1)[plan.occ], np.repeat(
        np.arange(mesh.n_nodes), counts))


def test_volumes_and_affinity_match_numpy(irregular_tet10, curved_tet10):
    np.testing.assert_allclose(rows.corner_volumes(irregular_tet10), irregular_tet10.volumes(),
                               rtol=1e-13)
    for mesh, straight in ((irregular_tet10, True), (curved_tet10, False)):
        dev, scale = rows.midside_deviation(mesh)
        corners = mesh.points[mesh.tets[:, kernels.TET10_EDGES]]
        ref = np.abs(mesh.points[mesh.tets[:, 4:]] - corners.mean(axis=2)).max()
        assert dev == pytest.approx(ref, rel=1e-14, abs=1e-15)
        assert kernels.is_affine(mesh) is straight
    # curved elements are assembled by the NumPy path
    assert assembly_module._Assembler(curved_tet10).plan is None


def test_inverted_element_still_refused(steel):
    mesh = TetMesh.box(divisions=(1, 1, 1))
    flipped = TetMesh(mesh.points, mesh.tets[:, [1, 0, 2, 3]])
    with pytest.raises(MeshError, match="6 inverted tetrahedra"):
        assemble(flipped, steel)


def test_short_buffer_is_a_value_error(irregular_tet4):
    plan = rows.RowPlan.of(irregular_tet4)
    with pytest.raises(ValueError, match="indices"):
        rows._rows.node_columns(irregular_tet4.tets, 4, plan.occ_ptr, plan.occ, plan.indptr,
                                np.empty(3, dtype=np.int32))


def test_without_extension_numpy_path_assembles(monkeypatch, irregular_tet4, steel):
    K, M = assemble(irregular_tet4, steel)
    monkeypatch.setattr(rows, "_rows", None)
    assert not rows.available()
    K0, M0 = assemble(irregular_tet4, steel)
    assert abs(K - K0).max() <= 1e-14 * abs(K0).max()
    assert abs(M - M0).max() <= 1e-14 * abs(M0).max()
