"""A four-link arm of CAD primitives without interface regions (for the seat finder).

``primitive_arm_robot(folder)`` writes the links as STL (trimesh primitives) and returns
the :class:`Robot`:

* ``base``: a cylinder r 0.15 m, z 0..0.3 (its bottom is the foundation);
* ``column``: a box 0.16 x 0.16 x 0.5 m on the base's top face (joint_1, axis z);
* ``arm``: a box beside the column (joint_2 pierces the column's -y face).  The joint
  frame is yawed by -90 deg (``rpy``), so the axis is x in the arm's frame and -y in the
  column's: the arm is 0.1 m thick along its x, 0.66 m long along its y;
* ``hub``: a tube (bore r 20 mm, outer r 45 mm, 60 mm long, written in millimetres) on
  the arm's end face (joint_3, axis y), carrying the tool at its far end.

:data:`SEATS` lists where each seat's centre must come out [m, link frame].
"""

from __future__ import annotations

import math

import numpy as np

#: (link, region) -> expected seat centre [m] in the link frame
SEATS = {
    ("base", "joint_1"): (0.0, 0.0, 0.3),
    ("base", "base"): (0.0, 0.0, 0.0),
    ("column", "joint_1"): (0.0, 0.0, 0.0),
    ("column", "joint_2"): (0.0, -0.08, 0.42),
    ("arm", "joint_2"): (0.0, 0.0, 0.0),
    ("arm", "joint_3"): (0.05, 0.6, 0.0),
    ("hub", "joint_3"): (0.0, 0.03, 0.0),  # the bore's middle
    ("hub", "tcp"): (0.0, 0.06, 0.0),
}


def _write(mesh, path, translate=(0.0, 0.0, 0.0), scale=1.0):
    mesh.apply_translation(translate)
    mesh.apply_scale(scale)
    mesh.export(path)
    return path


def primitive_arm_robot(folder, mesher: str = "gmsh"):
    """Write the STL files into ``folder`` and return the robot (no regions).

    gmsh by default: the same STL gives the same tetrahedra, so node counts in a seat are
    the same on every run (pytetwild's vary by a few nodes from run to run)."""
    import trimesh

    from flexarm.fe.material import MATERIALS
    from flexarm.robot.description import Joint, Link, ModelOptions, Robot, Tool
    from flexarm.robot.joints import JointModel

    steel = MATERIALS["steel"]
    base = _write(trimesh.creation.cylinder(0.15, 0.3, sections=64), folder / "base.stl",
                  (0, 0, 0.15))
    column = _write(trimesh.creation.box((0.16, 0.16, 0.5)), folder / "column.stl",
                    (0, 0, 0.25))
    arm = _write(trimesh.creation.box((0.1, 0.66, 0.1)), folder / "arm.stl", (0.05, 0.27, 0))
    tube = trimesh.creation.annulus(0.02, 0.045, 0.06, sections=48)  # along z, centred
    tube.apply_transform(trimesh.transformations.rotation_matrix(-math.pi / 2, [1, 0, 0]))
    hub = _write(tube, folder / "hub.stl", (0, 0.03, 0), scale=1e3)  # y 0..60 mm
    links = (Link("base", base, steel), Link("column", column, steel), Link("arm", arm, steel),
             Link("hub", hub, steel, units="mm"))
    spring = JointModel(torsion=1e5)
    lim = (-math.pi, math.pi)
    joints = (
        Joint("joint_1", "base", "column", (0.0, 0.0, 0.3), (0.0, 0.0, 1.0), *lim, spring),
        Joint("joint_2", "column", "arm", (0.0, -0.08, 0.42), (1.0, 0.0, 0.0), *lim, spring,
              rpy=(0.0, 0.0, -math.pi / 2)),
        Joint("joint_3", "arm", "hub", (0.05, 0.6, 0.0), (0.0, 1.0, 0.0), *lim, spring),
    )
    return Robot("primitive arm", links, joints, tool=Tool(xyz=(0.0, 0.06, 0.0)),
                 poses={"home": [0.0, 0.0, 0.0]},
                 options=ModelOptions(mesh_size=0.04, mesher=mesher))


def seat_centre(robot, link: str, region: str) -> np.ndarray:
    """The centre [m] of a region of ``robot`` (link frame)."""
    return np.asarray(robot.links[robot.link_index[link]].regions[region].center)


def urdf_cylinder(r: float, length: float, xyz="0 0 0", rpy: str = "0 0 0") -> str:
    """A URDF ``<collision>`` cylinder of radius ``r`` and ``length`` [m] at origin
    ``xyz`` (a string "x y z", or a number: z only) and ``rpy`` [rad]."""
    if not isinstance(xyz, str):
        xyz = f"0 0 {xyz}"
    return (f'<collision><origin xyz="{xyz}" rpy="{rpy}"/><geometry><cylinder radius="{r}" '
            f'length="{length}"/></geometry></collision>')
