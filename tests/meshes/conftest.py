"""Fixtures of the meshes tests: a private cache folder and one real pytetwild mesh."""

from __future__ import annotations

import numpy as np
import pytest

from flexarm.fe.mesh import TetMesh
from flexarm.meshes.primitives import bar_surface

#: The small bar every real tetrahedralisation test meshes [m].
BAR = (0.2, 0.1, 0.05)
BAR_EDGE = 0.02


@pytest.fixture(autouse=True)
def private_cache(tmp_path, monkeypatch):
    """Every test caches into its own tmp folder, never the user's cache."""
    folder = tmp_path / "cache"
    monkeypatch.setenv("FLEXARM_CACHE", str(folder))
    return folder


@pytest.fixture(scope="session")
def bar():
    return bar_surface(*BAR)


@pytest.fixture(scope="session")
def bar_tets(bar) -> TetMesh:
    """One real pytetwild mesh of the bar (not cached: the session has no cache folder)."""
    from flexarm.meshes.tetwild import tetrahedralize

    return tetrahedralize(bar, BAR_EDGE, cache=False, name="bar")


def jiggled_box(order: int) -> TetMesh:
    """A small box mesh with non-round coordinates and two node sets."""
    mesh = TetMesh.box((0.3, 0.1, 0.07), (3, 2, 1), order=order)
    rng = np.random.default_rng(7)
    points = mesh.points * np.pi / 3 + rng.normal(scale=1e-4, size=mesh.points.shape)
    return TetMesh(points, mesh.tets, {"root": [0, 1, 2], "tip": np.arange(5, mesh.n_nodes, 7)})
