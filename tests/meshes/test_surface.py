"""load_surface: units, repair, and one clear error for each kind of bad file."""

from __future__ import annotations

import logging
import re

import numpy as np
import pytest
import trimesh

from flexarm.fe.errors import MeshError, ReadError
from flexarm.meshes import load_surface, write_surface
from flexarm.meshes.primitives import bar_surface, hollow_link_surface

SUPPORTED = re.escape("(supported: .stl, .obj, .ply, .dae)")


def _write(path, mesh):
    """Write a surface (STL and PLY store float32: compare volumes to ~1e-7)."""
    write_surface(path, mesh)
    return path


def test_mm_and_m_differ_by_1e9_in_volume(tmp_path):
    path = _write(tmp_path / "block.stl", bar_surface(2.0, 1.0, 0.5))
    in_m = load_surface(path, units="m")
    in_mm = load_surface(path, units="mm")
    in_inch = load_surface(path, units="in")
    assert in_m.volume == pytest.approx(1.0, rel=1e-12)
    assert in_mm.volume / in_m.volume == pytest.approx(1e-9, rel=1e-12)
    assert in_inch.volume == pytest.approx(0.0254**3, rel=1e-12)
    np.testing.assert_allclose(in_mm.extents, [2e-3, 1e-3, 0.5e-3], rtol=1e-12)


def test_unknown_units_named(tmp_path):
    path = _write(tmp_path / "block.stl", bar_surface(2.0, 1.0, 0.5))
    with pytest.raises(ValueError, match=r"unknown units 'km'; expected one of 'm', 'mm'"):
        load_surface(path, units="km")


def test_inverted_normals_are_repaired_and_logged(tmp_path, caplog):
    box = bar_surface(0.2, 0.1, 0.05)
    box.invert()
    path = _write(tmp_path / "inside_out.stl", box)
    with caplog.at_level(logging.INFO, logger="flexarm.meshes"):
        surface = load_surface(path)
    assert surface.volume == pytest.approx(1e-3, rel=1e-6)
    assert "inverted the normals (they pointed inward)" in caplog.text


def test_inverted_normals_without_repair_rejected(tmp_path):
    box = bar_surface(0.2, 0.1, 0.05)
    box.invert()
    path = _write(tmp_path / "inside_out.stl", box)
    with pytest.raises(
        MeshError,
        match=re.escape(f"{path}: the surface encloses zero or negative volume (-0.001 m^3)")
        + "; the normals point inward",
    ):
        load_surface(path, repair=False)


def test_duplicated_vertices_and_faces_are_merged(tmp_path, caplog):
    box = bar_surface(0.2, 0.1, 0.05)
    soup = box.triangles.reshape(-1, 3)  # every face with its own three vertices
    faces = np.arange(len(soup)).reshape(-1, 3)
    faces = np.vstack([faces, faces[:1]])  # and one face twice
    path = tmp_path / "soup.obj"
    trimesh.Trimesh(soup, faces, process=False).export(path)
    with caplog.at_level(logging.INFO, logger="flexarm.meshes"):
        surface = load_surface(path)
    assert (len(surface.vertices), len(surface.faces)) == (8, 12)
    assert surface.volume == pytest.approx(1e-3, rel=1e-6)
    assert "merged 28 coincident vertices" in caplog.text
    assert "removed 1 duplicate face" in caplog.text


def test_small_hole_is_filled_with_a_warning(tmp_path, caplog):
    box = bar_surface(0.2, 0.1, 0.05).subdivide().subdivide().subdivide()  # 768 faces
    keep = np.ones(len(box.faces), dtype=bool)
    keep[[0, 377]] = False  # two separate one-triangle holes
    share = box.area_faces[~keep].sum() / box.area  # what the patch must cover
    box.update_faces(keep)
    path = _write(tmp_path / "gaps.stl", box)
    with caplog.at_level(logging.INFO, logger="flexarm.meshes"):
        assert load_surface(path).volume == pytest.approx(1e-3, rel=1e-6)  # float32 STL
    warned = [r.getMessage() for r in caplog.records if r.levelno == logging.WARNING]
    assert warned == [f"{path}: filled holes with 2 faces covering {share:.2%} of the area "
                      "and 0.00% of the volume"]
    with pytest.raises(MeshError, match=r"open \(6 boundary edges\); try repair=True"):
        load_surface(path, repair=False)


@pytest.mark.parametrize(("removed", "volume_error"), [
    ([1, 3], -1 / 6),  # two triangles of neighbouring sides: a diagonal patch
    ([4, 7], -1 / 6),
    ([0, 1], 0.0),  # a whole side: the right patch, but a guess at 13 % of the area
    ([10], 0.0),  # half an end
])
def test_large_fill_is_refused_naming_the_file(tmp_path, removed, volume_error):
    """The 800 x 100 x 100 mm box: trimesh would close each of these holes, some into a
    solid 17 % smaller (the volume it would give is checked independently here)."""
    import flexarm.meshes.repair as rp

    box = trimesh.creation.box((800.0, 100.0, 100.0))
    keep = np.ones(12, dtype=bool)
    keep[removed] = False
    open_box = box.copy()
    open_box.update_faces(keep)
    closed = open_box.copy()
    trimesh.repair.fill_holes(closed)
    assert closed.is_watertight
    assert (abs(closed.volume) - box.volume) / box.volume == pytest.approx(volume_error,
                                                                             abs=1e-9)
    path = _write(tmp_path / "bar.stl", open_box)
    with pytest.raises(MeshError) as err:
        load_surface(path, units="mm")
    msg = str(err.value)
    assert msg.startswith(f"{path}: the surface is open, and closing it takes ")
    area = float(msg.split(" covering ")[1].split("%")[0]) / 100
    assert area > rp.MAX_FILLED_AREA and "different solid" in msg and "\n" not in msg


def test_flipped_face_fixed_by_repair_and_refused_without(tmp_path):
    box = bar_surface(0.2, 0.1, 0.05)
    faces = box.faces.copy()
    faces[3] = faces[3, ::-1]
    path = _write(tmp_path / "flip.ply", trimesh.Trimesh(box.vertices, faces, process=False))
    assert load_surface(path).volume == pytest.approx(1e-3, rel=1e-6)
    with pytest.raises(MeshError, match=re.escape(f"{path}: inconsistent face winding")):
        load_surface(path, repair=False)


def test_sealed_void_is_not_flipped(tmp_path):
    """An internal void's shell encloses negative volume on purpose: keep it."""
    sealed = hollow_link_surface(hand_hole_radius=0.0, segments=24)
    path = _write(tmp_path / "sealed.stl", sealed)
    assert load_surface(path).volume == pytest.approx(sealed.volume, rel=1e-6)


def test_collada_is_read_like_the_others(tmp_path):
    """A DAE (COLLADA, as URDF visuals are published) reads with the caller's units; its
    triangles merge into one closed surface."""
    path = tmp_path / "cube.dae"
    trimesh.creation.box((20.0, 30.0, 40.0)).export(path)
    surface = load_surface(path, units="mm")
    np.testing.assert_allclose(surface.extents, [0.02, 0.03, 0.04], rtol=1e-6)
    assert surface.volume == pytest.approx(2.4e-5, rel=1e-6) and surface.is_watertight
    garbage = tmp_path / "garbage.dae"
    garbage.write_text("<mesh>not collada</mesh>")
    with pytest.raises(ReadError, match=f"garbage.dae: cannot read it as .dae: no '<COLLADA' "
                                        f"element .*{SUPPORTED}$"):
        load_surface(garbage)


def test_missing_file(tmp_path):
    path = tmp_path / "nope.stl"
    with pytest.raises(ReadError, match=f"^{re.escape(str(path))}: no such file$"):
        load_surface(path)


def test_garbage_stl(tmp_path):
    path = tmp_path / "garbage.stl"
    path.write_bytes(np.random.default_rng(0).integers(0, 256, 1000, dtype=np.uint8).tobytes())
    with pytest.raises(
        ReadError,
        match=f"^{re.escape(str(path))}: cannot read it as .stl: "
        f"neither a binary STL .*{SUPPORTED}$",
    ):
        load_surface(path)


def test_garbage_ply_and_obj(tmp_path):
    ply = tmp_path / "garbage.ply"
    ply.write_bytes(b"\x00\x01garbage" * 50)
    with pytest.raises(ReadError, match="garbage.ply: cannot read it as .ply: no 'ply' header"):
        load_surface(ply)
    obj = tmp_path / "garbage.obj"
    obj.write_bytes(b"\x00\xffgarbage" * 50)
    with pytest.raises(ReadError, match=f"cannot read it as .obj: binary bytes .*{SUPPORTED}"):
        load_surface(obj)


def test_unsupported_extension(tmp_path):
    path = tmp_path / "part.step"
    path.write_text("ISO-10303-21;")
    with pytest.raises(ReadError, match=f"part.step: cannot read '.step' files {SUPPORTED}$"):
        load_surface(path)


@pytest.mark.parametrize(
    "name, text",
    [("empty.stl", "solid empty\nendsolid empty\n"), ("empty.obj", "# nothing here\n")],
)
def test_empty_surface(tmp_path, name, text):
    path = tmp_path / name
    path.write_text(text)
    with pytest.raises(MeshError, match=f"^{re.escape(str(path))}: the surface has no faces$"):
        load_surface(path)


def test_empty_binary_stl(tmp_path):
    path = tmp_path / "empty.stl"
    path.write_bytes(b"\x00" * 80 + np.uint32(0).tobytes())
    with pytest.raises(MeshError, match="the surface has no faces"):
        load_surface(path)


def test_open_box_with_large_hole(tmp_path):
    box = bar_surface(0.2, 0.1, 0.05).subdivide().subdivide()
    box.update_faces(box.triangles_center[:, 2] < 0.05 - 1e-9)  # no lid: 4x4 squares
    path = _write(tmp_path / "open.stl", box)
    with pytest.raises(
        MeshError,
        match=re.escape(
            f"{path}: the surface is open (16 boundary edges) and repair could not close it"
        ),
    ):
        load_surface(path)


def test_non_manifold_edge(tmp_path):
    pair = trimesh.util.concatenate(
        [bar_surface(0.1, 0.1, 0.1), bar_surface(0.1, 0.1, 0.1, origin=(0.1, 0.1, 0.0))]
    )
    path = _write(tmp_path / "pair.stl", pair)
    with pytest.raises(MeshError, match=r"not manifold \(1 edge shared by more than two faces\)"):
        load_surface(path)


def test_flat_surface_has_zero_volume(tmp_path):
    box = bar_surface(0.2, 0.1, 0.05)
    vertices = box.vertices.copy()
    vertices[:, 2] = 0.0
    path = _write(tmp_path / "flat.stl", trimesh.Trimesh(vertices, box.faces, process=False))
    with pytest.raises(
        MeshError,
        match=f"^{re.escape(str(path))}: the surface encloses zero volume "
        r"\(all its points lie in a plane\)$",
    ):
        load_surface(path)


def test_absurd_size_for_units(tmp_path):
    path = _write(tmp_path / "huge.stl", bar_surface(900_000.0, 100.0, 100.0))  # 900 km in mm
    with pytest.raises(
        MeshError,
        match=re.escape(
            f"{path}: part is 900 m across with units='mm' (expected 0.001 to 20 m): "
            "are the units right?"
        ),
    ):
        load_surface(path, units="mm")
    tiny = _write(tmp_path / "tiny.stl", bar_surface(0.5, 0.2, 0.2))
    with pytest.raises(MeshError, match=r"part is 0.0005 m across with units='mm'"):
        load_surface(tiny, units="mm")
    assert load_surface(tiny, units="m").volume == pytest.approx(0.02)


def test_a_filled_hole_is_said_once_per_file(tmp_path, caplog, monkeypatch, private_cache):
    """Every command that meshes or measures a link reads its CAD again: the filled hole
    is a warning the first time only, in this process and in later ones."""
    import flexarm.meshes.surface as surface

    box = bar_surface(0.2, 0.1, 0.05).subdivide().subdivide()
    keep = np.ones(len(box.faces), dtype=bool)
    keep[7] = False
    box.update_faces(keep)
    path = _write(tmp_path / "gap.stl", box)

    def warnings_of(n_loads: int) -> list[str]:
        caplog.clear()
        with caplog.at_level(logging.INFO, logger="flexarm.meshes"):
            for _ in range(n_loads):
                load_surface(path)
        return [r.getMessage() for r in caplog.records if r.levelno == logging.WARNING]

    first = warnings_of(3)
    assert len(first) == 1 and "filled holes with 1 face" in first[0]
    assert "filled holes" in caplog.text  # the later reads still log it, as info
    monkeypatch.setattr(surface, "_SAID", set())  # a later command: a new process
    assert warnings_of(1) == []
    monkeypatch.setenv("FLEXARM_CACHE", str(tmp_path / "other-cache"))
    monkeypatch.setattr(surface, "_SAID", set())
    assert len(warnings_of(1)) == 1  # nobody has said it under that cache
