"""The deterministic CAD surface sample the seat finder works on."""

from __future__ import annotations

import math

import numpy as np
import pytest

from flexarm.robot.seat_sample import link_sample, surface_sample


def test_surface_sample_is_even_deterministic_and_outward():
    import trimesh

    box = trimesh.creation.box((0.3, 0.2, 0.1))
    a = surface_sample(box.vertices, box.faces, spacing=0.004)
    b = surface_sample(box.vertices, box.faces, spacing=0.004)
    assert len(a.points) == math.floor(box.area / 0.004**2)
    np.testing.assert_array_equal(a.points, b.points)
    assert a.weight * len(a.points) == pytest.approx(box.area)
    assert (np.einsum("ij,ij->i", a.normals, a.points) > 0).all()  # outward, box at 0
    # even: every 5 cm patch of the 0.3 x 0.2 top face holds its share of points (+-10 %)
    top = a.points[a.normals[:, 2] > 0.5]
    counts, _, _ = np.histogram2d(top[:, 0], top[:, 1], bins=(6, 4))
    assert counts.min() >= 0.9 * counts.mean() and counts.max() <= 1.1 * counts.mean()


def test_surface_sample_refuses_an_empty_surface():
    flat = np.zeros((3, 3))
    with pytest.raises(ValueError, match="need a surface with area > 0"):
        surface_sample(flat, [[0, 1, 2]], spacing=0.01)


def test_link_sample_is_kept_and_needs_a_mesh(demo_robot):
    import dataclasses

    link = demo_robot.links[-1]
    assert link_sample(link) is link_sample(link)
    with pytest.raises(ValueError, match=f"links.{link.name}: no CAD mesh"):
        link_sample(dataclasses.replace(link, mesh=None))


def test_the_sample_of_a_hollow_link_holds_no_point_of_its_cavity(demo_robot, tmp_path):
    """A shell (a 0.2 m box with a 0.1 m cavity, as hollowing writes it): every sample
    point lies on the outer faces, and the area is the outer box's."""
    import dataclasses

    import trimesh

    outer, inner = trimesh.creation.box((0.2, 0.2, 0.2)), trimesh.creation.box((0.1,) * 3)
    shell = trimesh.Trimesh(np.vstack([outer.vertices, inner.vertices]),
                            np.vstack([outer.faces, inner.faces[:, ::-1] + 8]), process=False)
    shell.export(tmp_path / "shell.stl")
    link = dataclasses.replace(demo_robot.links[-1], mesh=tmp_path / "shell.stl", units="m")
    s = link_sample(link)
    assert np.abs(s.points).max(axis=1).min() == pytest.approx(0.1)
    assert s.weight * len(s.points) == pytest.approx(6 * 0.2**2)
