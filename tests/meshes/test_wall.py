"""The wall for a mass (exact targets, impossible ones) and the bending-stiffness proxy."""

from __future__ import annotations

import numpy as np
import pytest
import trimesh

from flexarm.meshes import hollow, load_surface
from flexarm.meshes.hollow import hollow_surface
from flexarm.meshes.wall import bending_ratio, wall_for_mass

from .test_hollow import IRB_LINKS, _box_shell, _moved


def test_hollow_re_exports_the_wall_functions():
    assert hollow.wall_for_mass is wall_for_mass and hollow.bending_ratio is bending_ratio


def test_wall_for_mass_recovers_a_known_wall():
    boxes = [trimesh.creation.box((0.4, 0.2, 0.1)), _moved(trimesh.creation.box((0.3, 0.3, 0.02)))]
    rho, lumped, t = [7200.0, 2700.0], [3.0, 2.0], 0.0123
    # the plate (inscribed radius 10 mm) stays solid at this wall
    target = rho[0] * _box_shell((0.4, 0.2, 0.1), t) + rho[1] * 0.3 * 0.3 * 0.02 + 5.0
    assert hollow_surface(boxes[1], t).is_solid
    assert wall_for_mass(boxes, rho, target, lumped_mass=lumped) == pytest.approx(t, abs=1e-9)
    # one density for both
    target = 7200.0 * (_box_shell((0.4, 0.2, 0.1), 0.004) + _box_shell((0.3, 0.3, 0.02), 0.004))
    assert wall_for_mass(boxes, 7200.0, target) == pytest.approx(0.004, abs=1e-9)


def test_wall_for_mass_refuses_impossible_targets():
    boxes = [trimesh.creation.box((0.4, 0.2, 0.1))]  # 0.008 m^3: 57.6 kg solid
    with pytest.raises(ValueError, match="too light"):
        wall_for_mass(boxes, 7200.0, 60.0)
    with pytest.raises(ValueError, match="lumped"):
        wall_for_mass(boxes, 7200.0, 10.0, lumped_mass=10.0)
    with pytest.raises(ValueError, match="densities"):
        wall_for_mass(boxes, 0.0, 10.0)
    with pytest.raises(ValueError, match="at least one"):
        wall_for_mass([], 7200.0, 10.0)
    # exactly solid: the smallest wall that fills every part
    assert wall_for_mass(boxes, 7200.0, 57.6 + 1.0, lumped_mass=1.0) == pytest.approx(0.05)


def test_bending_ratio_of_a_hollow_cube():
    a, t = 0.2, 0.01
    cube = trimesh.creation.box((a, a, a))
    ratio = bending_ratio(cube, hollow_surface(cube, t))
    # int x^2 dV of a cube of side a is a^5 / 12, about every axis
    np.testing.assert_allclose(ratio, 1 - ((a - 2 * t) / a) ** 5, rtol=1e-12)
    np.testing.assert_allclose(bending_ratio(cube, cube), 1.0, rtol=1e-12)


def test_bending_ratio_of_a_turned_tube_is_its_section_ratio():
    length, side, t = 1.0, 0.1, 0.005
    bar = _moved(trimesh.creation.box((length, side, side)))
    ratio = bending_ratio(bar, hollow_surface(bar, t))
    inner = (side - 2 * t) / side
    along = 1 - inner**2 * ((length - 2 * t) / length) ** 3
    across = 1 - inner**4 * (length - 2 * t) / length  # the end walls add 2 t / length
    np.testing.assert_allclose(ratio, [along, across, across], rtol=1e-9)


@pytest.mark.skipif(not IRB_LINKS, reason="shared IRB 4600 data not present")
def test_irb4600_wall_for_its_datasheet_mass():
    surfaces = [load_surface(p) for p in IRB_LINKS]
    t = wall_for_mass(surfaces, 7200.0, 425.0)
    assert 0.005 < t < 0.03
    mass = sum(7200.0 * hollow_surface(s, t).volume for s in surfaces)
    assert mass == pytest.approx(425.0, rel=1e-6)
