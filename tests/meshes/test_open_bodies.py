"""Open published surfaces made solid: small holes patched within the tolerance, an open
body replaced by its convex hull (stated in one line naming the file), nothing else."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest
import trimesh

from flexarm.fe.errors import MeshError
from flexarm.meshes.open_bodies import MAX_FILLED_AREA, close_open_surface, is_closed
from flexarm.meshes.repair import check_surface

FOREARM = Path("/work/shared/data/robots/ur10/meshes/collision/forearm.stl")


def _open_tube_on_a_box(sections: int = 32):
    """A tube r 50 mm, 0.4 m long (z -0.2..0.2) without end caps, standing on a closed
    box 0.2 x 0.2 x 0.05 m whose top face is the tube's lower end (z = -0.2)."""
    tube = trimesh.creation.cylinder(0.05, 0.4, sections=sections)
    side = np.abs(tube.face_normals[:, 2]) < 0.5
    box = trimesh.creation.box((0.2, 0.2, 0.05))
    box.apply_translation((0.0, 0.0, -0.225))
    return trimesh.util.concatenate([trimesh.Trimesh(tube.vertices, tube.faces[side]), box])


def test_a_closed_surface_is_only_repaired():
    ball = trimesh.creation.icosphere(3, 0.1)
    res = close_open_surface(ball, "ball.stl")
    assert (res.n_open, res.hulled, res.note) == (0, 0, "")
    assert res.mesh.volume == pytest.approx(ball.volume, rel=1e-12)


def test_an_open_tube_becomes_its_hull_and_the_note_says_so():
    res = close_open_surface(_open_tube_on_a_box(), "forearm.stl")
    check_surface(res.mesh, "united")  # closed, manifold, outward
    assert (res.n_bodies, res.n_open, res.hulled) == (2, 1, 1)
    rod = 0.5 * 32 * 0.05**2 * math.sin(2 * math.pi / 32) * 0.4  # the 32-gon prism
    assert res.mesh.volume == pytest.approx(0.2 * 0.2 * 0.05 + rod, rel=1e-9)
    assert res.hull_share == pytest.approx(rod / res.mesh.volume, rel=1e-9)
    # one line, the user's file first, the tolerance and the fallback stated
    assert "\n" not in res.note and res.note.startswith("forearm.stl: not a closed surface "
                                                        "(2 bodies, 1 open, 64 boundary edges)")
    assert f"more than the {MAX_FILLED_AREA:.0%} a repair may" in res.note
    assert "replaced by its convex hull (61% of the solid's volume)" in res.note


def test_a_small_many_sided_hole_is_patched_not_hulled():
    """Six triangles around one vertex of a 1280-face ball: a hexagonal hole (0.5 % of
    the area) that the repair's own filler leaves open, closed by a flat fan."""
    ball = trimesh.creation.icosphere(3, 0.1)
    around = np.any(ball.faces == 0, axis=1)
    holed = trimesh.Trimesh(ball.vertices, ball.faces[~around])
    assert int(around.sum()) in (5, 6) and not is_closed(holed)
    res = close_open_surface(holed, "ball.stl")
    check_surface(res.mesh, "patched")
    assert (res.n_open, res.hulled) == (1, 0)
    assert 0 < res.filled_share < MAX_FILLED_AREA
    # a fan to the hole's centroid cuts off the cap of the missing vertex: < 0.1 %
    assert res.mesh.volume == pytest.approx(ball.volume, rel=1e-3)
    assert "holes closed by flat patches" in res.note


def test_a_flat_sheet_alone_is_refused():
    sheet = trimesh.Trimesh([[0, 0, 0], [1, 0, 0], [0, 1, 0], [1, 1, 0]], [[0, 1, 2], [1, 3, 2]])
    with pytest.raises(MeshError, match=r"^sheet\.stl: no closed body and no open one"):
        close_open_surface(sheet, "sheet.stl")


@pytest.mark.skipif(not FOREARM.is_file(), reason="no published UR10 data")
def test_the_published_ur10_forearm():
    """Seven bodies as published (one a flat sliver): the tube open at one end is
    hulled; the housings stay as they are."""
    m = trimesh.load(FOREARM, process=False)
    assert not is_closed(m, FOREARM.name)
    res = close_open_surface(m, FOREARM.name)
    check_surface(res.mesh, "forearm")
    assert (res.n_bodies, res.n_open, res.hulled) == (6, 1, 1)
    assert res.mesh.volume == pytest.approx(5.140e-3, rel=1e-3)
    assert res.hull_share == pytest.approx(0.52, abs=0.01)
    assert res.note.startswith("forearm.stl: not a closed surface (6 bodies, 1 open, "
                               "65 boundary edges); closing its holes would add 1.9% of its "
                               "area")
