"""The level-set cavity and hollowing of CAD made of overlapping bodies (the UR10's)."""

from __future__ import annotations

import numpy as np
import pytest
import trimesh

from flexarm.meshes import hollow_surface
from flexarm.meshes.level_set_cavity import GRID_PER_WALL, level_set_cavity
from flexarm.meshes.self_intersections import crossings


def _box(extent, centre=(0.0, 0.0, 0.0)) -> trimesh.Trimesh:
    return trimesh.creation.box(extent, trimesh.transformations.translation_matrix(centre))


def _distance_to_box(points, half) -> np.ndarray:
    """Distance [m] of points inside an origin-centred box of half extents ``half``."""
    return (np.asarray(half) - np.abs(points)).min(axis=1)


def test_box_cavity_lies_one_wall_inside_with_its_volume():
    t, half = 0.01, np.array([0.2, 0.1, 0.05])
    (cavity,) = level_set_cavity(_box(2 * half), t)
    assert cavity.is_volume
    depth = _distance_to_box(cavity.vertices, half)
    # on the faces exactly one wall deep; edges rounded inwards, never outwards
    assert np.median(depth) == pytest.approx(t, rel=1e-6)
    assert depth.min() > t * (1 - 1e-6)
    exact = np.prod(2 * (half - t))
    # rounded convex edges: within a grid step's share of the area
    assert 0.99 * exact < cavity.volume <= exact * (1 + 1e-9)


def test_overlapping_bodies_hollow_as_one_clean_solid():
    """Two boxes that overlap (as the UR10's wrist meshes): counted once, one cavity that
    runs through no skin, and a shell that crosses itself nowhere."""
    t = 0.01
    a, b = _box((0.2, 0.1, 0.1)), _box((0.2, 0.1, 0.1), (0.1, 0.05, 0.0))
    two = trimesh.util.concatenate([a, b])
    assert len(crossings(two.vertices, two.faces)[1]) > 0
    shell = hollow_surface(two, t)
    union = 2 * 0.2 * 0.1 * 0.1 - 0.1 * 0.05 * 0.1
    assert shell.solid.volume == pytest.approx(union, rel=1e-9)
    assert shell.mesh.is_volume and shell.mesh.body_count == 2
    assert len(crossings(shell.mesh.vertices, shell.mesh.faces)[1]) == 0
    # the cavity: the two boxes eroded, united, plus t^2 (1 - pi/4) along each of the two
    # reflex edges (0.08 m long inside), the level set's rounded edges within 1 %
    inner = 2 * 0.18 * 0.08 * 0.08 - 0.08 * 0.03 * 0.08
    exact = inner + 2 * 0.08 * t**2 * (1 - np.pi / 4)
    assert shell.cavity.volume == pytest.approx(exact, rel=1e-2)
    assert shell.volume == pytest.approx(union - shell.cavity.volume, rel=1e-9)


def test_wall_thicker_than_the_part_leaves_no_cavity():
    assert level_set_cavity(_box((0.1, 0.1, 0.01)), 0.006) == []
    assert GRID_PER_WALL >= 2
