"""Sheets of a closed surface that touch or cross: found, and replaced by the surface of
the solid's union (the published IRB 4600 hulls have a vertex 5 nm through a face)."""

from __future__ import annotations

import numpy as np
import pytest
import trimesh

from flexarm.meshes.self_intersections import crossings, united_surface


def _kissing() -> trimesh.Trimesh:
    """A box and a spike whose tip is 5 nm through the box's face (two closed bodies in one
    surface), as a published hull has a vertex through one of its own faces."""
    box = trimesh.creation.box((1.0, 1.0, 1.0))
    box.apply_translation([0.5, 0.5, 0.5])
    tip = [1.0 - 5e-9, 0.3, 0.6]  # off the diagonals of the face x = 1
    spike = trimesh.Trimesh([[2.0, 0.2, 0.5], [2.0, 0.5, 0.5], [2.0, 0.35, 0.8], tip],
                            [[0, 2, 1], [0, 1, 3], [1, 2, 3], [2, 0, 3]])
    spike.fix_normals()
    return trimesh.util.concatenate([box, spike])


def test_a_box_has_no_crossings_and_is_returned_as_it_is():
    box = trimesh.creation.box((0.3, 0.2, 0.1))
    edges, faces = crossings(box.vertices, box.faces)
    assert edges.shape == (0, 2) and faces.shape == (0,)
    assert united_surface(box) is box


def test_two_overlapping_boxes_cross_and_unite():
    a = trimesh.creation.box((1.0, 1.0, 1.0))
    b = a.copy().apply_translation([0.5, 0.3, 0.2])  # one corner of each inside the other
    both = trimesh.util.concatenate([a, b])
    edges, faces = crossings(both.vertices, both.faces)
    # the 3 edges at each box's inner corner pierce the other's faces
    assert len(faces) >= 6
    # every pair joins an edge of one box with a face of the other
    n_a = len(a.vertices)
    assert np.all((edges < n_a).all(axis=1) != (both.faces[faces] < n_a).all(axis=1))
    united = united_surface(both)
    assert united.is_volume and len(crossings(united.vertices, united.faces)[1]) == 0
    assert united.volume == pytest.approx(2.0 - 0.5 * 0.7 * 0.8, rel=1e-12)


def test_a_vertex_through_a_face_by_nanometres_is_united_and_stays_the_same_solid():
    surface = _kissing()
    assert len(crossings(surface.vertices, surface.faces)[1]) >= 1
    united = united_surface(surface)
    assert united.is_volume and len(crossings(united.vertices, united.faces)[1]) == 0
    # the spike and the box: their volumes to rounding (they only touched)
    assert united.volume == pytest.approx(surface.volume, rel=1e-6)
    np.testing.assert_allclose(united.bounds, surface.bounds, atol=1e-6)
    # the same surface gives the same union, bit for bit
    again = united_surface(surface)
    np.testing.assert_array_equal(again.vertices, united.vertices)
    np.testing.assert_array_equal(again.faces, united.faces)
