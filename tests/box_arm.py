"""A three-link test arm built from boxes (base, column, arm), fast to reduce.

``box_arm_robot(folder)`` writes STL boxes and a robot TOML and reads it back;
``box_mesher`` gives the matching structured Tet4 meshes (same solids, so the
E-model's surface mass properties equal the tet meshes' to round-off).
"""

from __future__ import annotations

import numpy as np

from flexarm.fe.mesh import TetMesh

#: link name -> (size [m], minimum corner [m] in the link frame, divisions)
BOXES = {
    "base": ((0.3, 0.3, 0.4), (-0.15, -0.15, 0.0), (2, 2, 3)),
    "column": ((0.2, 0.2, 0.8), (-0.1, -0.1, 0.0), (2, 2, 6)),
    "arm": ((1.0, 0.12, 0.12), (0.0, -0.06, -0.06), (8, 2, 2)),
}

TOML = """
format_version = 1
name = "box arm"
[model]
element_order = 1
mesh_size = 0.1
cb_modes = 6
[base]
support = "clamped"
[tool]
xyz = [1.0, 0.0, 0.0]
link = "arm"
[poses]
P1 = [0.0, 30.0]
P2 = [40.0, -20.0]
[[links]]
name = "base"
mesh = "base.stl"
material = "steel"
[links.regions.base]
center = [0.0, 0.0, 0.0]
axis = [0.0, 0.0, 1.0]
r_min = 0.0
r_max = 0.3
half_width = 0.001
[links.regions.joint_1]
center = [0.0, 0.0, 0.4]
axis = [0.0, 0.0, 1.0]
r_min = 0.0
r_max = 0.3
half_width = 0.001
[[links]]
name = "column"
mesh = "column.stl"
material = "steel"
[[links.lumped]]
name = "motor_2"
mass = 20.0
position = [0.0, 0.15, 0.75]
inertia = [0.1, 0.05, 0.1]
[links.regions.joint_1]
center = [0.0, 0.0, 0.0]
axis = [0.0, 0.0, 1.0]
r_min = 0.0
r_max = 0.3
half_width = 0.001
[links.regions.joint_2]
center = [0.0, 0.0, 0.8]
axis = [0.0, 0.0, 1.0]
r_min = 0.0
r_max = 0.3
half_width = 0.001
[[links]]
name = "arm"
mesh = "arm.stl"
material = "aluminium"
[links.regions.joint_2]
center = [0.0, 0.0, 0.0]
axis = [1.0, 0.0, 0.0]
r_min = 0.0
r_max = 0.2
half_width = 0.001
[links.regions.tcp]
center = [1.0, 0.0, 0.0]
axis = [1.0, 0.0, 0.0]
r_min = 0.0
r_max = 0.2
half_width = 0.001
coupling = "rbe3"
[[joints]]
name = "joint_1"
parent = "base"
child = "column"
origin = [0.0, 0.0, 0.4]
axis = [0.0, 0.0, 1.0]
limits_deg = [-180.0, 180.0]
[joints.model]
torsion = 1.0e6
tilt = 5.0e7
[[joints]]
name = "joint_2"
parent = "column"
child = "arm"
origin = [0.0, 0.0, 0.8]
axis = [0.0, 1.0, 0.0]
limits_deg = [-90.0, 90.0]
[joints.model]
torsion = 2.0e6
"""


def box_arm_robot(folder):
    """Write the box arm (STL + TOML) into ``folder`` and return its Robot."""
    import trimesh

    from flexarm.robot.formats.toml import read

    for name, (size, lo, _) in BOXES.items():
        box = trimesh.creation.box(extents=size)
        box.apply_translation(np.asarray(lo) + np.asarray(size) / 2)
        box.export(folder / f"{name}.stl")
    (folder / "robot.toml").write_text(TOML)
    return read(folder / "robot.toml")


def box_mesher(link, mesh_size, order):
    """Structured Tet4/Tet10 mesh of the box link (``mesh_size`` ignored)."""
    size, lo, div = BOXES[link.name]
    return TetMesh.box(size, div, order=order, origin=lo)
