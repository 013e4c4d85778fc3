"""mesh_part: file in millimetres -> metres tetrahedra + quality report."""

from __future__ import annotations

import numpy as np
import pytest

import flexarm.meshes.pipeline as pipeline
from flexarm.fe.mesh import TetMesh
from flexarm.meshes import QualityReport, mesh_part, write_surface
from flexarm.meshes.primitives import bar_surface, hollow_link_surface


def test_mm_stl_to_checked_tets(tmp_path, private_cache):
    path = tmp_path / "bar_mm.stl"
    write_surface(path, bar_surface(200.0, 100.0, 50.0))  # millimetres
    messages = []
    mesh, report = mesh_part(path, units="mm", size=0.025, progress=messages.append)
    assert isinstance(report, QualityReport)
    assert report.n_tets == mesh.n_tets and report.order == 1
    np.testing.assert_allclose(mesh.bounds(), [[0, 0, 0], [0.2, 0.1, 0.05]], atol=3e-4)
    assert abs(report.volume_error) < 1e-3 and report.volume == pytest.approx(1e-3, rel=1e-3)
    assert report.n_slivers == 0 and (mesh.volumes() > 0).all()
    assert str(path) in messages[0]
    assert len(list((private_cache / "tets").glob("*.npz"))) == 1


def test_default_size_is_a_twentieth_of_the_diagonal(tmp_path, monkeypatch):
    seen = {}

    def fake(surface, size, **kwargs):
        seen["size"] = size
        return TetMesh.box((0.2, 0.1, 0.05), (2, 1, 1), order=kwargs["order"])

    monkeypatch.setattr(pipeline, "tetrahedralize", fake)
    path = tmp_path / "bar.stl"
    write_surface(path, bar_surface(0.2, 0.1, 0.05))
    mesh, report = mesh_part(path, order=2)
    assert seen["size"] == pytest.approx(0.05 * np.sqrt(0.2**2 + 0.1**2 + 0.05**2), rel=1e-6)
    assert report.order == 2 and abs(report.volume_error) < 1e-6


@pytest.mark.slow
def test_hollow_link_meshes(tmp_path):
    path = tmp_path / "link.stl"
    write_surface(path, hollow_link_surface())
    mesh, report = mesh_part(path, size=0.03, order=2, cache=False)
    assert abs(report.volume_error) < 5e-3 and report.n_slivers == 0
    assert report.min_dihedral_deg > 5 and mesh.order == 2
