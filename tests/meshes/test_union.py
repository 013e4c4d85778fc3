"""One solid from pieces: overlaps count once, tangent contacts stay closed."""

from __future__ import annotations

import pytest
import trimesh

from flexarm.meshes.surface import load_surface
from flexarm.meshes.union import union

#: pi/2 to nine decimals, as URDF files write it: a hair off exact
HALF_PI_URDF = 1.570796327


def _cylinder(r, length, centre, along_y=False):
    m = trimesh.creation.cylinder(radius=r, height=length, sections=64)
    if along_y:
        m.apply_transform(trimesh.transformations.rotation_matrix(HALF_PI_URDF, [1, 0, 0]))
    m.apply_translation(centre)
    return m


def test_overlapping_boxes_count_once():
    a = trimesh.creation.box((1.0, 1.0, 1.0))
    b = trimesh.creation.box((1.0, 1.0, 1.0))
    b.apply_translation([0.5, 0.5, 0.0])
    u = union([a, b])
    assert u.is_volume and u.volume == pytest.approx(1.75, rel=1e-12)


@pytest.mark.parametrize("suffix", [".ply", ".stl"])
def test_tangent_pieces_stay_closed_through_a_file(tmp_path, suffix):
    """A hub across a bar whose side grazes the bar's end face (a UR-style wrist drawn
    with URDF primitives): the union leaves sub-nanometre edges where the surfaces are
    tangent, which a vertex merge on reading must not tear open."""
    bar = _cylinder(0.045, 0.078, [0.0, 0.099, 0.0], along_y=True)  # y 0.06 .. 0.138
    hub = _cylinder(0.045, 0.05, [0.0, 0.093, 0.025])  # its side touches y = 0.138
    u = union([bar, hub], "wrist")
    assert u.is_volume
    path = tmp_path / f"wrist{suffix}"
    u.export(path)
    back = load_surface(path)
    assert back.is_watertight and back.volume == pytest.approx(u.volume, rel=1e-6)
    # the exact volume: the bar plus the hub's half above the bar's axis plane, minus
    # the part of that half inside the bar (the hub stands on the bar's axis)
    assert u.volume > bar.volume and u.volume < bar.volume + hub.volume
