"""The cavity of a solid: the erosion against the exact convex offset, and the fallback
from the convex offset to the erosion when a face dips below the hull."""

from __future__ import annotations

import numpy as np
import pytest
import trimesh

from flexarm.meshes.hollow import hollow_surface
from flexarm.meshes.inward_offset import _Solid

from .test_hollow import _assert_closed_shell, _box_shell, _moved


def test_erosion_of_a_convex_box_is_exact():
    """Face prisms alone set the walls of a convex part: the erosion agrees with the
    exact offset (a cross-check of both constructions)."""
    box = _moved(trimesh.creation.box((0.5, 0.2, 0.1)))
    bodies = _Solid(box)._eroded_cavity(0.015, 24)
    assert len(bodies) == 1
    assert box.volume - bodies[0].volume == pytest.approx(
        _box_shell((0.5, 0.2, 0.1), 0.015), rel=1e-9)


def _folded_cube(h: float) -> trimesh.Trimesh:
    """Unit cube whose corner (1, 1, 1) is raised by ``h``, its top split along the
    *concave* diagonal: every vertex on the hull, the fold h / 2 below it."""
    v = np.array([[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0],
                  [0, 0, 1], [1, 0, 1], [1, 1, 1 + h], [0, 1, 1]], dtype=float)
    f = np.array([[0, 2, 1], [0, 3, 2], [0, 1, 5], [0, 5, 4], [1, 2, 6], [1, 6, 5],
                  [2, 3, 7], [2, 7, 6], [3, 0, 4], [3, 4, 7], [4, 5, 7], [5, 6, 7]])
    return trimesh.Trimesh(v, f, process=False)


def test_convex_looking_surface_with_a_deep_face_falls_back_to_erosion():
    surface = _folded_cube(2e-4)
    assert surface.is_watertight and surface.volume > 0
    solid = _Solid(surface)
    assert solid.is_convex  # by its vertices and volume
    thin = hollow_surface(surface, 5e-5)  # the fold (1e-4 deep) would cut the cavity
    thick = hollow_surface(surface, 0.1)
    assert (thin.method, thick.method) == ("erosion", "convex")
    for shell in (thin, thick):
        _assert_closed_shell(shell, surface)
    assert thick.volume == pytest.approx(1 - 0.8**3, rel=1e-3)
    assert thin.volume == pytest.approx(6 * 5e-5, rel=1e-3)
