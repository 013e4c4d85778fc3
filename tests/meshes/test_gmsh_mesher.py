"""tetrahedralize_gmsh: deterministic Gmsh meshes, exact volumes, physics, clear errors."""

from __future__ import annotations

import sys

import numpy as np
import pytest
import trimesh

from flexarm.fe import assemble, dof_split, modes, node_dofs, select_nodes, shift_invert
from flexarm.fe.errors import MeshError, MissingDependencyError
from flexarm.meshes import (
    dihedral_angles,
    mesh_part,
    mesh_quality,
    tetrahedralize_gmsh,
    tetrahedralizer,
    write_surface,
)
from flexarm.meshes import gmsh_passes
from flexarm.meshes.primitives import bar_surface
from flexarm.meshes.tet_cache import tet_cache_key

from .conftest import BAR

try:  # the wheel's libgmsh needs system GL/X libraries: OSError if they are missing
    import gmsh
except (ImportError, OSError):
    pytest.skip("gmsh is not importable", allow_module_level=True)

#: Timoshenko bending frequencies of the 0.05 x 0.05 x 1 m steel cantilever [Hz]
#: (tests/fe/test_cantilever.py, DESIGN.md section 9), each a degenerate pair.
F_TIMOSHENKO = (41.694, 258.29)


def _same(a, b) -> bool:
    return (a.points.shape == b.points.shape and a.tets.shape == b.tets.shape
            and np.array_equal(a.points, b.points) and np.array_equal(a.tets, b.tets))


def _check(mesh, surface, volume_rtol):
    vol = mesh.volumes()
    assert (vol > 0).all()
    assert len(np.unique(mesh.tets)) == mesh.n_nodes  # no unused nodes
    mesh.check()
    assert vol.sum() == pytest.approx(float(surface.volume), rel=volume_rtol)


def test_same_input_gives_bit_identical_meshes(bar, capfd):
    first = tetrahedralize_gmsh(bar, 0.02, cache=False, name="bar")
    second = tetrahedralize_gmsh(bar, 0.02, cache=False, name="bar")
    assert _same(first, second)
    # a differently ordered but identical copy of the surface gives the same mesh too
    copy = trimesh.Trimesh(bar.vertices.copy(), bar.faces.copy(), process=False)
    assert _same(first, tetrahedralize_gmsh(copy, 0.02, cache=False))
    out, err = capfd.readouterr()
    assert out == "" and err == ""  # General.Terminal=0, Netgen's prints swallowed
    assert not gmsh.isInitialized()  # finalised again: no global state left behind


@pytest.mark.parametrize(
    "shape, surface, size",
    [
        ("box", trimesh.creation.box((0.2, 0.1, 0.05)), 0.02),
        ("cylinder", trimesh.creation.cylinder(radius=0.05, height=0.2, sections=48), 0.0125),
    ],
)
def test_volume_and_orientation(shape, surface, size):
    mesh = tetrahedralize_gmsh(surface, size, cache=False, name=shape)
    _check(mesh, surface, volume_rtol=0.01)
    report = mesh_quality(mesh, surface)
    assert report.n_slivers == 0 and report.mean_radius_ratio > 0.6
    # nodes lie on or inside the CAD surface (a curved face is remeshed with chords)
    assert (mesh.bounds()[0] >= surface.bounds[0] - 1e-12).all()
    assert (mesh.bounds()[1] <= surface.bounds[1] + 1e-12).all()


def test_box_is_exact_and_conforming(bar):
    """Planar faces are meshed on exact plane surfaces: the volume is the CAD volume."""
    mesh = tetrahedralize_gmsh(bar, 0.025, cache=False)
    _check(mesh, bar, volume_rtol=1e-9)
    np.testing.assert_allclose(mesh.bounds(), [[0, 0, 0], BAR], atol=1e-12)


def test_tet10_cantilever_frequencies_within_one_percent(steel):
    mesh = tetrahedralize_gmsh(bar_surface(1.0, 0.05, 0.05), 0.025, order=2, cache=False)
    assert mesh.order == 2
    K, M = assemble(mesh, steel)
    split = dof_split(mesh.n_dofs, node_dofs(select_nodes(mesh, "x=min")))
    m = modes(split.condense(K), split.condense(M), n=4, eigensolver=shift_invert(0.0))
    assert m.n_rigid == 0
    for pair, ref in zip((m.freq_hz[0:2], m.freq_hz[2:4]), F_TIMOSHENKO, strict=True):
        np.testing.assert_allclose(pair, ref, rtol=0.01)
        assert np.all(pair > ref)  # conforming, consistent mass: from above


def test_open_surface_is_refused_with_its_name():
    box = trimesh.creation.box((0.1, 0.1, 0.1))
    open_box = trimesh.Trimesh(box.vertices, box.faces[:-2], process=False)
    with pytest.raises(MeshError, match=r"^lid\.stl: the surface is not closed"):
        tetrahedralize_gmsh(open_box, 0.05, cache=False, name="lid.stl")


def test_missing_gmsh_says_how_to_install(bar, monkeypatch):
    monkeypatch.setitem(sys.modules, "gmsh", None)  # import gmsh -> ImportError
    with pytest.raises(MissingDependencyError) as info:
        tetrahedralize_gmsh(bar, 0.05, cache=False)
    assert str(info.value) == "gmsh is not installed: pip install gmsh (or use mesher='tetwild')"


def test_cache_entries_are_separate_from_tetwild(bar, private_cache):
    messages = []
    first = tetrahedralize_gmsh(bar, 0.05, name="bar")
    again = tetrahedralize_gmsh(bar, 0.05, name="bar", progress=messages.append)
    assert _same(first, again) and "from cache" in messages[0]
    assert len(list((private_cache / "tets").glob("*.npz"))) == 1
    v, f = bar.vertices, bar.faces
    assert tet_cache_key(v, f, 0.05, True, 1) != tet_cache_key(v, f, 0.05, True, 1, mesher="gmsh")
    with pytest.raises(ValueError, match="mesher must be one of"):
        tet_cache_key(v, f, 0.05, True, 1, mesher="netgen")


def test_an_open_caller_session_is_left_as_it_was(bar):
    gmsh.initialize([], readConfigFiles=False, interruptible=False)
    try:
        gmsh.option.setNumber("General.Terminal", 0)
        gmsh.model.add("mine")
        gmsh.option.setNumber("Mesh.Algorithm3D", 10)
        gmsh.option.setNumber("Mesh.MeshSizeMax", 7.0)
        models = gmsh.model.list()
        mesh = tetrahedralize_gmsh(bar, 0.05, cache=False)
        assert gmsh.isInitialized() and gmsh.model.list() == models
        assert gmsh.model.getCurrent() == "mine"
        assert gmsh.option.getNumber("Mesh.Algorithm3D") == 10
        assert gmsh.option.getNumber("Mesh.MeshSizeMax") == 7.0
    finally:
        gmsh.finalize()
    assert _same(mesh, tetrahedralize_gmsh(bar, 0.05, cache=False))


def test_mesher_setting_through_mesh_part_and_cli(tmp_path):
    from flexarm.cli import main

    path = tmp_path / "bar_mm.stl"
    write_surface(path, bar_surface(200.0, 100.0, 50.0))
    mesh, report = mesh_part(path, units="mm", size=0.03, mesher="gmsh", cache=False)
    assert abs(report.volume_error) < 1e-9 and (mesh.volumes() > 0).all()
    assert tetrahedralizer("gmsh") is tetrahedralize_gmsh
    with pytest.raises(ValueError, match="mesher must be one of"):
        mesh_part(path, mesher="netgen")
    out = tmp_path / "bar.vtu"
    assert main(["mesh", str(path), "--units", "mm", "--size", "0.03", "--mesher", "gmsh",
                 "--no-cache", "-o", str(out)]) == 0
    assert out.is_file()


# --- each try in a child process with a CPU-time budget --------------------------------
def _stalls_on(stalled: set[int], monkeypatch) -> list[float]:
    """Make the tries numbered ``stalled`` spend their budget (as a Gmsh remesh that never
    returns does); the budgets given to every try, in order."""
    from flexarm.fe.processes import ChildTimeout, run_child
    from flexarm.meshes import gmsh_mesher

    budgets = []

    def child(function, args, cpu_seconds, name):
        budgets.append(cpu_seconds)
        if len(budgets) in stalled:
            raise ChildTimeout(f"{name}: stopped after {cpu_seconds:g} CPU-s")
        return run_child(function, args, cpu_seconds=cpu_seconds, name=name)

    monkeypatch.setattr(gmsh_mesher, "run_child", child)
    return budgets


def test_a_stalled_try_is_stopped_and_the_next_pre_mesh_gives_its_own_mesh(bar, monkeypatch):
    """Try 1 stalls: try 2 (the next pre-mesh edge) runs and gives the mesh it gives when
    the ladder starts there; the budget grows with the elements of the try."""
    from flexarm.meshes import gmsh_mesher
    from flexarm.meshes.gmsh_mesher import try_cpu_seconds

    said = []
    budgets = _stalls_on({1}, monkeypatch)
    mesh = tetrahedralize_gmsh(bar, 0.02, cache=False, name="bar", progress=said.append)
    assert budgets == [try_cpu_seconds(bar, 0.02, f) for f in gmsh_mesher.PREMESH_FRACTIONS[:2]]
    assert budgets[1] > budgets[0]  # a finer pre-mesh: more triangles, more time
    assert any("gmsh try 2/4: remesh (pre-mesh edge 0.00667 m, at most" in s for s in said)
    monkeypatch.setattr(gmsh_mesher, "PREMESH_FRACTIONS", gmsh_mesher.PREMESH_FRACTIONS[1:])
    _stalls_on(set(), monkeypatch)
    assert _same(mesh, tetrahedralize_gmsh(bar, 0.02, cache=False))


def test_when_every_remesh_stalls_the_volume_on_the_pre_mesh_is_named(bar, monkeypatch):
    """Through ``mesher="auto"``: Gmsh without its remesh, named in the note (and so in
    the build table), with the budget each try spent."""
    from flexarm.meshes import mesh_surface
    from flexarm.meshes.gmsh_mesher import try_cpu_seconds

    _stalls_on({1, 2, 3}, monkeypatch)
    made = mesh_surface(bar, 0.025, name="bar", cache=False)
    assert made.mesher == "gmsh" and made.is_reproducible
    b = [round(try_cpu_seconds(bar, 0.025, f)) for f in (1 / 2, 1 / 3, 1 / 4)]
    assert made.note == (f"the volume on the pre-mesh surface (try 1: no answer in {b[0]} "
                         f"CPU-s; try 2: no answer in {b[1]} CPU-s; try 3: no answer in "
                         f"{b[2]} CPU-s)")
    _check(made.mesh, bar, volume_rtol=1e-9)  # the exact planar facets


def test_every_try_stalled_falls_back_to_tetwild_with_the_reason(bar, monkeypatch):
    from flexarm.meshes import mesh_surface

    _stalls_on({1, 2, 3, 4}, monkeypatch)
    with pytest.warns(UserWarning, match=r"bar: meshed by fTetWild \(gmsh failed \(try 1: "
                                         r"no answer in \d+ CPU-s; try 2"):
        made = mesh_surface(bar, 0.025, name="bar", cache=False)
    assert made.mesher == "tetwild" and made.note.startswith("gmsh failed (try 1: no answer")
    _stalls_on({1, 2, 3, 4}, monkeypatch)
    with pytest.raises(MeshError, match=r"^bar: gmsh failed \(try 1: no answer in \d+ CPU-s; "
                                        r".*\); try mesher='tetwild'$"):
        tetrahedralize_gmsh(bar, 0.025, cache=False, name="bar")


def test_a_pre_mesh_volume_with_slivers_is_refused(bar, monkeypatch):
    """The pre-mesh keeps the CAD's triangles where a face is curved (a level-set cavity's
    thousands): its volume mesh is refused with a single sliver (here a flat tetrahedron,
    1.4 deg, beside the bar's), and ``"auto"`` goes on to fTetWild."""
    from flexarm.fe.mesh import TetMesh
    from flexarm.meshes import gmsh_mesher

    box = TetMesh.box(BAR, (2, 2, 2))
    flat = np.array([[0, 0, 0], [0.05, 0, 0], [0, 0.05, 0], [0.02, 0.02, 5e-4]]) + [1, 0, 0]
    points = np.vstack([box.points, flat])
    tets = np.vstack([box.tets, box.n_nodes + np.arange(4)[None]])

    def child(function, args, cpu_seconds, name):
        if args[0] == gmsh_passes.PREMESH:
            return points, tets
        raise gmsh_mesher._GmshFailed("Wrong topology of boundary mesh for parametrization")

    monkeypatch.setattr(gmsh_mesher, "run_child", child)
    with pytest.raises(MeshError, match=r"^bar: gmsh failed \(try 1: Wrong topology of "
                                        r"boundary mesh for parametrization; tries 2-3: "
                                        r"skipped \(the same patches at every pre-mesh "
                                        r"edge\); try 4: 1 sliver tetrahedra\); "
                                        r"try mesher='tetwild'$"):
        tetrahedralize_gmsh(bar, 0.05, cache=False, name="bar")


def test_a_remesh_that_fails_for_its_patches_is_not_tried_at_other_edges(bar, monkeypatch):
    """Gmsh's patches come from the sharp edges between planar facets, which every
    pre-mesh edge keeps: after a topology failure the ladder goes straight to the volume
    on the pre-mesh (which here works), and a stall still moves to the next edge."""
    from flexarm.meshes import gmsh_mesher

    ran = []

    def child(function, args, cpu_seconds, name):
        ran.append((args[0], args[5]))
        if args[0] == "remesh":
            raise gmsh_mesher._GmshFailed("Wrong topology of boundary mesh for parametrization")
        return gmsh_passes.gmsh_try(*args)

    monkeypatch.setattr(gmsh_mesher, "run_child", child)
    said = []
    mesh = tetrahedralize_gmsh(bar, 0.025, cache=False, name="bar", progress=said.append)
    assert ran == [("remesh", 0.5), (gmsh_passes.PREMESH, 0.5)]
    assert sum("skipped (the same patches" in s for s in said) == 2
    _check(mesh, bar, volume_rtol=1e-9)
    budgets = _stalls_on({1}, monkeypatch)  # a stall is no property of the patches
    tetrahedralize_gmsh(bar, 0.025, cache=False, name="bar")
    assert len(budgets) == 2  # try 2 remeshed


@pytest.fixture(scope="module")
def stepped():
    """Two boxes united whose side faces stand 10 um apart: the union keeps a facet
    10 um wide, as CAD unions do where two bodies almost line up."""
    from flexarm.meshes.union import union

    lower = trimesh.creation.box((0.2, 0.1, 0.05))
    upper = trimesh.creation.box((0.1, 0.1, 0.05), trimesh.transformations.translation_matrix(
        [0.05 + 1e-5, 0.0, 0.04]))
    return union([lower, upper])


def _premesh_try(surface, size):
    from flexarm.meshes.gmsh_model import _facet_labels

    return gmsh_passes.gmsh_try(gmsh_passes.PREMESH, np.asarray(surface.vertices, float),
                                 np.asarray(surface.faces, np.int64), _facet_labels(surface),
                                 size, 0.5, True, ())


def test_a_needle_in_the_pre_mesh_is_refused_before_its_volume(stepped, monkeypatch):
    """The 10 um facet pre-meshes into needle triangles; the volume on them would hold
    slivers (checked with the refusal off), so it is not meshed."""
    from dataclasses import replace

    with pytest.raises(gmsh_passes._GmshFailed,
                       match=r"^\d+ needle triangles in the pre-mesh \(smallest angle "
                             r"0\.0\d+ deg\)$"):
        _premesh_try(stepped, 0.02)
    monkeypatch.setattr(gmsh_passes, "tol", replace(gmsh_passes.tol, premesh_needle_deg=0.0))
    points, tets = _premesh_try(stepped, 0.02)
    smallest = dihedral_angles(points, tets).min(axis=1)
    assert (smallest < gmsh_passes.tol.sliver_dihedral_deg).sum() > 10
    # the remesh of the same surface works: the needle only ends the last try
    assert tetrahedralize_gmsh(stepped, 0.02, cache=False).n_tets > 0

