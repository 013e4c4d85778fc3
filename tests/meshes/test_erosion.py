"""The erosion of non-convex parts: a wall for a mass in a few erosions (Newton steps on
the cavity's exact area), each erosion cached, and shells that come back closed from a
file as a reader repairs it."""

from __future__ import annotations

import numpy as np
import pytest
import trimesh

import flexarm.meshes.inward_offset as inward_offset
from flexarm.meshes import load_surface
from flexarm.meshes.erosion import eroded_cavity
from flexarm.meshes.hollow import hollow_surface
from flexarm.meshes.primitives import hollow_link_surface
from flexarm.meshes.wall import wall_for_mass

from .test_hollow import _l_shape, _l_shell_volume, _moved


def test_wall_for_the_mass_of_an_l_shape_in_a_few_erosions(monkeypatch):
    calls = []
    real = inward_offset.eroded_cavity

    def counted(surface, thickness, *args, **kwargs):
        calls.append(thickness)
        return real(surface, thickness, *args, **kwargs)

    monkeypatch.setattr(inward_offset, "eroded_cavity", counted)
    surface = _moved(_l_shape())
    rho, t = 7100.0, 0.01
    target = rho * _l_shell_volume(t)  # the exact shell of a 10 mm wall
    wall = wall_for_mass([surface], rho, target)
    # Brent's method on every erosion took 12 or more; Newton's method, four at most
    assert len(set(calls)) <= 4, calls
    # the erosion's inscribed ball leaves the concave fillet 1.1e-4 of the volume thin,
    # so its wall for this mass is a little thicker than 10 mm
    assert wall == pytest.approx(t, rel=2e-3)
    shell = hollow_surface(surface, wall)
    assert rho * shell.volume == pytest.approx(target, rel=2e-3)


def test_an_erosion_is_computed_once():
    surface = _moved(_l_shape())
    first = eroded_cavity(surface, 0.012)
    again = eroded_cavity(surface, 0.012)  # from the package cache
    assert len(first) == len(again) == 1
    np.testing.assert_array_equal(first[0].vertices, again[0].vertices)
    assert float(first[0].volume) == pytest.approx(
        0.1**3 * 3 - _l_shell_volume(0.012), rel=1e-3)


def test_an_eroded_shell_comes_back_closed_from_its_file(tmp_path):
    """What ``import-urdf --wall`` writes, read back as ``flexarm build`` reads it."""
    from flexarm.robot.formats.urdf_meshes import write_derived

    link = hollow_link_surface(segments=12)  # a cast link with bores: concave everywhere
    shell = hollow_surface(link, 0.004)
    assert shell.method == "erosion"
    back = load_surface(write_derived(shell.mesh, tmp_path, "cast"))
    assert back.is_volume and len(back.faces) == len(shell.mesh.faces)
    assert float(back.volume) == pytest.approx(shell.volume, rel=1e-9)
    # every cavity face keeps an area the reader does not call degenerate
    assert trimesh.triangles.nondegenerate(shell.cavity.triangles, height=1e-9).all()
