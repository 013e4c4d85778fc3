"""Dihedral angles, radius ratios and the QualityReport against hand-computed values."""

from __future__ import annotations

import numpy as np
import pytest

from flexarm.fe.mesh import TET10_EDGES, TetMesh
from flexarm.meshes import QualityReport, dihedral_angles, mesh_quality, radius_ratios
from flexarm.meshes.primitives import bar_surface

REGULAR = np.array([[1, 1, 1], [1, -1, -1], [-1, 1, -1], [-1, -1, 1]], dtype=float)


def test_regular_tet():
    tets = np.array([[0, 2, 1, 3]])
    np.testing.assert_allclose(dihedral_angles(REGULAR, tets), np.degrees(np.arccos(1 / 3)))
    np.testing.assert_allclose(radius_ratios(REGULAR, tets), 1.0, rtol=1e-14)


def test_unit_tet():
    m = TetMesh.unit_tet()
    angles = np.sort(dihedral_angles(m.points, m.tets)[0])
    np.testing.assert_allclose(angles, [np.degrees(np.arccos(1 / np.sqrt(3)))] * 3 + [90] * 3)
    np.testing.assert_allclose(radius_ratios(m.points, m.tets), np.sqrt(3) - 1, rtol=1e-14)


def test_flat_and_inverted_tets():
    flat = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [1, 1, 0]], dtype=float)
    assert radius_ratios(flat, np.array([[0, 1, 2, 3]]))[0] == 0.0
    assert dihedral_angles(flat, np.array([[0, 1, 2, 3]])).min() == pytest.approx(0.0, abs=1e-6)
    m = TetMesh.unit_tet()
    assert radius_ratios(m.points, m.tets[:, [0, 2, 1, 3]])[0] == pytest.approx(1 - np.sqrt(3))


def _dihedral_by_edges(p):
    """Independent reference: angle between the other two corners seen along each edge."""
    out = []
    for i, j in TET10_EDGES:
        k, m = (c for c in range(4) if c not in (i, j))
        e = (p[j] - p[i]) / np.linalg.norm(p[j] - p[i])
        u = p[k] - p[i] - np.dot(p[k] - p[i], e) * e
        v = p[m] - p[i] - np.dot(p[m] - p[i], e) * e
        out.append(np.degrees(np.arccos(np.dot(u, v) / np.linalg.norm(u) / np.linalg.norm(v))))
    return out


def test_dihedral_matches_independent_formula_on_random_tets():
    rng = np.random.default_rng(3)
    points = rng.normal(size=(40, 3))
    tets = np.arange(40).reshape(10, 4)
    angles = dihedral_angles(points, tets)
    for t in range(10):
        np.testing.assert_allclose(angles[t], _dihedral_by_edges(points[tets[t]]), atol=1e-9)


def test_report_of_structured_box_and_surface():
    mesh = TetMesh.box((1.0, 0.5, 0.25), (8, 4, 2))
    report = mesh_quality(mesh, bar_surface(1.0, 0.5, 0.25))
    assert isinstance(report, QualityReport)
    assert (report.n_nodes, report.n_tets, report.order) == (9 * 5 * 3, 6 * 64, 1)
    assert report.volume == pytest.approx(0.125, rel=1e-14)
    assert abs(report.volume_error) < 1e-13
    assert report.min_dihedral_deg == pytest.approx(45.0)  # Kuhn tets: 45, 60, 90 deg
    assert 0 < report.min_radius_ratio <= report.mean_radius_ratio < 1
    assert report.n_slivers == 0
    table = report.table()
    assert "384 Tet4" in table and "0.125 m^3" in table and len(table.splitlines()) == 6


def test_tet10_report_uses_corners():
    mesh = TetMesh.box((1.0, 0.5, 0.25), (4, 2, 1))
    r1, r2 = mesh_quality(mesh), mesh_quality(mesh.to_tet10())
    assert r2.order == 2 and r2.n_nodes > r1.n_nodes
    assert r2.min_dihedral_deg == r1.min_dihedral_deg and r2.volume == r1.volume
    assert r2.volume_error is None and "Tet10" in r2.table()


def test_slivers_counted():
    points = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0.5, 0.5, 0.01]], dtype=float)
    report = mesh_quality(TetMesh(points, [[0, 1, 2, 3]]))
    assert report.n_slivers == 1 and report.min_dihedral_deg < 2


def test_empty_mesh_rejected():
    with pytest.raises(ValueError, match="at least one element"):
        mesh_quality(TetMesh(np.zeros((0, 3)), np.zeros((0, 4), dtype=int)))
