"""repair_surface / check_surface on in-memory surfaces."""

from __future__ import annotations

import numpy as np
import pytest

from flexarm.fe.errors import MeshError
from flexarm.meshes import check_surface, repair_surface
from flexarm.meshes.primitives import bar_surface


def test_clean_surface_needs_no_repair():
    bar = bar_surface(0.2, 0.1, 0.05)
    fixed, notes = repair_surface(bar)
    assert notes == ()
    np.testing.assert_array_equal(fixed.faces, bar.faces)


def test_repair_does_not_touch_its_input():
    bar = bar_surface(0.2, 0.1, 0.05)
    bar.invert()
    before = bar.faces.copy()
    fixed, notes = repair_surface(bar)
    np.testing.assert_array_equal(bar.faces, before)
    assert bar.volume == pytest.approx(-1e-3)
    assert fixed.volume == pytest.approx(1e-3)
    assert notes == ("inverted the normals (they pointed inward)",)


def test_degenerate_face_removed():
    bar = bar_surface(0.2, 0.1, 0.05)
    faces = np.vstack([bar.faces, [[0, 0, 1]]])
    soup = type(bar)(bar.vertices, faces, process=False)
    fixed, notes = repair_surface(soup)
    assert len(fixed.faces) == 12
    assert "removed 1 degenerate face" in notes[0]
    check_surface(fixed)


def test_check_names_the_part():
    bar = bar_surface(0.2, 0.1, 0.05)
    bar.update_faces(np.arange(10))
    with pytest.raises(MeshError, match=r"^arm.stl: the surface is open \(4 boundary edges\)"):
        check_surface(bar, "arm.stl")
