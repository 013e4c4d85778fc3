"""Measurement points and the test geometry: where the points are at a pose, and which
link a node of a universal file's geometry sits on.

The arm is drawn as a stick figure: link ``i`` is the segments from its frame origin
(its joint) to the origins of the joints it carries, and to the TCP on the tool's link.
A node of a test geometry (2411/15 coordinates in the base frame at a known pose) is
put on the link whose segment passes nearest to it (the first in chain order on a
tie, so a node on a joint axis sits on the link before the joint); its position in that
link's frame follows.  A node farther than ``tol.max_point_distance`` from every link is
refused: the geometry is then not of this arm, or not at this pose.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from ...fe.errors import ReadError
from ...fe.typing import ArrayLike, FloatArray, PathType
from ..data.shape_data import Points
from ..tolerances import tol

__all__ = ["link_ends", "point_coordinates", "points_from_geometry", "file_points"]


def link_ends(robot, i: int) -> list[np.ndarray]:
    """Ends of link ``i``'s stick segments in its own frame [m]: the origins of the joints
    it carries and, on the tool's link, the TCP.

    Examples
    --------
    >>> from flexarm.robot.demo_arm import load_demo_robot
    >>> [e.tolist() for e in link_ends(load_demo_robot(), 1)]
    [[0.175, 0.0, 0.0]]
    """
    chain = robot.chain
    ends = [np.asarray(jt.origin, float) for j, jt in enumerate(robot.joints)
            if int(chain.parents[j]) == i]
    if i == chain.tcp_body:
        ends.append(np.asarray(chain.tool[:3, 3], float))
    return ends


def _frames(robot, q: ArrayLike) -> FloatArray:
    from ...robot.kinematics import link_frames

    chain = robot.chain
    return link_frames(chain, np.asarray(q, float)[:chain.n_joints])


def point_coordinates(robot, q: ArrayLike, points: Points) -> FloatArray:
    """(k, 3) base-frame positions [m] of ``points`` at joint angles ``q`` [rad].

    Examples
    --------
    >>> from flexarm.robot.demo_arm import load_demo_robot
    >>> r = load_demo_robot()
    >>> p = Points(nodes=[1], links=[1], positions=[[0.175, 0.0, 0.0]])
    >>> point_coordinates(r, np.zeros(6), p).round(3).tolist()
    [[0.175, 0.0, 0.495]]
    """
    F = _frames(robot, q)
    return np.einsum("kij,kj->ki", F[points.links, :3, :3], points.positions) + \
        F[points.links, :3, 3]


def points_from_geometry(robot, q: ArrayLike, nodes: ArrayLike,
                         coordinates: ArrayLike) -> Points:
    """The points table of a test geometry: each node on the link whose stick segment is
    nearest at joint angles ``q`` [rad] (see the module docstring).

    Parameters
    ----------
    robot : Robot
    q : (n,) float
        Joint angles of the pose the coordinates are given at [rad].
    nodes : (k,) int
        Node ids.
    coordinates : (k, 3) float
        Base-frame positions at that pose [m].

    Examples
    --------
    >>> from flexarm.robot.demo_arm import load_demo_robot
    >>> r = load_demo_robot()
    >>> p = points_from_geometry(r, np.zeros(6), [7], [[0.1, 0.0, 0.495]])
    >>> p.links.tolist(), p.positions.round(3).tolist()
    ([1], [[0.1, 0.0, 0.0]])
    """
    F = _frames(robot, q)
    bodies, starts, ends = [], [], []
    for i in range(1, len(robot.links)):
        for e in link_ends(robot, i) or [np.zeros(3)]:
            bodies.append(i)
            starts.append(F[i, :3, 3])
            ends.append(F[i, :3, :3] @ e + F[i, :3, 3])
    b, a, e = np.array(bodies), np.array(starts), np.array(ends)
    x = np.asarray(coordinates, float).reshape(-1, 3)
    nodes = np.asarray(nodes, np.int64)
    ab = e - a
    t = np.einsum("ksj,sj->ks", x[:, None] - a[None], ab) / np.maximum(
        np.einsum("sj,sj->s", ab, ab), tol.point_tie**2)
    near = a[None] + np.clip(t, 0.0, 1.0)[..., None] * ab[None]
    d = np.linalg.norm(x[:, None] - near, axis=2)
    best = d.min(axis=1)
    far = np.flatnonzero(best > tol.max_point_distance)
    if far.size:
        k = int(far[0])
        raise ValueError(f"node {nodes[k]} lies {best[k]:.3f} m from every link of the arm at "
                         "the measured pose: say where the file's nodes sit on the arm in "
                         "<data>.points.csv next to it (columns node, link, x_mm, y_mm, z_mm)")
    seg = np.argmax(d <= best[:, None] + tol.point_tie, axis=1)  # first in chain order
    link = b[seg]
    local = np.einsum("kji,kj->ki", F[link, :3, :3], x - F[link, :3, 3])
    return Points(nodes=nodes, links=link, positions=local)


def file_points(path: PathType, robot, pose: str, q: ArrayLike) -> Points | None:
    """The points table that the geometry (2411/15) of the universal file ``path`` gives
    at its pose ``pose`` (the pose of a flexarm file's own block, else the file's only
    geometry, taken at ``q`` [rad]); None for another file or one without geometry.

    Examples
    --------
    >>> import tempfile, pathlib
    >>> from flexarm.robot.demo_arm import load_demo_robot
    >>> from flexarm.validation.data.formats.uff_geometry import PoseGeometry
    >>> from flexarm.validation.data.formats.uff_write import write_uff
    >>> r = load_demo_robot()
    >>> g = PoseGeometry("home", np.array([7]), np.array([[0.1, 0.0, 0.495]]), np.array([7]))
    >>> f = write_uff(pathlib.Path(tempfile.mkdtemp()) / "g.uff", geometry=[g])
    >>> p = file_points(f, r, "home", np.zeros(6))
    >>> p.links.tolist(), p.positions.round(3).tolist()
    ([1], [[0.1, 0.0, 0.0]])
    """
    from ..data.formats.uff import EXTENSIONS, read_uff

    path = Path(path)
    if path.suffix.lower() not in EXTENSIONS:
        return None
    content = read_uff(path, pose, q)
    mine = [g for g in content.geometry if g.pose in (pose, None) and len(g.nodes)]
    if not mine:
        return None
    g = mine[0]
    try:
        return points_from_geometry(robot, q, g.nodes, g.coordinates)
    except ValueError as exc:
        raise ReadError(f"{path}: {exc}") from None
