"""Poses the robot can take: self-collision and floor contact from the link CAD.

Each link is its CAD's convex hull (cached per file), placed by forward kinematics
(:func:`~flexarm.robot.kinematics.link_frames`).  Two links collide when their hulls
intersect (FCL through trimesh's :class:`~trimesh.collision.CollisionManager`).  Hulls
are a conservative stand-in for the links: they fill a fork's gap and an elbow's
inside, so links that touch at every pose are not checked against each other:

* links joined by a joint (adjacent), and
* links whose hulls already intersect at the rest pose (all joints at 0, or their
  nearest limit): the way MoveIt's setup assistant disables "default" pairs.

A moving link touches the floor when any point of its hull lies more than
:data:`FLOOR_CLEARANCE` below the base's lowest point (the mounting face); the link on
the base (joint 1's) and links already below it at rest are not checked.  Frames: the
robot's base frame, z up; lengths in metres.
"""

from __future__ import annotations

import logging
from dataclasses import dataclass

import numpy as np

from ..fe.typing import ArrayLike, FloatArray
from .description import Robot
from .kinematics import link_frames

__all__ = ["FLOOR_CLEARANCE", "PoseCheck", "CollisionChecker", "convex_hull", "pose_note"]

log = logging.getLogger(__name__)

#: A hull point this far [m] below the base's lowest point counts as floor contact (the
#: slack of a faceted hull and of a mounting plate's thickness).
FLOOR_CLEARANCE = 0.01


def convex_hull(link) -> tuple[FloatArray, np.ndarray]:
    """Vertices (v, 3) [m, link frame] and triangles (t, 3) of the convex hull of a
    link's CAD, cached by the file's content and units (open surfaces have one too)."""
    from ..fe.cache import cache_key, cached
    from ..fe.files import file_digest

    def compute() -> dict:
        import trimesh
        from scipy.spatial import QhullError

        from ..fe.errors import MeshError
        from ..fe.units import LENGTH_UNITS

        mesh = trimesh.load(link.mesh, force="mesh")
        try:
            hull = trimesh.convex.convex_hull(np.asarray(mesh.vertices)
                                              * LENGTH_UNITS[link.units])
        except QhullError:
            raise MeshError(f"links.{link.name}.mesh: {link.mesh}: the surface encloses zero "
                            f"volume (its {len(mesh.vertices)} points lie in a plane or on a "
                            "line)") from None
        return {"vertices": hull.vertices.tolist(), "faces": hull.faces.tolist()}

    d = cached("convex-hulls", cache_key("convex-hull", file_digest(link.mesh), link.units),
               compute).value
    return np.asarray(d["vertices"], float), np.asarray(d["faces"], np.int64)


@dataclass(frozen=True)
class PoseCheck:
    """What one pose hits: colliding link ``pairs`` and ``floor`` links (names)."""

    pairs: tuple[tuple[str, str], ...] = ()
    floor: tuple[str, ...] = ()

    @property
    def ok(self) -> bool:
        """True when the pose is free."""
        return not (self.pairs or self.floor)

    def text(self) -> str:
        """``"link_6 hits base_link; link_3 below the floor"`` (empty when free).

        Examples
        --------
        >>> PoseCheck((("base", "hand"),), ("arm",)).text()
        'base hits hand; arm below the floor'
        """
        parts = [f"{a} hits {b}" for a, b in self.pairs]
        parts += [f"{name} below the floor" for name in self.floor]
        return "; ".join(parts)


class CollisionChecker:
    """The links' convex hulls of ``robot`` and the pairs worth checking.

    Attributes
    ----------
    names : tuple of str
        Links with CAD (the others carry no shape).
    ignored : tuple of (str, str)
        Pairs never checked: adjacent, or intersecting at the rest pose.
    floor_z : float
        Height [m] of the floor (the base's lowest point, base frame).

    Examples
    --------
    >>> from flexarm.robot.demo_arm import load_demo_robot
    >>> robot = load_demo_robot()
    >>> check = CollisionChecker(robot)
    >>> check.check(robot.pose("P1")).ok
    True
    >>> q = np.radians([0, 0, 75, 0, 120, 0])  # the wrist bent back onto the tube
    >>> check.check(q).pairs
    (('tube_shaft', 'turning_disc'),)
    >>> check.colliding(np.stack([robot.pose("P1"), q])).tolist()
    [False, True]
    """

    def __init__(self, robot: Robot):
        import trimesh
        from trimesh.collision import CollisionManager

        log.info("collision hulls of %s", robot.name)
        self._chain = robot.chain
        self._bodies = [i for i, lk in enumerate(robot.links) if lk.mesh is not None]
        self.names = tuple(robot.links[i].name for i in self._bodies)
        hulls = [convex_hull(robot.links[i]) for i in self._bodies]
        self._points = [v for v, _ in hulls]
        self._manager = CollisionManager()
        for name, (v, f) in zip(self.names, hulls, strict=True):
            self._manager.add_object(name, trimesh.Trimesh(v, f, process=False))
        chain = self._chain
        adjacent = {frozenset((robot.links[int(chain.parents[j])].name, robot.links[j + 1].name))
                    for j in range(chain.n_joints)}
        q0 = np.clip(np.zeros(chain.n_joints), robot.lower, robot.upper)
        at_rest = self._pairs(link_frames(chain, q0))
        self.ignored = tuple(sorted(tuple(sorted(p)) for p in adjacent | at_rest))
        self._ignored = adjacent | at_rest
        base = 0 if 0 in self._bodies else None
        self.floor_z = 0.0 if base is None else float(self._points[0][:, 2].min())
        rest_low = self._lowest(link_frames(chain, q0)[None])[0]
        on_base = {j + 1 for j in range(chain.n_joints) if chain.parents[j] == 0} | {0}
        self._floor_links = [k for k, b in enumerate(self._bodies) if b not in on_base
                             and rest_low[k] >= self.floor_z - FLOOR_CLEARANCE]
        log.info("collision hulls of %s: %d links, %d pairs ignored", robot.name,
                 len(self.names), len(self.ignored))

    def _pairs(self, frames: FloatArray) -> set:
        """Intersecting hull pairs (frozensets of names) at one pose's frames."""
        for name, b in zip(self.names, self._bodies, strict=True):
            self._manager.set_transform(name, frames[b])
        hit, names = self._manager.in_collision_internal(return_names=True)
        return {frozenset(p) for p in names} if hit else set()

    def _lowest(self, frames: FloatArray) -> FloatArray:
        """(m, links) lowest hull height [m] of each link at each of m poses' frames."""
        out = np.zeros((len(frames), len(self._bodies)))
        for k, (b, v) in enumerate(zip(self._bodies, self._points, strict=True)):
            z = np.einsum("mj,vj->mv", frames[:, b, 2, :3], v) + frames[:, b, 2, 3][:, None]
            out[:, k] = z.min(axis=1)
        return out

    def check(self, q: ArrayLike) -> PoseCheck:
        """The colliding pairs and floor links at one pose ``q`` (n,) [rad]."""
        frames = link_frames(self._chain, np.asarray(q, float))
        pairs = sorted(tuple(sorted(p)) for p in self._pairs(frames) - self._ignored)
        low = self._lowest(frames[None])[0]
        floor = tuple(self.names[k] for k in self._floor_links
                      if low[k] < self.floor_z - FLOOR_CLEARANCE)
        return PoseCheck(tuple(pairs), floor)

    def colliding(self, Q: ArrayLike) -> np.ndarray:
        """(...) bool: poses ``Q`` (..., n) [rad] where links collide or touch the floor."""
        Q = np.asarray(Q, float)
        flat = Q.reshape(-1, Q.shape[-1])
        frames = link_frames(self._chain, flat)
        low = self._lowest(frames)[:, self._floor_links]
        hit = (low < self.floor_z - FLOOR_CLEARANCE).any(axis=1)
        for m in np.flatnonzero(~hit):
            hit[m] = bool(self._pairs(frames[m]) - self._ignored)
        return hit.reshape(Q.shape[:-1])


def pose_note(robot: Robot, q: ArrayLike) -> str:
    """What pose ``q`` (n,) [rad] hits (:meth:`PoseCheck.text`), or "" when it is free or
    cannot be checked (a link's CAD unreadable: the command that needs it says so).

    Examples
    --------
    >>> from flexarm.robot.demo_arm import load_demo_robot
    >>> robot = load_demo_robot()
    >>> pose_note(robot, robot.pose("P1"))
    ''
    >>> pose_note(robot, np.radians([0, 0, 75, 0, 120, 0]))
    'tube_shaft hits turning_disc'
    """
    from ..fe.errors import FlexarmError

    try:
        return CollisionChecker(robot).check(q).text()
    except (OSError, ValueError, FlexarmError) as exc:
        log.info("no collision check: %s", exc)
        return ""
