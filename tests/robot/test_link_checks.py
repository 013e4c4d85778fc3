"""A link's CAD and masses are checked before they become mass properties: the surface
``flexarm mesh`` accepts, a plausible density and mass, units against the reach."""

from __future__ import annotations

from dataclasses import replace

import numpy as np
import pytest
import trimesh

from flexarm.assembly.emodel import link_mass_properties
from flexarm.fe.errors import MeshError, ReadError
from flexarm.robot.formats.link_units import check_link_units
from flexarm.robot.link_checks import (
    check_link_density,
    check_link_mass,
    link_surface,
    naming_link,
)
from flexarm.robot.tolerances import tol


def _with_cad(link, tmp_path, mesh: trimesh.Trimesh, name="cad.stl"):
    path = tmp_path / name
    mesh.export(path)
    return replace(link, mesh=path, lumped=())


def test_surface_mass_equals_the_volume_integrals_of_the_raw_file(demo_robot):
    """The checked reader changes nothing for closed CAD: trimesh's integrals of the file
    as stored (an independent path: no merge, no repair) give the same mass and centre."""
    for lk in demo_robot.links:
        raw = trimesh.load(lk.mesh, force="mesh", process=False)
        mp = link_mass_properties(replace(lk, lumped=()), "surface")
        assert mp.mass == pytest.approx(lk.material.rho * raw.volume, rel=1e-12)
        assert np.abs(mp.center_of_mass - raw.center_mass).max() < 1e-12


def test_inverted_cad_is_repaired_to_the_same_mass(demo_robot, tmp_path):
    lk = demo_robot.links[4]
    good = link_mass_properties(replace(lk, lumped=()), "surface")
    inverted = trimesh.load(lk.mesh, force="mesh")
    inverted.invert()
    mp = link_mass_properties(_with_cad(lk, tmp_path, inverted), "surface")
    assert mp.mass == pytest.approx(good.mass, rel=1e-12)
    assert np.abs(mp.center_of_mass - good.center_of_mass).max() < 1e-12


def test_open_cad_is_refused_not_weighed_low(demo_robot, tmp_path):
    """Dropping a fifth of the faces used to weigh the link ~24 % light."""
    lk = demo_robot.links[4]
    s = trimesh.load(lk.mesh, force="mesh")
    s.update_faces(np.arange(len(s.faces)) >= len(s.faces) // 5)
    bad = _with_cad(lk, tmp_path, s, "open.stl")
    with pytest.raises(MeshError, match=r"^links\.tube_shaft\.mesh: .*open\.stl: the surface "
                                        r"is open \(\d+ boundary edges\)"):
        link_mass_properties(bad, "surface")
    with pytest.raises(MeshError, match=r"^links\.tube_shaft\.mesh: .*the surface is open"):
        link_surface(bad)


def test_non_manifold_cad_is_refused(demo_robot, tmp_path):
    a, b = trimesh.creation.box((0.4, 0.4, 0.4)), trimesh.creation.box((0.4, 0.4, 0.4))
    b.apply_translation([0.4, 0.4, 0.0])
    bad = _with_cad(demo_robot.links[4], tmp_path, trimesh.util.concatenate([a, b]))
    with pytest.raises(MeshError, match=r"not manifold \(1 edge shared by more than two"):
        link_mass_properties(bad, "surface")


def test_naming_link_prefixes_once():
    from types import SimpleNamespace

    link = SimpleNamespace(name="hand")
    with pytest.raises(MeshError, match=r"^links\.hand\.mesh: a\.stl: open$"):
        with naming_link(link), naming_link(link):
            raise MeshError("a.stl: open")


@pytest.mark.parametrize("rho, ok", [(tol.density_min, True), (7850.0, True),
                                     (tol.density_max, True), (0.0, False), (7.85, False),
                                     (7.85e6, False)])
def test_density_bounds(demo_robot, rho, ok):
    lk = demo_robot.links[6]
    link = replace(lk, material=replace(lk.material, rho=rho))
    if ok:
        check_link_density(link)
    else:
        with pytest.raises(ValueError, match=r"^links\.turning_disc\.material\.rho: "):
            check_link_density(link)
    check_link_density(replace(link, mesh=None))  # no CAD: the density is not used


def test_link_mass_bounds():
    from types import SimpleNamespace

    hand = SimpleNamespace(name="hand", mesh=None,
                           lumped=(SimpleNamespace(mass=0.0), SimpleNamespace(mass=0.0)))
    check_link_mass(hand, 1e-3)
    check_link_mass(hand, tol.link_mass_max)
    with pytest.raises(ValueError, match=r"^links\.hand: the link has no mass \(no CAD solid, "
                                         r"lumped masses 0 kg\)"):
        check_link_mass(hand, 0.0)
    with pytest.raises(ValueError, match=r"^links\.hand: 6e\+04 kg is not a plausible link "
                                         r"mass \(CAD solid 6e\+04 kg, lumped masses 0 kg; at "
                                         r"most 50000 kg\)"):
        check_link_mass(hand, 6e4, 6e4)
    with pytest.raises(ValueError, match="no mass"):
        check_link_mass(hand, float("nan"))


@pytest.mark.parametrize("unit, factor", [("mm", 1e-3), ("cm", 1e-2), ("in", 0.0254)])
def test_units_of_the_last_link_held_against_the_reach(demo_robot, unit, factor):
    """The flange carries no joint: 0.16 m across on a 2.84 m arm; a wrong unit moves the
    ratio 0.056 below the 2e-3 floor."""
    links = demo_robot.links[:-1] + (replace(demo_robot.links[-1], units=unit),)
    size = 0.16 * factor
    with pytest.raises(ValueError, match=rf"^links\.turning_disc\.units: the CAD is "
                                         rf"{size:.3g} m across with units='{unit}' but the "
                                         r"robot reaches 2\.84 m"):
        check_link_units(replace(demo_robot, links=links))


def test_published_robots_pass_the_leaf_check(demo_robot):
    import warnings
    from pathlib import Path

    from flexarm.robot import load_robot

    check_link_units(demo_robot)
    folder = Path(__file__).resolve().parents[3] / "shared" / "data"
    urdfs = [p for p in [folder / "irb4600/urdf/irb4600_60_205.urdf",
                         *sorted((folder / "robots").glob("*/urdf/*.urdf"))] if p.is_file()]
    if not urdfs:
        pytest.skip("no published robots here")
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # their import notes are not this test's business
        for p in urdfs:
            check_link_units(load_robot(p))


def test_damping_ratio_names_the_joint(tmp_path):
    from flexarm.robot.demo_arm import demo_robot_path
    from flexarm.robot.formats import read

    text = demo_robot_path().read_text().replace("meshes/", f"{demo_robot_path().parent}/meshes/")
    text = text.replace('= "tets/', f'= "{demo_robot_path().parent}/tets/')
    path = tmp_path / "r.toml"
    path.write_text(text.replace("damping_ratio = 0.03", "damping_ratio = 1.2", 3))
    with pytest.raises(ReadError, match=r"joints\.joint_1\.model\.damping_ratio must be in "
                                         r"\[0, 1\), got 1\.2"):
        read(path)
