"""Plausibility of each link's CAD ``units`` against the joint positions it carries.

A wrong ``units`` scales a link's CAD by 1000 (mm read as m), 39 (inch) or 100 (cm):
its mass, inertia and stiffness change by powers of that factor, and every analysis
still runs.  The joints do not scale with it, so the CAD's size over the distance to the
farthest joint the link carries gives the mistake away: over the IRB 4600 and the demo
arm the ratio lies between 0.8 and 3.6; with a wrong unit it leaves ``[0.1, 100]``.  A
link that carries no joint (the flange) is held against the robot's reach instead (the
sum of its joint offsets, :attr:`~flexarm.robot.tolerances.Tolerances.leaf_size_ratio`).
"""

from __future__ import annotations

import logging

import numpy as np

from ...fe.units import LENGTH_UNITS
from ..description import Robot
from ..tolerances import tol

__all__ = ["check_link_units", "SIZE_RATIO"]

log = logging.getLogger(__name__)

#: Plausible range of (largest CAD extent) / (distance to the farthest child joint) [-].
SIZE_RATIO = (0.1, 100.0)


def _extent(path) -> float | None:
    """Largest bounding-box extent of a CAD file in its own units (None if unreadable:
    the mesher reports that file with its own message), cached by the file's bytes: every
    command reads its robot, and the CAD need not be parsed each time."""
    from ...fe.cache import cache_key, cached
    from ...fe.files import file_digest

    def measure() -> dict:
        import trimesh

        mesh = trimesh.load(path, force="mesh", process=False)
        return {"extent": float(np.ptp(np.asarray(mesh.vertices), axis=0).max())}

    try:
        key = cache_key("cad-extent", "raw", file_digest(path))
        return float(cached("cad-extent", key, measure).value["extent"])
    except Exception as exc:  # noqa: BLE001 - any reader failure: leave it to the mesher
        log.info("%s: not checked against the joints (%s)", path, exc)
        return None


def check_link_units(robot: Robot) -> None:
    """Raise ``ValueError`` naming ``links.<name>.units`` when a link's CAD, in its
    ``units``, is far smaller or larger than the distance to the joints it carries.

    Examples
    --------
    >>> from flexarm.robot import load_robot
    >>> from dataclasses import replace
    >>> robot = load_robot()
    >>> check_link_units(robot)
    >>> links = (robot.links[0], replace(robot.links[1], units="in")) + robot.links[2:]
    >>> check_link_units(replace(robot, links=links))
    Traceback (most recent call last):
    ...
    ValueError: links.frame.units: the CAD is 0.0146 m across with units='in' but carries \
joint_2 at 0.175 m: is the unit of meshes/frame.stl right (m, mm, cm, in)?
    """
    arm_reach = sum(float(np.linalg.norm(j.origin)) for j in robot.joints)
    for lk in robot.links:
        reach = [(float(np.linalg.norm(j.origin)), j.name) for j in robot.joints
                 if j.parent == lk.name]
        leaf = not reach  # it carries nothing, so the whole arm is the yardstick
        lo, hi = tol.leaf_size_ratio if leaf else SIZE_RATIO
        reach = [(arm_reach, "")] if leaf else reach
        if lk.mesh is None or max(reach)[0] <= 0:
            continue
        extent = _extent(lk.mesh)
        if extent is None:
            continue
        size = extent * LENGTH_UNITS[lk.units]
        distance, joint = max(reach)
        if not lo <= size / distance <= hi:
            shown = "/".join(lk.mesh.parts[-2:])
            carries = (f"the robot reaches {distance:.3g} m (a link without a child joint is "
                       f"{lo:g} to {hi:g} times that)" if leaf else
                       f"carries {joint} at {distance:.3g} m")
            raise ValueError(f"links.{lk.name}.units: the CAD is {size:.3g} m across with "
                             f"units={lk.units!r} but {carries}: is the unit of {shown} right "
                             f"({', '.join(LENGTH_UNITS)})?")
