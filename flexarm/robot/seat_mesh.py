"""How many FE nodes a seat gets on the tet mesh, and the local edge that gives it enough.

A region's coupling needs nodes on it, and the pair check of a joint's two seats asks
for six a side (:data:`MIN_SEAT_NODES`).  Gmsh keeps the edge ``h`` it is given, so a
seat of CAD surface area ``A`` holds about ``A / (NODE_AREA h^2)`` surface nodes
(``NODE_AREA = 0.87``: the area per node of equilateral triangles): a small end face on
a coarse mesh holds five, or none.  Growing the seat is not always possible (the face
ends where it ends), so the mesh is refined over it instead: every region whose estimate
falls short of the six asks for the local edge that gives it twice that,
``tol.seat_mesh_nodes_factor`` x the rank-6 minimum (:data:`SEAT_NODES`, 12: the seat
finder's growth target; :func:`seat_edge`), down to ``tol.seat_local_edge_min`` x ``h``.
A seat with six or more keeps the edge, and a link whose seats all do keeps its mesh.
The build meshes the link with those local sizes (:func:`seat_local_sizes`, a
:class:`~flexarm.meshes.local_size.LocalSize` per such region) and the import report
estimates the nodes at the same edges (:func:`seat_mesh_nodes`).

The estimate is that of a flat face, and it holds there (a 30 mm disc refined to 10 mm:
32.6 estimated, 33 on the mesh); the faceted hulls' feature edges and a seat's rim add
nodes, and a link smaller than a few edges is meshed finer than asked, so on a robot it
is a lower bound: the M-20iA's 12 joint seats at 30 mm hold 1.3 to 2.9 times it (joint
4's on link_3: 12 estimated, 16 on the mesh; measured 2026-11-27,
``tests/studies/test_own_robot_published.py``).

The areas are measured on the link's CAD sample
(:func:`~flexarm.robot.seat_sample.link_sample`: its outer skin, as the build selects
nodes on it).  A mesh the link pins (``volume_meshes``) or fTetWild makes does not take
local sizes; the estimate is Gmsh's.
"""

from __future__ import annotations

import math

import numpy as np

from ..meshes.local_size import LocalSize
from ..reduction.tolerances import tol as red_tol
from .description import Link
from .seat_geometry import NODE_AREA
from .seat_sample import link_sample
from .tolerances import tol

__all__ = ["MIN_SEAT_NODES", "SEAT_NODES", "seat_areas", "seat_edge", "seat_local_sizes",
           "seat_mesh_nodes"]

#: Nodes each seat of a joint must hold on the mesh: the three of a rank-6 coupling,
#: twice over (the pair check of ``flexarm build``).
MIN_SEAT_NODES = 2 * red_tol.min_region_nodes
#: Nodes a seat that falls short of :data:`MIN_SEAT_NODES` is meshed to hold (estimate):
#: the seat finder's growth target.
SEAT_NODES = tol.seat_mesh_nodes_factor * red_tol.min_region_nodes


def seat_edge(area: float, mesh_size: float) -> float:
    """The tet edge [m] a seat of CAD surface ``area`` [m^2] is meshed with at the mesh
    size ``mesh_size`` [m]: ``mesh_size``, or where that would put fewer than
    :data:`MIN_SEAT_NODES` nodes on it the edge that puts :data:`SEAT_NODES` on it (not
    below ``tol.seat_local_edge_min`` x ``mesh_size``).

    Examples
    --------
    >>> seat_edge(0.005, 0.03)             # 50 cm^2: 6.4 nodes at 30 mm, kept
    0.03
    >>> round(seat_edge(0.0035, 0.03), 4)  # 35 cm^2: 4.5 nodes at 30 mm, refined
    0.0184
    """
    h = float(mesh_size)
    if area <= 0 or _nodes(area, h) >= MIN_SEAT_NODES:
        return h
    need = math.sqrt(area / (NODE_AREA * SEAT_NODES))
    return max(need, tol.seat_local_edge_min * h)


def _nodes(area: float, edge: float) -> float:
    return area / (NODE_AREA * edge**2)


def seat_areas(link: Link) -> dict[str, float]:
    """Region name -> CAD surface area [m^2] it holds (outer skin), for a link with a mesh.

    Examples
    --------
    >>> from flexarm.robot import load_robot
    >>> a = seat_areas(load_robot().links[0])
    >>> sorted(a), round(1e4 * a["joint_1"])
    (['base', 'joint_1'], 343)
    """
    sample = link_sample(link)
    return {name: float(reg.contains(sample.points).sum()) * sample.weight
            for name, reg in link.regions.items()}


def seat_mesh_nodes(link: Link, mesh_size: float) -> dict[str, float]:
    """Region name -> about how many surface nodes the build's Gmsh mesh at
    ``mesh_size`` [m] puts on it, at its :func:`seat_edge`.

    Examples
    --------
    >>> from flexarm.robot import load_robot
    >>> robot = load_robot()
    >>> n = seat_mesh_nodes(robot.links[0], 0.08)  # enough at 80 mm: kept
    >>> round(n["joint_1"], 2), round(n["base"], 1)
    (6.18, 25.1)
    >>> n = seat_mesh_nodes(robot.links[robot.link_index["turning_disc"]], 0.08)
    >>> {name: round(v, 6) for name, v in n.items()}  # 1.5 and 5.0 at 80 mm: refined
    {'joint_6': 12.0, 'tcp': 12.0}
    """
    h = float(mesh_size)
    return {name: _nodes(a, seat_edge(a, h)) if a > 0 else 0.0
            for name, a in seat_areas(link).items()}


def seat_local_sizes(link: Link, mesh_size: float) -> tuple[LocalSize, ...]:
    """A :class:`~flexarm.meshes.local_size.LocalSize` over every region of ``link`` that
    needs an edge finer than ``mesh_size`` [m] (link frame, metres), in name order;
    empty for a link without a mesh or regions.

    Examples
    --------
    >>> from flexarm.robot import load_robot
    >>> robot = load_robot()
    >>> link = robot.links[robot.link_index["turning_disc"]]
    >>> seat_local_sizes(link, 0.03)
    ()
    >>> [round(c.size, 4) for c in seat_local_sizes(link, 0.08)]  # joint_6, tcp
    [0.0283, 0.0515]
    """
    if link.mesh is None or not link.regions:
        return ()
    h = float(mesh_size)
    out = []
    for name, area in sorted(seat_areas(link).items()):
        edge = seat_edge(area, h)
        if edge < h:
            reg = link.regions[name]
            a = np.asarray(reg.axis, dtype=float)
            a = a / np.linalg.norm(a)
            out.append(LocalSize(tuple(map(float, reg.center)), tuple(map(float, a)),
                                 float(reg.r_max), float(reg.half_width), edge))
    return tuple(out)
