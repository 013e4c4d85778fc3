"""A second published robot that no one here drew: a UR5-class arm.

The joint origins, axes, limits and link masses are those of Universal Robots' UR5 as
published in ROS-Industrial's ``ur_description`` (``ur5.urdf.xacro``: d1 = 0.089159 m,
shoulder offset 0.13585 m, a2 = 0.425 m, elbow offset 0.1197 m, a3 = 0.39225 m,
d4 = 0.093 m, d5 = 0.09465 m, d6 = 0.0823 m; 18.4 kg).  The link shapes are URDF
``<cylinder>``/``<box>`` primitives written here (hubs around each joint axis, tubes
between them), several collision elements per link, so the importer unions them and the
seat finder has to find every bearing seat itself: no ``[links.regions]`` is written.
"""

from __future__ import annotations

import math
import re

import numpy as np
import pytest

from flexarm.assembly.analyses import modes, tcp_compliance
from flexarm.assembly.arm import ArmSpec, build_arm
from flexarm.robot import load_robot
from flexarm.robot.kinematics import tcp_frame

from ..cli_run import run_cli
from ..primitive_arm import urdf_cylinder as _cyl

pytestmark = pytest.mark.filterwarnings("ignore:.*placeholder stiffness")

H = 0.02  # [m] tet edge of the build
R90 = f"{math.pi / 2:.9f}"
ALONG_Y = f"{R90} 0 0"  # a URDF cylinder's axis is its z: roll it onto y

# joint: (parent, child, xyz, rpy, axis, effort [N m]) of ur5.urdf.xacro
JOINTS = {
    "shoulder_pan_joint": ("base_link", "shoulder_link", "0 0 0.089159", "0 0 0", "0 0 1", 150),
    "shoulder_lift_joint": ("shoulder_link", "upper_arm_link", "0 0.13585 0", f"0 {R90} 0",
                            "0 1 0", 150),
    "elbow_joint": ("upper_arm_link", "forearm_link", "0 -0.1197 0.425", "0 0 0", "0 1 0", 150),
    "wrist_1_joint": ("forearm_link", "wrist_1_link", "0 0 0.39225", f"0 {R90} 0", "0 1 0", 28),
    "wrist_2_joint": ("wrist_1_link", "wrist_2_link", "0 0.093 0", "0 0 0", "0 0 1", 28),
    "wrist_3_joint": ("wrist_2_link", "wrist_3_link", "0 0 0.09465", "0 0 0", "0 1 0", 28),
}
MASSES = {"base_link": 4.0, "shoulder_link": 3.7, "upper_arm_link": 8.393,
          "forearm_link": 2.275, "wrist_1_link": 1.219, "wrist_2_link": 1.219,
          "wrist_3_link": 0.1879}


def _box(size, xyz):
    return (f'<collision><origin xyz="{xyz}" rpy="0 0 0"/><geometry>'
            f'<box size="{size}"/></geometry></collision>')


# Each link in its own frame (the frame of the joint that carries it).  Neighbouring
# links meet face to face at each joint: the hubs' end faces are the bearing seats.
SHAPES = {
    "base_link": [_cyl(0.075, 0.029, "0 0 0.0145")],  # top face at z = 0.029
    "shoulder_link": [_cyl(0.06, 0.12, "0 0 0"),  # bottom face on the base
                      _cyl(0.055, 0.075, "0 0.0375 0", ALONG_Y)],  # +y face at y = 0.075
    "upper_arm_link": [_cyl(0.055, 0.06, "0 -0.03 0", ALONG_Y),  # -y face at y = -0.06
                       _box("0.05 0.05 0.425", "0 -0.03 0.2125"),
                       _cyl(0.05, 0.06, "0 -0.03 0.425", ALONG_Y)],  # elbow hub
    "forearm_link": [_cyl(0.05, 0.0597, "0 0.02985 0", ALONG_Y),  # +y... meets the elbow
                     _box("0.04 0.04 0.39225", "0 0.03 0.196125"),
                     _cyl(0.045, 0.06, "0 0.03 0.39225", ALONG_Y)],  # wrist-1 hub
    "wrist_1_link": [_cyl(0.045, 0.078, "0 0.099 0", ALONG_Y),  # y 0.06 .. 0.138
                     _cyl(0.045, 0.05, "0 0.093 0.025")],  # +z face at z = 0.05
    "wrist_2_link": [_cyl(0.045, 0.0897, "0 0 0.09485"),  # z 0.05 .. 0.1397
                     _cyl(0.045, 0.05, "0 0.025 0.09465", ALONG_Y)],  # +y face at y = 0.05
    "wrist_3_link": [_cyl(0.045, 0.0323, "0 0.06615 0", ALONG_Y)],  # y 0.05 .. 0.0823
}


def ur5_urdf() -> str:
    links = []
    for name, mass in MASSES.items():
        links.append(f'<link name="{name}"><inertial><mass value="{mass}"/>'
                     '<origin xyz="0 0 0"/><inertia ixx="0.01" ixy="0" ixz="0" iyy="0.01" '
                     f'iyz="0" izz="0.01"/></inertial>{"".join(SHAPES[name])}</link>')
    links.append('<link name="tool0"/>')
    joints = []
    for name, (parent, child, xyz, rpy, axis, effort) in JOINTS.items():
        joints.append(f'<joint name="{name}" type="revolute"><parent link="{parent}"/>'
                      f'<child link="{child}"/><origin xyz="{xyz}" rpy="{rpy}"/>'
                      f'<axis xyz="{axis}"/><limit lower="{-2 * math.pi:.6f}" '
                      f'upper="{2 * math.pi:.6f}" effort="{effort}" velocity="3.15"/></joint>')
    joints.append('<joint name="wrist_3_link-tool0_fixed_joint" type="fixed">'
                  '<parent link="wrist_3_link"/><child link="tool0"/>'
                  f'<origin xyz="0 0.0823 0" rpy="{-math.pi / 2:.9f} 0 0"/></joint>')
    return f'<?xml version="1.0"?>\n<robot name="ur5">{"".join(links + joints)}</robot>\n'


_run = run_cli


@pytest.fixture(scope="module")
def ur5(tmp_path_factory):
    folder = tmp_path_factory.mktemp("ur5")
    (folder / "ur5.urdf").write_text(ur5_urdf())
    toml = folder / "ur5.toml"
    code, out, err = _run(["import-urdf", str(folder / "ur5.urdf"), "--total-mass", "18.4",
                           "-o", str(toml)])
    assert code == 0, err
    return toml, out, err


def test_ur5_imports_with_every_seat_found(ur5):
    toml, out, err = ur5
    assert not [ln for ln in err.splitlines() if ln.strip()], err  # no warning at all
    assert "14 regions found" in out  # 6 joints x 2 links + flange + foundation
    robot = load_robot(toml)
    assert robot.joint_names == tuple(JOINTS)
    # the published chain at zero angles (UR DH: a2 + a3, d4 + d6, d1 - d5)
    tcp = tcp_frame(robot.chain, np.zeros(6))[:3, 3]
    assert tcp == pytest.approx([0.425 + 0.39225, 0.10915 + 0.0823, 0.089159 - 0.09465],
                                abs=1e-9)


def test_ur5_builds_and_runs_modes_cb(ur5):
    toml = str(ur5[0])
    code, out, err = _run(["build", "--robot", toml, "--mesh-size", str(H)])
    assert code == 0, err
    code, out, err = _run(["modes", "--robot", toml, "--model", "cb", "--mesh-size", str(H),
                           "--pose", "0,-90,90,0,90,0", "-n", "6"])
    assert code == 0, err
    f = np.array([float(x) for x in re.findall(r"^\s*\d+\s+(\d+\.\d+)\s", out, re.M)])
    assert len(f) == 6 and np.all(np.isfinite(f)) and f[0] > 0


def test_ur5_cb_is_softer_than_its_rigid_link_emodel(ur5):
    robot = load_robot(ur5[0])
    q = np.radians([0, -90, 90, 0, 90, 0])
    cb = build_arm(robot, ArmSpec("cb", mesh_size=H)).model
    em = build_arm(robot, ArmSpec("emodel", "tets", H)).model
    assert modes(cb, q).freq_hz[0] <= modes(em, q).freq_hz[0] * (1 + 1e-9)
    assert tcp_compliance(cb, q)[1, 1] >= tcp_compliance(em, q)[1, 1] * (1 - 1e-9)
