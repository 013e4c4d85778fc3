"""Cache keys and entries of tetrahedralisations."""

from __future__ import annotations

import dataclasses
import re

import numpy as np
import pytest

from flexarm.fe.cache import cached, lookup
from flexarm.fe.errors import MeshError
from flexarm.fe.mesh import TetMesh
from flexarm.meshes import tolerances
from flexarm.meshes.tet_cache import (
    TET_CODEC,
    cached_mesh,
    cached_tetrahedralization,
    estimated_tets,
    tet_cache_key,
)

V = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]], dtype=float)
F = np.array([[0, 2, 1], [0, 1, 3], [1, 2, 3], [0, 3, 2]])


def test_key_depends_on_every_input(monkeypatch):
    base = tet_cache_key(V, F, 0.1, True, 1)
    assert base == tet_cache_key(V.astype(np.float32), F.astype(np.int32), 0.1, True, 1)
    moved = V.copy()
    moved[3, 2] += 1e-12
    others = {
        tet_cache_key(moved, F, 0.1, True, 1),
        tet_cache_key(V, F[:, ::-1], 0.1, True, 1),
        tet_cache_key(V, F, 0.1000001, True, 1),
        tet_cache_key(V, F, 0.1, False, 1),
        tet_cache_key(V, F, 0.1, True, 2),
        tet_cache_key(V, F, 0.1, True, 1, mesher="gmsh"),
    }
    stricter = dataclasses.replace(tolerances.tol, sliver_dihedral_deg=10.0)
    monkeypatch.setattr("flexarm.meshes.tet_cache.tol", stricter)
    others.add(tet_cache_key(V, F, 0.1, True, 1))
    assert base not in others and len(others) == 7


def test_key_depends_on_the_mesher_version(monkeypatch):
    from flexarm.fe import cache

    base = tet_cache_key(V, F, 0.1, True, 1)
    real = cache.library_versions

    def bumped(libraries=()):
        return tuple((n, v + ".post1" if n == "pytetwild" else v) for n, v in real(libraries))

    monkeypatch.setattr(cache, "library_versions", bumped)
    assert tet_cache_key(V, F, 0.1, True, 1) != base


def test_store_then_load(private_cache):
    mesh = TetMesh.box((1.0, 1.0, 1.0), (2, 1, 1), order=2)
    key = tet_cache_key(V, F, 0.1, True, 2)
    assert cached_mesh(key) is None
    entry = cached("tets", key, lambda: mesh, TET_CODEC)
    assert not entry.is_hit and entry.path.parent == private_cache / "tets"
    back = cached_mesh(key)
    np.testing.assert_array_equal(back.points, mesh.points)
    np.testing.assert_array_equal(back.tets, mesh.tets)


def test_inverted_entry_is_discarded(private_cache):
    mesh = TetMesh.unit_tet()
    key = "k" * 64
    entry = cached("tets", key, lambda: TetMesh(mesh.points, mesh.tets[:, [0, 2, 1, 3]]),
                   TET_CODEC)
    assert lookup("tets", key, TET_CODEC) is None and not entry.path.exists()


def _box_maker(calls):
    def make(vertices, faces, report):  # a deterministic stand-in for the mesher
        calls.append(1)
        return TetMesh.box((0.2, 0.1, 0.05), (4, 2, 1))
    return make


@pytest.mark.parametrize("size, message", [
    (1e-5, "edge 1e-05 m on a part of 0.001 m^3 gives about 8.5e+12 tetrahedra (limit "
           "2e+06, about 1.7e+07 GB to mesh): use an edge of at least 0.0016 m"),
    (0.5, "edge 0.5 m is larger than the part (0.2 m across)"),
])
def test_hopeless_edge_is_refused_before_meshing(size, message):
    from flexarm.meshes.primitives import bar_surface

    calls = []
    with pytest.raises(MeshError, match=re.escape(f"bar: {message}")):
        cached_tetrahedralization(bar_surface(0.2, 0.1, 0.05), size, True, 1, True, "bar",
                                  None, _box_maker(calls))
    assert not calls


def test_estimate_is_a_lower_bound_of_real_meshes(bar, bar_tets):
    estimate = estimated_tets(bar.volume, 0.02)  # the BAR_EDGE of bar_tets
    assert estimate < bar_tets.n_tets < 2 * estimate


def test_truncated_npz_with_a_valid_checksum_heals_to_a_clean_build(private_cache, caplog):
    from flexarm.fe.files import file_digest
    from flexarm.meshes.primitives import bar_surface

    surface, calls = bar_surface(0.2, 0.1, 0.05), []

    def mesh():
        return cached_tetrahedralization(surface, 0.05, True, 1, True, "bar", None,
                                         _box_maker(calls))

    clean = mesh()
    (path,) = (private_cache / "tets").glob("*.npz")
    path.write_bytes(path.read_bytes()[:300])  # a BadZipFile, which the checksum vouches for
    path.with_name(path.name + ".sha256").write_text(file_digest(path))
    with caplog.at_level("WARNING"):
        healed = mesh()
    assert "is damaged" in caplog.text and str(path) in caplog.text and len(calls) == 2
    np.testing.assert_array_equal(healed.points, clean.points)
    np.testing.assert_array_equal(healed.tets, clean.tets)
    assert mesh().n_tets == clean.n_tets and len(calls) == 2
