"""``mesher = "auto"``: Gmsh on clean closed surfaces (reproducible), fTetWild for dirty
CAD with the reason, the choice cached with the mesh it gave."""

from __future__ import annotations

import numpy as np
import pytest
import trimesh

import flexarm.meshes.auto_mesher as auto_mesher
from flexarm.fe.errors import MeshError
from flexarm.meshes import MESHER_SETTINGS, cached_surface_mesh, mesh_surface, tetrahedralizer
from flexarm.meshes.primitives import bar_surface

pytest.importorskip("gmsh", exc_type=ImportError)

EDGE = 0.05


@pytest.fixture(scope="module")
def bar():
    return bar_surface(0.2, 0.1, 0.05)


def test_settings():
    assert MESHER_SETTINGS == ("auto", "tetwild", "gmsh")
    with pytest.raises(ValueError, match="mesher must be one of 'auto'"):
        mesh_surface(trimesh.creation.box(), 0.1, "netgen")


def test_a_clean_closed_surface_goes_to_gmsh_and_is_cached_with_its_choice(bar, monkeypatch,
                                                                           tmp_path):
    first = mesh_surface(bar, EDGE, name="bar")
    assert (first.mesher, first.note, first.is_cached) == ("gmsh", "", False)
    assert first.is_reproducible
    assert float(first.mesh.volumes().sum()) == pytest.approx(1e-3, rel=1e-12)
    # a warm call reads the choice and the mesh: no surface check, no meshing
    monkeypatch.setattr(auto_mesher, "united_surface", None)
    monkeypatch.setattr(auto_mesher, "_gmsh_mesh", None)
    again = mesh_surface(bar, EDGE, name="bar")
    assert again.is_cached and again.mesher == "gmsh"
    np.testing.assert_array_equal(again.mesh.points, first.mesh.points)
    looked_up = cached_surface_mesh(bar, EDGE)
    np.testing.assert_array_equal(looked_up.mesh.tets, first.mesh.tets)
    # the same surface meshed in an empty cache: the same elements, bit for bit
    monkeypatch.undo()
    monkeypatch.setenv("FLEXARM_CACHE", str(tmp_path / "other"))
    assert cached_surface_mesh(bar, EDGE) is None
    fresh = mesh_surface(bar, EDGE, name="bar")
    assert not fresh.is_cached
    np.testing.assert_array_equal(fresh.mesh.points, first.mesh.points)
    np.testing.assert_array_equal(fresh.mesh.tets, first.mesh.tets)


def test_the_auto_choice_and_the_meshers_never_share_an_entry(bar):
    auto = mesh_surface(bar, EDGE)
    assert cached_surface_mesh(bar, EDGE, "gmsh") is not None  # the same Gmsh request
    assert cached_surface_mesh(bar, EDGE, "tetwild") is None
    assert cached_surface_mesh(bar, EDGE, "auto", order=2) is None
    assert tetrahedralizer("auto")(bar, EDGE).n_tets == auto.mesh.n_tets


def test_an_open_surface_falls_back_to_tetwild_with_its_reason(bar):
    box = trimesh.creation.box((0.2, 0.1, 0.05))
    box.update_faces(np.arange(len(box.faces)) != 0)  # one triangle missing
    with pytest.warns(UserWarning, match=r"open: meshed by fTetWild \(the surface is not "
                                         r"closed\): not reproducible"):
        made = mesh_surface(box, EDGE, name="open")
    assert made.mesher == "tetwild" and made.note == "the surface is not closed"
    assert not made.is_reproducible and made.mesh.n_tets > 0


def test_a_gmsh_failure_falls_back_to_tetwild(bar, monkeypatch):
    def fails(surface, size, *args, **kwargs):
        raise MeshError("bar: gmsh failed (try 1: PLC Error); try mesher='tetwild'")

    monkeypatch.setattr(auto_mesher, "_gmsh_mesh", fails)
    with pytest.warns(UserWarning, match=r"bar: meshed by fTetWild \(gmsh failed \(try 1: "
                                         r"PLC Error\)\): not reproducible"):
        made = mesh_surface(bar, EDGE, name="bar")
    assert made.mesher == "tetwild" and made.note == "gmsh failed (try 1: PLC Error)"
    # the choice is kept: a warm run does not try Gmsh again
    monkeypatch.setattr(auto_mesher, "tetrahedralize", None)
    warm = mesh_surface(bar, EDGE, name="bar")
    assert warm.is_cached and warm.mesher == "tetwild"
    np.testing.assert_array_equal(warm.mesh.points, made.mesh.points)


def test_after_a_gmsh_failure_ftetwild_meshes_the_union(monkeypatch):
    """Two overlapping boxes in one surface (as published collision hulls come): where
    Gmsh fails, fTetWild is given their union, the same solid without the faces inside
    it (which it would refine along): 0.0015 m^3 enclosed once, where the two boxes'
    surfaces enclose 0.002 m^3 together."""
    from flexarm.meshes.self_intersections import crossings

    a = trimesh.creation.box((0.2, 0.1, 0.05))
    b = trimesh.creation.box((0.2, 0.1, 0.05),
                             trimesh.transformations.translation_matrix([0.1, 0.0, 0.0]))
    both = trimesh.util.concatenate([a, b])
    given, original = [], auto_mesher.tetrahedralize

    def fails(surface, size, *args, **kwargs):
        raise MeshError("boxes: gmsh failed (try 1: PLC Error); try mesher='tetwild'")

    def tetwild(surface, *args, **kwargs):
        given.append(surface)
        return original(surface, *args, **kwargs)

    monkeypatch.setattr(auto_mesher, "_gmsh_mesh", fails)
    monkeypatch.setattr(auto_mesher, "tetrahedralize", tetwild)
    with pytest.warns(UserWarning, match=r"boxes: meshed by fTetWild"):
        made = mesh_surface(both, EDGE, name="boxes", cache=False)
    assert made.mesher == "tetwild"
    assert float(abs(both.volume)) == pytest.approx(2e-3, rel=1e-9)
    assert float(given[0].volume) == pytest.approx(1.5e-3, rel=1e-9)
    assert len(crossings(given[0].vertices, given[0].faces)[1]) == 0
    assert float(made.mesh.volumes().sum()) == pytest.approx(1.5e-3, rel=5e-3)
