"""Pinned meshes make a robot file a function of its inputs: fTetWild's elements (which
differ between two meshings of the same CAD) written once, then every build in any
empty cache gives the same model to the last bit."""

from __future__ import annotations

import re

import numpy as np
import pytest

from flexarm.assembly.pin_meshes import pin_meshes, pinned_folder
from flexarm.meshes import read_volume_mesh
from flexarm.robot import load_robot
from flexarm.robot.formats.toml import write as write_toml
from flexarm.robot.seats import detect_regions

from ..cli_run import run_cli
from ..primitive_arm import primitive_arm_robot

SIZE = 0.06


@pytest.fixture(scope="module")
def tetwild_arm(tmp_path_factory):
    """The primitive arm with seats, meshed by fTetWild, as a robot file."""
    pytest.importorskip("pytetwild", exc_type=ImportError)
    folder = tmp_path_factory.mktemp("pin")
    path = folder / "arm.toml"
    write_toml(path, detect_regions(primitive_arm_robot(folder, mesher="tetwild")))
    return path


def _frequencies(text: str) -> np.ndarray:
    return np.array([float(f) for f in re.findall(r"^\s*\d+\s+(\d+\.\d+)\s", text, flags=re.M)])


def _build_and_modes(robot: str, cache, monkeypatch) -> tuple[str, np.ndarray]:
    monkeypatch.setenv("FLEXARM_CACHE", str(cache))
    code, built, err = run_cli(["build", "--robot", robot, "--mesh-size", str(SIZE)])
    assert code == 0, err
    code, out, err = run_cli(["modes", "--robot", robot, "--model", "cb", "--mesh-size",
                              str(SIZE), "--pose", "home", "-n", "6"])
    assert code == 0, err
    return built, _frequencies(out)


@pytest.fixture(scope="module")
def pinned_path(tetwild_arm, tmp_path_factory):
    """``flexarm build --pin`` of the fTetWild arm (meshed once, in its own cache)."""
    folder = tmp_path_factory.mktemp("pinned")
    with pytest.MonkeyPatch.context() as mp:
        mp.setenv("FLEXARM_CACHE", str(folder / "cache"))
        code, out, err = run_cli(["build", "--robot", str(tetwild_arm), "--mesh-size",
                                  str(SIZE), "--pin", str(folder / "cell" / "arm_pinned.toml")])
    assert code == 0, err
    assert re.search(r"^arm\s+tetwild\s+\d+\s+arm_60mm\.vtu$", out, flags=re.M), out
    assert ("fTetWild never meshes twice alike, so a build in a fresh cache differs: "
            "`flexarm build --pin OUT.toml` keeps these elements") in out
    return folder / "cell" / "arm_pinned.toml"


def test_a_pinned_robot_builds_the_same_model_in_two_empty_caches(pinned_path, tmp_path,
                                                                   monkeypatch):
    runs = [_build_and_modes(str(pinned_path), tmp_path / cache, monkeypatch)
            for cache in ("second", "third")]
    (table, first), (_, second) = runs
    # every meshed link read from its pinned file, not meshed again
    assert re.findall(r"^(\w+)\s+file\*?\s", table, flags=re.M) == ["base", "column", "arm",
                                                                   "hub"], table
    assert len(first) == 6 and np.all(first > 0)
    np.testing.assert_array_equal(first, second)
    # the pinned elements are the ones the build made: same node coordinates, same cells
    robot = load_robot(pinned_path)
    for link in robot.links:
        assert set(link.volume_meshes) == {SIZE}
        pinned = read_volume_mesh(link.volume_meshes[SIZE])
        assert pinned.n_tets > 0 and pinned.order == 1


def test_pinning_again_keeps_the_elements_and_the_paths_relative(tetwild_arm, pinned_path,
                                                                   tmp_path, monkeypatch):
    monkeypatch.setenv("FLEXARM_CACHE", str(tmp_path / "cache"))  # empty: nothing to mesh
    robot = load_robot(tetwild_arm)
    first = load_robot(pinned_path)
    again = pin_meshes(first, tmp_path / "sub" / "b.toml", SIZE)
    # a link that names a file for the size keeps its elements, byte for byte
    assert again.meshers == ("file",) * 4
    for f, g in zip([lk.volume_meshes[SIZE] for lk in first.links], again.files, strict=True):
        a, b = read_volume_mesh(f), read_volume_mesh(g)
        np.testing.assert_array_equal(a.points, b.points)
        np.testing.assert_array_equal(a.tets, b.tets)
    text = (tmp_path / "sub" / "b.toml").read_text()
    assert '"0.06" = "b_tets/arm_60mm.vtu"' in text  # relative: the folder can move
    moved = load_robot(again.robot_path)
    assert [lk.mesh.resolve() for lk in moved.links] == [lk.mesh.resolve() for lk in robot.links]
    assert sorted(p.name for p in pinned_folder(tmp_path / "sub" / "b.toml").iterdir()) == [
        "arm_60mm.vtu", "base_60mm.vtu", "column_60mm.vtu", "hub_60mm.vtu"]


def test_a_pin_file_that_is_not_toml_is_refused_before_any_meshing(tetwild_arm, tmp_path):
    code, out, err = run_cli(["build", "--robot", str(tetwild_arm), "--pin",
                              str(tmp_path / "arm.urdf")])
    assert code == 2 and out == ""
    assert err.strip().splitlines() == [
        f"flexarm build: error: --pin: {tmp_path / 'arm.urdf'}: the pinned robot file must "
        "be a .toml"]
    assert list(tmp_path.iterdir()) == []


def test_a_tet10_robot_pins_the_corners_of_its_elements(demo_robot, tmp_path):
    import dataclasses

    tet10 = dataclasses.replace(demo_robot, options=dataclasses.replace(
        demo_robot.options, element_order=2))
    pinned = pin_meshes(tet10, tmp_path / "arm10.toml", 0.03)
    for link, file in zip(demo_robot.links, pinned.files, strict=True):
        shipped, written = read_volume_mesh(link.volume_meshes[0.03]), read_volume_mesh(file)
        assert written.order == 1
        np.testing.assert_array_equal(written.points, shipped.points)
        np.testing.assert_array_equal(written.tets, shipped.tets)
