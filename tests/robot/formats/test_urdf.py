# ruff: noqa: E501
import math
import re
import shutil
import warnings
import xml.etree.ElementTree as ET
from pathlib import Path

import numpy as np
import pytest
import trimesh
import trimesh.transformations as tt

from flexarm.assembly.analyses import modes
from flexarm.assembly.emodel import emodel, link_mass_properties, total_mass
from flexarm.fe.errors import ReadError
from flexarm.meshes import load_surface
from flexarm.robot.demo_arm import demo_robot_path
from flexarm.robot.formats import toml as robot_toml
from flexarm.robot.formats import urdf
from flexarm.robot.kinematics import tcp_frame

IRB = Path(__file__).resolve().parents[3] / "shared" / "data" / "irb4600"
IRB_URDF = IRB / "urdf" / "irb4600_60_205.urdf"
if not IRB_URDF.is_file():
    IRB_URDF = Path("/work/shared/data/irb4600/urdf/irb4600_60_205.urdf")


@pytest.mark.skipif(not IRB_URDF.is_file(), reason="shared IRB 4600 data not present")
def test_irb4600_urdf_emodel():
    with warnings.catch_warnings():
        warnings.simplefilter("error")
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
    assert any("link 'arm': no collision geometry, using the visual one" in m for m in msgs)
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
        warnings.simplefilter("error")
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
        warnings.simplefilter("error")
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


# --- URDFs as they are published: synthetic packages written by the tests ---------------
HALF_PI = "1.5707963267948966"
MASS = '<inertial><mass value="1"/></inertial>'


def _frame(xyz=(0, 0, 0), rpy=(0, 0, 0)):
    """URDF origin as trimesh builds it (static-axes x-y-z Euler = Rz Ry Rx), independent of
    the code under test."""
    T = tt.euler_matrix(*rpy, axes="sxyz")
    T[:3, 3] = xyz
    return T


def _box(path, extents, units=1.0):
    mesh = trimesh.creation.box(extents=np.asarray(extents) / units)
    mesh.export(path)
    return trimesh.creation.box(extents=extents)


def _package(tmp_path, name="demo_pkg"):
    pkg = tmp_path / name
    (pkg / "urdf").mkdir(parents=True)
    (pkg / "meshes").mkdir()
    (pkg / "package.xml").write_text(f"<package><name>{name}</name></package>")
    return pkg


def _write_urdf(pkg, body, name="robot.urdf"):
    path = pkg / "urdf" / name
    path.write_text(f'<robot name="t">{body}</robot>')
    return path


def _geom(filename, kind="collision", xyz="0 0 0", rpy="0 0 0", scale="1 1 1"):
    """A ``<visual>`` or ``<collision>`` mesh element."""
    return (f'<{kind}><origin xyz="{xyz}" rpy="{rpy}"/><geometry><mesh filename="{filename}" '
            f'scale="{scale}"/></geometry></{kind}>')


def _joint(name, parent, child, xyz="0 0 0", rpy="0 0 0", axis="0 0 1", kind="revolute"):
    limit = '<limit lower="-3" upper="3"/>' if kind == "revolute" else ""
    return (f'<joint name="{name}" type="{kind}"><origin xyz="{xyz}" rpy="{rpy}"/>'
            f'<axis xyz="{axis}"/><parent link="{parent}"/><child link="{child}"/>{limit}'
            "</joint>")


@pytest.fixture
def multi(tmp_path):
    """A base of three visual elements with origins (OBJ, PLY, DAE in mm) and an arm whose
    one DAE is found through package://."""
    pkg = _package(tmp_path)
    m = pkg / "meshes"
    pieces = [(_box(m / "plate.obj", (0.4, 0.3, 0.1)), _frame((0, 0, 0.05))),
              (_box(m / "post.ply", (0.1, 0.05, 0.2)), _frame((0.3, 0, 0.1), (0, 0, math.pi / 2))),
              (_box(m / "block.dae", (0.1, 0.06, 0.04), units=1e-3),
               _frame((-0.3, 0, 0.1), (math.pi / 2, 0, 0)))]
    _box(m / "arm.dae", (0.6, 0.1, 0.1))
    path = _write_urdf(pkg, f"""
      <link name="base">
        {_geom("../meshes/plate.obj", "visual", xyz="0 0 0.05")}
        {_geom("../meshes/post.ply", "visual", xyz="0.3 0 0.1", rpy=f"0 0 {HALF_PI}")}
        {_geom("package://demo_pkg/meshes/block.dae", "visual", xyz="-0.3 0 0.1",
               rpy=f"{HALF_PI} 0 0", scale="0.001 0.001 0.001")}
      </link>
      <link name="arm">{_geom("package://demo_pkg/meshes/arm.dae", "visual")}</link>
      {_joint("j1", "base", "arm", xyz="0 0 0.2")}""")
    expected = trimesh.util.concatenate([b.copy().apply_transform(T) for b, T in pieces])
    return path, expected


def test_several_elements_with_origins_become_one_derived_mesh(multi, tmp_path):
    path, expected = multi
    out = tmp_path / "derived"
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        imp = urdf.load(path, meshes="visual", derived_dir=out)
    base, arm = imp.robot.links
    assert base.mesh.parent == out and re.fullmatch(r"base-[0-9a-f]{16}\.ply", base.mesh.name)
    assert imp.derived == {"base": base.mesh} and base.units == "m" and base.regions == {}
    got = trimesh.load(base.mesh, force="mesh")
    np.testing.assert_allclose(got.bounds, expected.bounds, atol=1e-6)
    assert got.volume == pytest.approx(expected.volume, rel=1e-6)
    np.testing.assert_allclose(got.center_mass, expected.center_mass, atol=1e-6)
    # the one DAE at the link frame is used as published (through package://)
    assert arm.mesh == (path.parents[1] / "meshes" / "arm.dae").resolve() and arm.units == "m"
    assert load_surface(arm.mesh, arm.units).volume == pytest.approx(0.006, rel=1e-6)
    # importing again reuses the derived file (named by content)
    mtime = base.mesh.stat().st_mtime_ns
    again = urdf.read(path, meshes="visual", derived_dir=out)
    assert again.links[0].mesh == base.mesh and base.mesh.stat().st_mtime_ns == mtime
    assert len(list(out.iterdir())) == 1


@pytest.mark.parametrize("scale, units, extents", [
    ("0.001 0.001 0.001", "mm", (0.2, 0.1, 0.1)),  # a unit: the published file, in mm
    ("2 1 0.5", None, (0.4, 0.1, 0.05)),  # non-uniform: applied to the vertices
    ("0.5 0.5 0.5", None, (0.1, 0.05, 0.05)),  # uniform but not a unit: applied too
])
def test_mesh_scale(tmp_path, scale, units, extents):
    pkg = _package(tmp_path)
    _box(pkg / "meshes" / "arm.stl", (0.2, 0.1, 0.1), units=1e-3 if units else 1.0)
    path = _write_urdf(pkg, f"""<link name="base">{MASS}</link>
      <link name="arm"><collision><geometry><mesh filename="../meshes/arm.stl" scale="{scale}"/>
      </geometry></collision></link>{_joint("j1", "base", "arm")}""")
    arm = urdf.read(path, derived_dir=tmp_path / "d").links[1]
    if units:
        assert arm.mesh == pkg / "meshes" / "arm.stl" and arm.units == units
    else:
        assert arm.mesh.parent == tmp_path / "d" and arm.units == "m"
    np.testing.assert_allclose(load_surface(arm.mesh, arm.units).extents, extents, rtol=1e-6)


def test_link_with_only_inertial_is_a_lumped_mass(tmp_path):
    pkg = _package(tmp_path)
    path = _write_urdf(pkg, f"""<link name="base">{MASS}</link>
      <link name="arm"><inertial><origin xyz="0.1 0.2 0.3" rpy="0 0 {HALF_PI}"/>
        <mass value="12.5"/><inertia ixx="1" ixy="0" ixz="0" iyy="2" iyz="0" izz="3"/>
      </inertial></link>{_joint("j1", "base", "arm")}""")
    arm = urdf.read(path).links[1]
    assert arm.mesh is None and len(arm.lumped) == 1
    lm = arm.lumped[0]
    assert lm.mass == 12.5 and lm.position == pytest.approx((0.1, 0.2, 0.3))
    np.testing.assert_allclose(lm.inertia, np.diag([2.0, 1.0, 3.0]), atol=1e-12)
    mp = link_mass_properties(arm)
    assert mp.mass == 12.5 and np.allclose(mp.center_of_mass, [0.1, 0.2, 0.3])


def test_fixed_joint_merges_geometry_and_inertial(tmp_path):
    """arm + motor (fixed, with its own element origin) + cable (fixed to the motor, only
    an inertial): one link whose mass, centre of mass and inertia are those of the union
    of the pieces (they overlap) and the cable's inertial."""
    pkg = _package(tmp_path)
    m = pkg / "meshes"
    base, arm, motor = (_box(m / "base.stl", (0.3, 0.3, 0.1)), _box(m / "arm.stl", (0.8, 0.1, 0.1)),
                        _box(m / "motor.stl", (0.12, 0.1, 0.08)))
    path = _write_urdf(pkg, f"""
      <link name="base">{_geom("../meshes/base.stl")}</link>
      <link name="arm">{_geom("../meshes/arm.stl", xyz="0.4 0 0")}
        <inertial><mass value="99"/></inertial></link>
      <link name="motor">{_geom("../meshes/motor.stl", xyz="0.05 0 0", rpy=f"0 {HALF_PI} 0")}</link>
      <link name="cable"><inertial><origin xyz="0 0.1 0"/><mass value="3"/>
        <inertia ixx="0.01" ixy="0" ixz="0" iyy="0.02" iyz="0" izz="0.03"/></inertial></link>
      {_joint("j1", "base", "arm", xyz="0 0 0.3", axis="0 1 0")}
      {_joint("arm-motor", "arm", "motor", xyz="0.6 0 0.1", rpy="0.3 0 0.5", kind="fixed")}
      {_joint("motor-cable", "motor", "cable", xyz="0 0 0.2", kind="fixed")}""")
    imp = urdf.load(path, derived_dir=tmp_path / "d")
    robot = imp.robot
    assert [lk.name for lk in robot.links] == ["base", "arm"] and robot.joint_names == ("j1",)
    assert imp.merged == {"arm": ("motor", "cable")} and set(imp.derived) == {"arm"}
    assert robot.links[0].mesh == m / "base.stl"  # published, untouched
    rho = robot.links[1].material.rho
    T_motor = _frame((0.6, 0, 0.1), (0.3, 0, 0.5))
    pieces = [arm.copy().apply_transform(_frame((0.4, 0, 0))),
              motor.copy().apply_transform(T_motor @ _frame((0.05, 0, 0), (0, math.pi / 2, 0)))]
    cable_T = T_motor @ _frame((0, 0, 0.2)) @ _frame((0, 0.1, 0))
    # the motor overlaps the arm: one solid, the overlap counted once
    solid = trimesh.boolean.union(pieces, engine="manifold")
    assert solid.volume < sum(p.volume for p in pieces) - 5e-5
    masses = [rho * solid.volume, 3.0]
    centres = [solid.center_mass, cable_T[:3, 3]]
    mass = sum(masses)
    com = sum(mi * ci for mi, ci in zip(masses, centres, strict=True)) / mass
    R = cable_T[:3, :3]
    inertia = rho * solid.moment_inertia + R @ np.diag([0.01, 0.02, 0.03]) @ R.T
    for mi, ci in zip(masses, centres, strict=True):
        d = ci - com
        inertia = inertia + mi * (d @ d * np.eye(3) - np.outer(d, d))
    mp = link_mass_properties(robot.links[1])
    assert mp.mass == pytest.approx(mass, rel=1e-6)
    np.testing.assert_allclose(mp.center_of_mass, com, atol=1e-6)
    np.testing.assert_allclose(mp.inertia, inertia, rtol=1e-5, atol=1e-6 * np.abs(inertia).max())
    assert total_mass(robot) == pytest.approx(mass + rho * base.volume, rel=1e-6)


def _tool_chain(tool0: bool = True) -> str:
    """world (a pure frame) - base - j1 - l1 - j2 - l2 - flange (- tool0), all fixed but
    j1 and j2."""
    body = (f'<link name="base">{MASS}</link><link name="l1">{MASS}</link>'
            f'<link name="l2">{MASS}</link><link name="flange"/><link name="world"/>'
            + _joint("j1", "base", "l1", xyz="0 0 0.4")
            + _joint("j2", "l1", "l2", xyz="0.1 0 0.3", rpy="0.2 -0.1 0.4", axis="0 1 0")
            + _joint("l2-flange", "l2", "flange", xyz="0.5 0.02 -0.03", rpy="0.1 0.2 0.3",
                     kind="fixed")
            + _joint("world-base", "world", "base", kind="fixed"))
    if tool0:
        body += '<link name="tool0"/>' + _joint("flange-tool0", "flange", "tool0",
                                                xyz="0 0 0.12", rpy=f"0 {HALF_PI} 0", kind="fixed")
    return body


def test_tool0_frame_is_the_tcp(tmp_path):
    """The TCP at any pose is the forward kinematics of the URDF chain to tool0; a pure
    frame at the root (world) and the flange merge away."""
    pkg = _package(tmp_path)
    imp = urdf.load(_write_urdf(pkg, _tool_chain()))
    robot = imp.robot
    assert imp.tool_frame == "tool0" and robot.tool.link == "l2"
    assert [lk.name for lk in robot.links] == ["world", "l1", "l2"]
    assert imp.merged == {"world": ("base",), "l2": ("flange", "tool0")}
    for q in ([0.0, 0.0], [0.7, -0.4], [-2.0, 1.3]):
        T = (_frame((0, 0, 0.4)) @ tt.rotation_matrix(q[0], [0, 0, 1])
             @ _frame((0.1, 0, 0.3), (0.2, -0.1, 0.4)) @ tt.rotation_matrix(q[1], [0, 1, 0])
             @ _frame((0.5, 0.02, -0.03), (0.1, 0.2, 0.3))
             @ _frame((0, 0, 0.12), (0, math.pi / 2, 0)))
        np.testing.assert_allclose(tcp_frame(robot.chain, q), T, atol=1e-12)
    imp = urdf.load(_write_urdf(pkg, _tool_chain(tool0=False), "flange.urdf"))
    assert imp.tool_frame == "flange" and imp.robot.tool.link == "l2"
    assert imp.robot.tool.xyz == pytest.approx((0.5, 0.02, -0.03))
    assert imp.robot.tool.rpy == pytest.approx((0.1, 0.2, 0.3))


BASE = f'<link name="a">{MASS}</link><link name="b">{MASS}</link>{_joint("j1", "a", "b")}'


@pytest.mark.parametrize("body, message", [
    (BASE + f'<link name="c">{MASS}</link>{_joint("j2", "ghost", "c")}',
     "joint 'j2': parent link 'ghost' does not exist"),
    (BASE + _joint("j2", "b", "ghost"), "joint 'j2': child link 'ghost' does not exist"),
    (BASE + f'<link name="c">{MASS}</link>{_joint("j2", "b", "c")}{_joint("j3", "a", "c")}',
     "closed loop: link 'c' is the child of joints 'j2' and 'j3'"),
    (BASE + f'<link name="c">{MASS}</link><link name="d">{MASS}</link>'
     + _joint("j2", "c", "d") + _joint("j3", "d", "c"),
     "closed loop: joints j2 -> j3 form a cycle"),
    (BASE + _joint("j2", "b", "a"), "closed loop: joints j1 -> j2 form a cycle"),
    (BASE + f'<link name="b">{MASS}</link>', "duplicate link name 'b'"),
    (BASE + f'<link name="c">{MASS}</link>{_joint("j1", "b", "c")}', "duplicate joint name 'j1'"),
    (BASE + f'<link name="c">{MASS}</link>{_joint("slide", "b", "c", kind="prismatic")}',
     "joint 'slide': type 'prismatic' is not supported"),
    (BASE + f'<link name="c">{MASS}</link>{_joint("free", "b", "c", kind="floating")}',
     "joint 'free': type 'floating' is not supported"),
    (BASE + f'<link name="c">{MASS}</link>{_joint("flat", "b", "c", kind="planar")}',
     "joint 'flat': type 'planar' is not supported"),
    (BASE + f'<link name="c"/>{_joint("j2", "b", "c")}',
     "link 'c' (a moving link) has no mesh and no <inertial> mass"),
    (BASE.replace(f'<link name="a">{MASS}</link>', '<link name="a"/>'),
     "link 'a' (the base) has no mesh and no <inertial> mass"),
    (BASE + '<link name="c"><visual><geometry><mesh filename="../meshes/nope.stl"/></geometry>'
     f'</visual></link>{_joint("j2", "b", "c")}', "link 'c': mesh file not found: "),
    (BASE + '<link name="c"><visual><geometry><mesh filename="../meshes/c.step"/></geometry>'
     f'</visual></link>{_joint("j2", "b", "c")}',
     "link 'c': mesh '../meshes/c.step': '.step' files are not supported"),
    (BASE + '<link name="c"><visual><geometry><mesh filename="package://elsewhere/c.stl"/>'
     f'</geometry></visual></link>{_joint("j2", "b", "c")}',
     "link 'c': mesh 'package://elsewhere/c.stl': package://elsewhere: no package.xml"),
    (BASE + f'<link name="c">{MASS}</link>' + _joint("j2", "b", "c").replace(
        'lower="-3" upper="3"', 'lower="1" upper="-1"'), "joint 'j2': limit lower=1 must be"),
    (f'<link name="a">{MASS}</link>', "no revolute or continuous joints"),
], ids=["missing parent", "missing child", "two parents", "detached cycle", "cycle", "dup link",
        "dup joint", "prismatic", "floating", "planar", "massless link", "massless base",
        "missing mesh", "step mesh", "unknown package", "reversed limits", "nothing moves"])
def test_errors_name_the_file_and_the_joint_or_link(tmp_path, body, message):
    path = _write_urdf(_package(tmp_path), body, "bad.urdf")
    with pytest.raises(ReadError, match=f"^{re.escape(str(path))}: {re.escape(message)}"):
        urdf.read(path)


def test_pure_frames_and_fixed_frames_are_not_errors(tmp_path):
    path = _write_urdf(_package(tmp_path), BASE + '<link name="frame"/>'
                       + _joint("b-frame", "b", "frame", kind="fixed"))
    imp = urdf.load(path)
    assert imp.merged == {"b": ("frame",)} and imp.tool_frame is None


def test_placeholder_stiffness_round_trips_through_toml(tmp_path):
    path = _write_urdf(_package(tmp_path), BASE)
    robot = urdf.read(path)
    assert [j.model.source for j in robot.joints] == ["placeholder"]
    assert robot.joints[0].model.torsion == urdf.DEFAULT_TORSION[0]
    robot_toml.write(tmp_path / "r.toml", robot)
    text = (tmp_path / "r.toml").read_text()
    assert text.count("placeholder = true") == 1
    assert robot_toml.read(tmp_path / "r.toml").joints[0].model.is_placeholder
    (tmp_path / "r.toml").write_text(text.replace("placeholder = true", 'placeholder = "yes"'))
    with pytest.raises(ReadError, match=r"joints\.j1\.model\.placeholder must be true or false"):
        robot_toml.read(tmp_path / "r.toml")
    (tmp_path / "r.toml").write_text(text.replace("placeholder = true\n", ""))
    assert not robot_toml.read(tmp_path / "r.toml").joints[0].model.is_placeholder
    # files with given stiffness are written as before: no placeholder key
    robot_toml.write(tmp_path / "demo.toml", robot_toml.read(demo_robot_path()))
    assert "placeholder" not in (tmp_path / "demo.toml").read_text()


def test_cli_import_writes_relocatable_toml(tmp_path, capsys):
    """Derived meshes go next to the TOML, published ones are referenced relatively: the
    folder holding both moves as a whole."""
    from flexarm.cli import main

    pkg = _package(tmp_path / "a")
    for name, ext in (("base", (0.3, 0.3, 0.1)), ("arm", (0.8, 0.1, 0.1)), ("cap", (0.1,) * 3)):
        _box(pkg / "meshes" / f"{name}.stl", ext)
    urdf_path = _write_urdf(pkg, "".join(
        f'<link name="{n}">{_geom(f"../meshes/{n}.stl")}</link>' for n in ("base", "arm", "cap"))
        + '<link name="tool0"/>' + _joint("j1", "base", "arm")
        + _joint("arm-cap", "arm", "cap", xyz="0.45 0 0", kind="fixed")
        + _joint("cap-tool0", "cap", "tool0", xyz="0.05 0 0", kind="fixed"))
    out = tmp_path / "a" / "out" / "robot.toml"
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        assert main(["import-urdf", str(urdf_path), "-o", str(out), "--no-regions"]) == 0
    text = capsys.readouterr()
    assert text.err == ""
    lines = text.out.splitlines()
    assert lines[0].startswith(f"wrote {out}: 2 links, 1 joint, ")
    assert lines[1] == ("links: base, arm (+ cap, tool0); meshes: 1 as published, 1 derived in "
                        f"{out.parent / 'robot_meshes'}")
    assert lines[3] == "tool: tool0 on arm, xyz [0.5, 0, 0] m, rpy [0, 0, 0] deg"
    assert lines[4] == "mass: no URDF <inertial>; solid CAD 127.8 kg (no datasheet mass: the " \
                       "CAD's is used)"
    assert lines[5].startswith("placeholder stiffness (a URDF has none) on j1: identify it ")
    assert "flexarm diagnose" in lines[5] and "--apply" in lines[5]
    text = out.read_text()
    assert 'mesh = "../demo_pkg/meshes/base.stl"' in text
    assert re.search(r'mesh = "robot_meshes/arm-[0-9a-f]{16}\.ply"', text)
    shutil.move(tmp_path / "a", tmp_path / "b")
    back = robot_toml.read(tmp_path / "b" / "out" / "robot.toml")
    assert back.links[1].mesh.parent == tmp_path / "b" / "out" / "robot_meshes"
    assert total_mass(back) == pytest.approx(7100.0 * (0.009 + 0.008 + 0.001), rel=1e-6)


def _urdf_origins(path):
    root = ET.parse(path).getroot()
    return {j.get("name"): [float(v) for v in j.find("origin").get("xyz").split()]
            for j in root.findall("joint") if j.get("type") == "revolute"}


@pytest.mark.skipif(not IRB_URDF.is_file(), reason="shared IRB 4600 data not present")
@pytest.mark.parametrize("meshes, suffix", [("collision", ".stl"), ("visual", ".dae")])
def test_irb4600_imports_without_warnings(tmp_path, meshes, suffix):
    """The collision hulls as published; of the visual meshes, the base's is open (a body
    whose rims cross themselves): one warning naming it, and its hull in a derived file."""
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        imp = urdf.load(IRB_URDF, meshes=meshes, derived_dir=tmp_path / "d")
    robot = imp.robot
    assert len(robot.links) == 7 and len(robot.joints) == 6
    published = robot.links if meshes == "collision" else robot.links[1:]
    if meshes == "collision":
        assert caught == [] and not (tmp_path / "d").exists() and imp.derived == {}
    else:
        (w,) = caught
        assert str(w.message).startswith("base_link.dae: not a closed surface (2 bodies, 1 "
                                         "open, 93 boundary edges); flat patches on its holes")
        assert str(w.message).endswith("replaced by its convex hull (100% of the solid's "
                                       "volume) (link 'base_link')")
        assert list(imp.derived) == ["base_link"]
        assert robot.links[0].mesh.parent == (tmp_path / "d").resolve()
    assert all(lk.mesh.suffix == suffix and meshes in lk.mesh.parent.name for lk in published)
    assert all(lk.regions == {} and lk.lumped == () for lk in robot.links)
    origins = _urdf_origins(IRB_URDF)
    for j in robot.joints:
        assert list(j.origin) == origins[j.name] and j.rpy == (0.0, 0.0, 0.0)
    assert imp.tool_frame == "tool0" and robot.tool.link == "link_6"
    assert robot.tool.xyz == (0.0, 0.0, 0.0)
    assert robot.tool.rpy == pytest.approx((0, math.pi / 2, 0))
    assert imp.merged == {"base_link": ("base",), "link_6": ("flange", "tool0")}
    assert imp.placeholder_joints == robot.joint_names
    T = tcp_frame(robot.chain, np.zeros(6))
    np.testing.assert_allclose(T[:3, 3], [1.27, 0.0, 1.57], atol=1e-12)
    np.testing.assert_allclose(T[:3, 2], [1.0, 0.0, 0.0], atol=1e-12)  # tool z along x


@pytest.mark.skipif(not IRB_URDF.is_file(), reason="shared IRB 4600 data not present")
@pytest.mark.parametrize("meshes", ["collision", pytest.param("visual", marks=pytest.mark.slow)])
def test_cli_irb4600_import_prints_no_warnings(tmp_path, capsys, meshes):
    from flexarm.cli import main

    out = tmp_path / "irb.toml"
    assert main(["import-urdf", str(IRB_URDF), "-o", str(out), "--meshes", meshes]) == 0
    text = capsys.readouterr()
    if meshes == "collision":  # closed hulls: every bearing seat found, nothing to warn
        assert text.err == ""
        assert sum(len(lk.regions) for lk in robot_toml.read(out).links) == 14
    else:  # one real problem, in one line: the open visual base becomes its hull
        assert text.err.startswith("warning: base_link.dae: not a closed surface")
        assert sum("warning: " in ln for ln in text.err.splitlines()) == 1
        assert sum(len(lk.regions) for lk in robot_toml.read(out).links) == 14
    lines = text.out.splitlines()
    assert lines[0].startswith(f"wrote {out}: 7 links, 6 joints, ")
    assert lines[1].startswith("links: base_link (+ base), link_1, ")
    assert ("meshes: 7 as published, 0 derived" if meshes == "collision" else
            "meshes: 6 as published, 1 derived") in lines[1]
    assert lines[3] == "tool: tool0 on link_6, xyz [0, 0, 0] m, rpy [0, 90, 0] deg"
    assert lines[-2].startswith("placeholder stiffness (a URDF has none) on joint_1, joint_2, "
                                "joint_3, joint_4, joint_5, joint_6: ")
    # the visual meshes are no hulls; their small holes are filled, as for meshing
    cad = "1791.7" if meshes == "collision" else "1253.5"
    assert lines[-1].startswith(f"placeholder size rule: {cad} kg (CAD), reach 2.05 m")
    assert (tmp_path / "irb_meshes").exists() == (meshes == "visual")
    assert robot_toml.read(out).joints[0].model.is_placeholder


@pytest.mark.skipif(not IRB_URDF.is_file(), reason="shared IRB 4600 data not present")
def test_xacro_is_refused_with_the_way_out():
    xacro = IRB_URDF.with_name("irb4600_60_205.xacro")
    with pytest.raises(ReadError, match=f"^{re.escape(str(xacro))}: this is a xacro file, not "
                                        r"a URDF: expand it first \(xacro "):
        urdf.read(xacro)


def test_mimic_joint_is_imported_with_a_warning(tmp_path):
    path = _write_urdf(_package(tmp_path), BASE + f'<link name="c">{MASS}</link>'
                       + _joint("j2", "b", "c").replace("</joint>", '<mimic joint="j1"/></joint>'))
    with pytest.warns(UserWarning, match=r"^robot\.urdf: joint 'j2': <mimic joint=\"j1\"> not "
                                         r"modelled \(it turns on its own\)$"):
        robot = urdf.read(path)
    assert robot.joint_names == ("j1", "j2")


def test_primitive_shapes_and_mirrored_meshes_become_closed_derived_meshes(tmp_path):
    """Box, cylinder and sphere elements are meshed; a mirroring scale keeps the surface
    outward (positive volume)."""
    pkg = _package(tmp_path)
    _box(pkg / "meshes" / "arm.stl", (0.2, 0.1, 0.1))
    shapes = [('<box size="0.2 0.1 0.3"/>', 0.006), ('<cylinder radius="0.05" length="0.2"/>',
                                                    math.pi * 0.05**2 * 0.2),
              ('<sphere radius="0.05"/>', 4 / 3 * math.pi * 0.05**3)]
    for k, (shape, volume) in enumerate(shapes):
        path = _write_urdf(pkg, f"""<link name="base">{MASS}</link>
          <link name="arm"><collision><geometry>{shape}</geometry></collision></link>
          {_joint("j1", "base", "arm")}""", f"s{k}.urdf")
        mesh = load_surface(urdf.read(path, derived_dir=tmp_path / "d").links[1].mesh)
        assert mesh.volume == pytest.approx(volume, rel=0.02)
    path = _write_urdf(pkg, f"""<link name="base">{MASS}</link>
      <link name="arm">{_geom("../meshes/arm.stl", scale="-1 1 1")}</link>
      {_joint("j1", "base", "arm")}""", "mirror.urdf")
    mesh = load_surface(urdf.read(path, derived_dir=tmp_path / "d").links[1].mesh, repair=False)
    assert mesh.volume == pytest.approx(0.002, rel=1e-6)


def test_collada_unit_scales_its_coordinates(tmp_path):
    """A DAE drawn in mm (``<unit meter="0.001">``) is used as published in mm, and placed
    in metres when it has to be derived."""
    pkg = _package(tmp_path)
    path = pkg / "meshes" / "arm.dae"
    trimesh.creation.box((200.0, 100.0, 100.0)).export(path)
    path.write_text(path.read_text().replace("<up_axis>", '<unit meter="0.001"/><up_axis>'))
    urdf_path = _write_urdf(pkg, f"""<link name="base">{MASS}</link>
      <link name="arm">{_geom("../meshes/arm.dae", "visual")}</link>
      <link name="tip">{_geom("../meshes/arm.dae", "visual", xyz="0.3 0 0")}</link>
      {_joint("j1", "base", "arm")}{_joint("j2", "arm", "tip")}""")
    arm, tip = urdf.read(urdf_path, meshes="visual", derived_dir=tmp_path / "d").links[1:]
    assert arm.mesh == path and arm.units == "mm"
    np.testing.assert_allclose(load_surface(arm.mesh, arm.units).extents, [0.2, 0.1, 0.1])
    np.testing.assert_allclose(trimesh.load(tip.mesh).bounds, [[0.2, -0.05, -0.05],
                                                               [0.4, 0.05, 0.05]], atol=1e-7)
