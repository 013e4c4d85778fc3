"""Built-in CAD surfaces: closed, outward, deterministic, with the volumes they should have."""

from __future__ import annotations

import numpy as np
import pytest
import trimesh

from flexarm.meshes import load_surface
from flexarm.meshes.primitives import (
    bar_surface,
    cylinder_surface,
    hollow_link_surface,
    write_surface,
)


def _polygon_area(radius, n):
    return 0.5 * n * radius**2 * np.sin(2 * np.pi / n)


def test_bar():
    bar = bar_surface(0.3, 0.2, 0.1, origin=(1.0, 2.0, 3.0))
    assert bar.is_watertight and bar.is_winding_consistent
    assert bar.volume == pytest.approx(0.006, rel=1e-14)
    np.testing.assert_allclose(bar.bounds, [[1, 2, 3], [1.3, 2.2, 3.1]], rtol=1e-15)


def test_cylinder_volume_is_the_polygon_prism():
    rod = cylinder_surface(0.05, 0.2, segments=40)
    assert rod.is_watertight
    assert rod.volume == pytest.approx(_polygon_area(0.05, 40) * 0.2, rel=1e-12)


def test_hollow_link_is_a_plausible_deterministic_casting():
    link = hollow_link_surface()
    again = hollow_link_surface()
    np.testing.assert_array_equal(link.vertices, again.vertices)
    np.testing.assert_array_equal(link.faces, again.faces)
    assert link.is_watertight and link.is_winding_consistent
    assert link.euler_number == -2  # one shell, two through-bores
    assert len(link.split(only_watertight=False)) == 1
    np.testing.assert_allclose(link.bounds, [[-0.11, -0.1, -0.11], [0.91, 0.1, 0.11]], atol=1e-12)
    mass = 7850 * link.volume  # a cast-steel link of about a metre: tens of kg, not tonnes
    assert 60 < mass < 200


def test_hand_hole_removes_exactly_its_plug_from_the_top_wall():
    kw = {"segments": 32, "wall": 0.012}
    with_hole = hollow_link_surface(hand_hole_radius=0.04, **kw)
    sealed = hollow_link_surface(hand_hole_radius=0.0, **kw)
    plug = _polygon_area(0.04, 32) * 0.012
    assert sealed.volume - with_hole.volume == pytest.approx(plug, rel=1e-9)
    assert sealed.euler_number == 0  # outer genus-2 shell + the sealed void's sphere


@pytest.mark.parametrize(
    "kwargs, match",
    [
        ({"bore_radius": 0.1}, "bore_radius \\+ wall < hub_radius"),
        ({"hand_hole_radius": 0.09}, "hand_hole_radius=0.09 must be <"),
    ],
)
def test_hollow_link_rejects_impossible_walls(kwargs, match):
    with pytest.raises(ValueError, match=match):
        hollow_link_surface(**kwargs)


def test_bar_rejects_bad_sizes():
    with pytest.raises(ValueError, match="three positive numbers"):
        bar_surface(1.0, 0.0, 1.0)


@pytest.mark.parametrize("ext", [".stl", ".obj", ".ply"])
def test_write_surface_round_trip(tmp_path, ext):
    link = hollow_link_surface(segments=24)
    path = tmp_path / f"link{ext}"
    write_surface(path, link)
    back = load_surface(path)
    assert back.volume == pytest.approx(link.volume, rel=1e-6)
    assert list(tmp_path.iterdir()) == [path]


def test_write_surface_is_atomic(tmp_path, monkeypatch):
    def broken(self, *args, **kwargs):
        raise OSError("disk full")

    monkeypatch.setattr(trimesh.Trimesh, "export", broken)
    with pytest.raises(OSError, match="disk full"):
        write_surface(tmp_path / "bar.stl", bar_surface(1, 1, 1))
    assert list(tmp_path.iterdir()) == []
    with pytest.raises(ValueError, match="cannot write '.step' surfaces"):
        write_surface(tmp_path / "bar.step", bar_surface(1, 1, 1))
