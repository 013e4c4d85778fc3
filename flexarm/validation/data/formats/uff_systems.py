"""Coordinate systems of a universal file (2420, 18) and the nodes (15/2411) defined in them.

Every node of a 15 or 2411 set names two coordinate systems: the *definition* system its
coordinates are given in and the *displacement* system the directions of its 55 and 58
data refer to.  Analyzer exports (Testlab, NX) define them in 2420 sets (a label, a
type and a transformation matrix each) or, older, in 18 sets (three points each).  This
module puts every node into the base frame of the file and gives, per node, the
rotation that turns its displacement directions into base-frame ones.

Conventions (those of I-DEAS, as SDynPy implements them):

- **2420 matrix**, 4 rows of 3: rows 1-3 are the system's x, y, z axes as unit
  vectors in the global frame, row 4 its origin; a point of local Cartesian
  coordinates ``l`` is at ``l @ axes + origin``.
- **Types**: 0 rectangular ``(x, y, z)``; 1 cylindrical ``(r, theta [deg], z)``; 2
  spherical ``(r, theta [deg] from local z, phi [deg] about it)``.
- **Directions** of a cylindrical system at a point: radial, tangential, axial; of a
  spherical one, SDynPy's ``R_z(phi) R_y(theta)`` frame: ``e_theta``, ``e_phi``,
  ``e_r`` (Nastran orders them ``e_r, e_theta, e_phi``; a file from a tool that does
  so reads rotated).
- **Label 0** is the global frame in every file (I-DEAS labels start at 1; many
  writers put 0 for "global").  Any other label must be defined: a node that names an
  undefined one is refused, never taken as global.
- **18** (method 1): origin, a point on +x and a point in the +xz half-plane, given in
  a reference system defined before it (0: global).
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ....fe.errors import ReadError
from ....fe.typing import FloatArray, IntArray
from ...tolerances import tol

__all__ = ["CoordinateSystem", "NodeFrames", "systems_2420", "systems_18", "node_frames",
           "GLOBAL"]

_KINDS = {0: "rectangular", 1: "cylindrical", 2: "spherical"}


@dataclass(frozen=True, eq=False)
class CoordinateSystem:
    """One coordinate system of a universal file, in the global frame.

    Attributes
    ----------
    label : int
    kind : int
        0 rectangular, 1 cylindrical, 2 spherical.
    axes : (3, 3) float
        Rows: the system's x, y, z axes as unit vectors in the global frame.
    origin : (3,) float
        Its origin in the global frame [m].
    """

    label: int
    kind: int
    axes: FloatArray
    origin: FloatArray

    def to_global(self, local, length: float = 1.0) -> FloatArray:
        """Global positions [m] of (k, 3) coordinates in this system (lengths in file units,
        ``length`` of them per metre; angles in degrees).

        Examples
        --------
        >>> cs = CoordinateSystem(2, 1, np.eye(3), np.array([0.0, 0.0, 1.0]))
        >>> cs.to_global([[2.0, 90.0, 0.5]]).round(12).tolist()
        [[0.0, 2.0, 1.5]]
        """
        c = np.array(local, float).reshape(-1, 3)
        if self.kind == 1:
            t = np.deg2rad(c[:, 1])
            c = np.column_stack([c[:, 0] * np.cos(t), c[:, 0] * np.sin(t), c[:, 2]])
        elif self.kind == 2:
            t, p = np.deg2rad(c[:, 1]), np.deg2rad(c[:, 2])
            c = c[:, :1] * np.column_stack([np.sin(t) * np.cos(p), np.sin(t) * np.sin(p),
                                            np.cos(t)])
        return c / length @ self.axes + self.origin

    def directions(self, points) -> FloatArray:
        """(k, 3, 3) rotations whose columns are this system's displacement directions 1,
        2, 3 at the global ``points`` (k, 3) [m], as global unit vectors.

        Examples
        --------
        >>> cs = CoordinateSystem(2, 1, np.eye(3), np.zeros(3))
        >>> cs.directions([[0.0, 3.0, 0.0]])[0].T.round(12).tolist()  # r, theta, z at +y
        [[0.0, 1.0, 0.0], [-1.0, 0.0, 0.0], [0.0, 0.0, 1.0]]
        """
        local = (np.asarray(points, float).reshape(-1, 3) - self.origin) @ self.axes.T
        k = len(local)
        if self.kind == 0:
            turn = np.broadcast_to(np.eye(3), (k, 3, 3))
        else:
            phi = np.arctan2(local[:, 1], local[:, 0])
            c, s, o, i = np.cos(phi), np.sin(phi), np.zeros(k), np.ones(k)
            turn = np.stack([np.stack([c, -s, o], -1), np.stack([s, c, o], -1),
                             np.stack([o, o, i], -1)], 1)
            if self.kind == 2:
                th = np.arccos(np.clip(local[:, 2] / np.maximum(
                    np.linalg.norm(local, axis=1), np.finfo(float).tiny), -1, 1))
                ct, st = np.cos(th), np.sin(th)
                tilt = np.stack([np.stack([ct, o, st], -1), np.stack([o, i, o], -1),
                                 np.stack([-st, o, ct], -1)], 1)
                turn = turn @ tilt
        return self.axes.T @ turn


#: The global frame, label 0.
GLOBAL = CoordinateSystem(0, 0, np.eye(3), np.zeros(3))


def _kind(path: Path, i: int, t: int, label: int, kind) -> int:
    if int(kind) not in _KINDS:
        raise ReadError(f"{path}, dataset {i + 1} (type {t}): coordinate system {label} has "
                        f"type {int(kind)}, not 0 (rectangular), 1 (cylindrical) or 2 "
                        "(spherical): export it again")
    return int(kind)


def systems_2420(path: Path, i: int, dset: dict, length: float = 1.0) -> list:
    """The :class:`CoordinateSystem` of a 2420 set as pyuff reads it (origins in file
    units, ``length`` of them per metre); a matrix whose axes are not orthonormal is
    refused."""
    out = []
    for label, kind, m in zip(dset.get("CS_sys_labels", []), dset.get("CS_types", []),
                              dset.get("CS_matrices", []), strict=True):
        m = np.asarray(m, float)
        axes = m[:3]
        if np.max(np.abs(axes @ axes.T - np.eye(3))) > tol.cs_orthonormal:
            raise ReadError(f"{path}, dataset {i + 1} (type 2420): coordinate system "
                            f"{int(label)}: the rows of its matrix are not orthonormal "
                            "unit axes: export it again")
        out.append(CoordinateSystem(int(label), _kind(path, i, 2420, label, kind), axes,
                                    m[3] / length))
    return out


def systems_18(path: Path, i: int, dset: dict, known: dict, length: float = 1.0) -> list:
    """The :class:`CoordinateSystem` of an 18 set (method 1: origin, point on +x, point
    in the +xz plane, in a reference system of ``known`` or global)."""
    out, known = [], dict(known)
    for k, label in enumerate(np.asarray(dset.get("cs_num", []), float).astype(int)):
        ref, method = int(dset["ref_cs_num"][k]), int(dset["method"][k])
        where = f"{path}, dataset {i + 1} (type 18): coordinate system {label}"
        if method != 1:
            raise ReadError(f"{where}: definition method {method}, not 1 (origin, +x "
                            "point, +xz point): export it as dataset 2420")
        if ref and ref not in known:
            raise ReadError(f"{where}: its reference system {ref} is not defined before it: "
                            "export the file with every coordinate system")
        base = known.get(ref, GLOBAL)
        o, px, pxz = base.to_global(np.vstack([dset["ref_o"][k], dset["x_point"][k],
                                               dset["xz_point"][k]]), length)
        x, v = px - o, pxz - o
        z = v - (v @ x) / (x @ x) * x if x @ x > 0 else v
        if not (np.linalg.norm(x) > 0 and np.linalg.norm(z) > 0):
            raise ReadError(f"{where}: its three points are on one line: export it again")
        x, z = x / np.linalg.norm(x), z / np.linalg.norm(z)
        cs = CoordinateSystem(int(label), _kind(path, i, 18, label, dset["cs_type"][k]),
                              np.vstack([x, np.cross(z, x), z]), o)
        known[cs.label] = cs
        out.append(cs)
    return out


@dataclass(frozen=True, eq=False)
class NodeFrames:
    """Nodes in the global frame with their displacement directions.

    Attributes
    ----------
    nodes : (k,) int
        Node ids as in the file.
    coordinates : (k, 3) float
        Global positions [m].
    rotations : (k, 3, 3) float
        Columns: the node's displacement directions 1, 2, 3 as global unit vectors.
    disp_cs : (k,) int
        The node's displacement system label (for messages).
    """

    nodes: IntArray
    coordinates: FloatArray
    rotations: FloatArray
    disp_cs: IntArray

    def of(self, ids) -> tuple[FloatArray, IntArray]:
        """(n, 3, 3) rotations and displacement labels of node ``ids``; a node the file
        does not list is taken in the global frame."""
        ids = np.asarray(ids, np.int64).ravel()
        rot = np.broadcast_to(np.eye(3), (len(ids), 3, 3)).copy()
        cs = np.zeros(len(ids), np.int64)
        order = np.argsort(self.nodes, kind="stable")
        pos = np.clip(np.searchsorted(self.nodes[order], ids), 0, max(len(order) - 1, 0))
        hit = (self.nodes[order][pos] == ids) if len(order) else np.zeros(len(ids), bool)
        rot[hit], cs[hit] = self.rotations[order][pos[hit]], self.disp_cs[order][pos[hit]]
        return rot, cs

    def is_global(self, ids) -> bool:
        """Whether every node of ``ids`` has the global directions exactly."""
        rot, _ = self.of(ids)
        return bool(np.all(rot == np.eye(3)))


def node_frames(path: Path, blocks: list, systems: dict) -> NodeFrames:
    """The nodes of the 15/2411 ``blocks`` (tuples ``(ids, local (k, 3), def_cs,
    disp_cs, length)``, coordinates in file units) in the global frame, their systems
    looked up in ``systems`` (label -> :class:`CoordinateSystem`; 0 is global).

    Examples
    --------
    >>> cs = CoordinateSystem(2, 0, np.array([[0., 1, 0], [-1, 0, 0], [0, 0, 1]]),
    ...                       np.array([1.0, 0, 0]))
    >>> f = node_frames(Path("a.unv"), [([5], [[2.0, 0, 0]], [2], [2], 1.0)], {2: cs})
    >>> f.coordinates.tolist(), f.rotations[0, :, 0].tolist()  # local x is global +y
    ([[1.0, 2.0, 0.0]], [0.0, 1.0, 0.0])
    >>> node_frames(Path("a.unv"), [([5], [[0, 0, 0]], [0], [7], 1.0)], {})
    Traceback (most recent call last):
    ...
    flexarm.fe.errors.ReadError: a.unv: node 5 refers to coordinate system 7, which the \
file does not define (datasets 2420 or 18): export the file with its coordinate systems
    """
    systems = {0: GLOBAL, **systems}
    ids, xyz, rot, disp = [], [], [], []
    for nodes, local, def_cs, disp_cs, length in blocks:
        nodes = np.asarray(nodes, float).astype(np.int64)
        local = np.asarray(local, float).reshape(-1, 3)
        def_cs = np.asarray(def_cs, float).astype(np.int64)
        disp_cs = np.asarray(disp_cs, float).astype(np.int64)
        for which in (def_cs, disp_cs):
            bad = np.flatnonzero(~np.isin(which, list(systems)))
            if bad.size:
                raise ReadError(f"{path}: node {nodes[bad[0]]} refers to coordinate system "
                                f"{which[bad[0]]}, which the file does not define (datasets "
                                "2420 or 18): export the file with its coordinate systems")
        g = np.zeros((len(nodes), 3))
        r = np.zeros((len(nodes), 3, 3))
        for label in np.unique(def_cs):
            mine = def_cs == label
            g[mine] = systems[int(label)].to_global(local[mine], length)
        for label in np.unique(disp_cs):
            mine = disp_cs == label
            r[mine] = systems[int(label)].directions(g[mine])
        ids.append(nodes), xyz.append(g), rot.append(r), disp.append(disp_cs)
    if not ids:
        return NodeFrames(np.zeros(0, np.int64), np.zeros((0, 3)), np.zeros((0, 3, 3)),
                          np.zeros(0, np.int64))
    return NodeFrames(np.concatenate(ids), np.concatenate(xyz), np.concatenate(rot),
                      np.concatenate(disp))
