# ruff: noqa: E501
import shutil
import warnings
from pathlib import Path

import numpy as np
import pytest

from flexarm.assembly.analyses import modes
from flexarm.assembly.emodel import emodel
from flexarm.robot.demo_arm import demo_robot_path
from flexarm.robot.formats import toml as robot_toml
from flexarm.robot.formats import urdf

IRB = Path(__file__).resolve().parents[3] / "shared" / "data" / "irb4600"
IRB_URDF = IRB / "urdf" / "irb4600_60_205.urdf"
if not IRB_URDF.is_file():
    IRB_URDF = Path("/work/shared/data/irb4600/urdf/irb4600_60_205.urdf")


@pytest.mark.skipif(not IRB_URDF.is_file(), reason="shared IRB 4600 data not present")
def test_irb4600_urdf_emodel():
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        robot = urdf.read(IRB_URDF)
    assert len(robot.joints) == 6
    assert np.allclose(robot.joints[2].origin, [0, 0, 0.9])
    assert robot.joints[1].upper == pytest.approx(2.617)
    assert robot.links[3].mesh.name == "link_3.stl" and "collision" in str(robot.links[3].mesh)
    f = modes(emodel(robot, method="surface"), np.zeros(6)).freq_hz
    assert len(f) == 6 and np.all(np.isfinite(f)) and f[0] > 0


URDF_TEXT = """<robot name="mini">
  <link name="base"><collision><geometry><mesh filename="package://mini_pkg/meshes/base.stl"/></geometry></collision></link>
  <link name="arm"><visual><geometry><mesh filename="../meshes/lower_arm.stl"/></geometry></visual></link>
  <link name="tool0"/>
  <joint name="j1" type="revolute"><origin xyz="0 0 0.5" rpy="0 0 0"/><axis xyz="0 1 0"/>
    <parent link="base"/><child link="arm"/><limit lower="-1" upper="1"/></joint>
  <joint name="j1-tool0" type="fixed"><parent link="arm"/><child link="tool0"/></joint>
</robot>"""


def test_package_paths_fallback_and_warnings(tmp_path, recwarn):
    pkg = tmp_path / "mini_pkg"
    (pkg / "urdf").mkdir(parents=True)
    (pkg / "meshes").mkdir()
    for name in ("base", "lower_arm"):
        shutil.copy(demo_robot_path().parent / "meshes" / f"{name}.stl", pkg / "meshes")
    (pkg / "package.xml").write_text("<package><name>mini_pkg</name></package>")
    (pkg / "urdf" / "mini.urdf").write_text(URDF_TEXT)
    robot = urdf.read(pkg / "urdf" / "mini.urdf")
    assert robot.links[0].mesh == pkg / "meshes" / "base.stl"
    assert robot.links[1].mesh == (pkg / "meshes" / "lower_arm.stl").resolve()
    msgs = [str(w.message) for w in recwarn]
    assert any("no STL collision mesh, using the visual one" in m for m in msgs)
    # round trip through TOML
    robot_toml.write(tmp_path / "mini.toml", robot)
    back = robot_toml.read(tmp_path / "mini.toml")
    assert back.joint_names == ("j1",) and back.links[1].mesh == robot.links[1].mesh


def test_cli_import_urdf(tmp_path):
    from flexarm.cli import main

    if not IRB_URDF.is_file():
        pytest.skip("shared IRB 4600 data not present")
    out = tmp_path / "irb.toml"
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        assert main(["import-urdf", str(IRB_URDF), "-o", str(out)]) == 0
    assert robot_toml.read(out).joint_names[-1] == "joint_6"


def test_import_urdf_total_mass(tmp_path, capsys):
    """The IRB 4600 collision hulls are solid: ~1,790 kg of cast iron for a 435 kg robot.
    ``--total-mass`` scales every density by one factor; the file keeps it."""
    from flexarm.assembly.emodel import total_mass
    from flexarm.cli import main

    if not IRB_URDF.is_file():
        pytest.skip("shared IRB 4600 data not present")
    out = tmp_path / "irb.toml"
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        assert main(["import-urdf", str(IRB_URDF), "-o", str(out), "--total-mass", "435"]) == 0
        solid = total_mass(urdf.read(IRB_URDF), "surface")
    back = robot_toml.read(out)
    assert total_mass(back, "surface") == pytest.approx(435.0, rel=1e-9)
    rho = {lk.material.rho for lk in back.links if lk.mesh is not None}
    assert len(rho) == 1 and rho.pop() == pytest.approx(7100.0 * 435.0 / solid, rel=1e-9)
    assert "435.0 kg" in capsys.readouterr().out
    with pytest.raises(ValueError, match="must exceed the lumped masses"):
        from flexarm.assembly.emodel import with_total_mass

        with_total_mass(back, 0.0)
