"""Cache keys and entries of tetrahedralisations."""

from __future__ import annotations

import dataclasses

import numpy as np

from flexarm.fe.cache import cached, lookup
from flexarm.fe.mesh import TetMesh
from flexarm.meshes import tolerances
from flexarm.meshes.tet_cache import TET_CODEC, cached_mesh, tet_cache_key

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
