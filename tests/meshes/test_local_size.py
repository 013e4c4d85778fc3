"""Local sizes: Gmsh refines a coarse mesh over a small disc (a seat) and nowhere far from
it, the same bytes every run, under its own cache key."""

from __future__ import annotations

import math

import numpy as np
import pytest

from flexarm.meshes import cached_surface_mesh, mesh_surface, tetrahedralize_gmsh
from flexarm.meshes.local_size import GRADING, LocalSize, local_size_at, local_sizes_key
from flexarm.meshes.primitives import bar_surface

try:  # the wheel's libgmsh needs system GL/X libraries: OSError if they are missing
    import gmsh  # noqa: F401
except (ImportError, OSError):
    pytest.skip("gmsh is not importable", allow_module_level=True)

#: a 0.4 m bar of 0.1 x 0.1 m meshed at 50 mm; the "seat": a disc of 30 mm radius on
#: its end face x = 0.4 m, refined to 10 mm
LENGTH, H, R, FINE = 0.4, 0.05, 0.03, 0.01
SEAT = LocalSize((LENGTH, 0.05, 0.05), (1.0, 0.0, 0.0), R, 0.002, FINE)
#: area per surface node of equilateral triangles of edge h, in h^2
NODE_AREA = math.sqrt(3.0) / 2.0


def _on_disc(mesh, x: float) -> int:
    p = mesh.points[mesh.boundary_nodes()]
    return int(((np.abs(p[:, 0] - x) < 1e-9)
                & (np.hypot(p[:, 1] - 0.05, p[:, 2] - 0.05) <= R)).sum())


@pytest.fixture(scope="module")
def bar():
    return bar_surface(LENGTH, 0.1, 0.1)


def test_the_disc_gets_the_nodes_of_its_local_edge_and_the_far_end_keeps_the_coarse_one(bar):
    coarse = tetrahedralize_gmsh(bar, H, cache=False)
    fine = tetrahedralize_gmsh(bar, H, cache=False, local_sizes=(SEAT,))
    flat = math.pi * R**2 / (NODE_AREA * FINE**2)  # 32.6 nodes on a flat disc at 10 mm
    assert _on_disc(coarse, LENGTH) <= 5
    assert 0.8 * flat <= _on_disc(fine, LENGTH) <= 1.3 * flat
    # the grading reaches 0.05 m (the global edge) 80 mm from the disc: the end x = 0
    # is as coarse as without the local size
    assert _on_disc(fine, 0.0) == _on_disc(coarse, 0.0)
    assert fine.volumes().sum() == pytest.approx(LENGTH * 0.01, rel=1e-12)


def test_the_same_local_sizes_give_the_same_bytes(bar):
    a = tetrahedralize_gmsh(bar, H, cache=False, local_sizes=(SEAT,))
    b = tetrahedralize_gmsh(bar, H, cache=False, local_sizes=(SEAT,))
    assert np.array_equal(a.points, b.points) and np.array_equal(a.tets, b.tets)


def test_local_sizes_have_their_own_cache_entry_and_none_keep_the_old_one(bar):
    assert local_sizes_key(()) == ()
    plain = mesh_surface(bar, H, "gmsh")
    assert cached_surface_mesh(bar, H, "gmsh") is not None
    assert cached_surface_mesh(bar, H, "gmsh", local_sizes=(SEAT,)) is None
    refined = mesh_surface(bar, H, "auto", local_sizes=(SEAT,))
    assert refined.mesher == "gmsh" and refined.mesh.n_nodes > plain.mesh.n_nodes
    again = cached_surface_mesh(bar, H, "auto", local_sizes=(SEAT,))
    assert again is not None and np.array_equal(again.mesh.points, refined.mesh.points)


def test_the_size_grows_from_the_cylinder_by_the_grading():
    c = LocalSize((0.0, 0.0, 0.0), (0.0, 0.0, 1.0), 0.1, 0.02, 0.01)
    assert local_size_at([c], 0.0, 0.05, 0.0, 1.0) == 0.01  # inside
    # 0.3 m out radially and 0.4 m axially: 0.5 m away
    assert local_size_at([c], 0.4, 0.0, 0.42, 1.0) == pytest.approx(0.01 + GRADING * 0.5)
    assert local_size_at([c], 10.0, 0.0, 0.0, 0.05) == 0.05  # never coarser than asked
    with pytest.raises(ValueError, match="unit"):
        LocalSize((0, 0, 0), (0, 0, 2), 0.1, 0.02, 0.01)
