"""Measurement points and measured mode shapes at them, as frozen dataclasses (SI).

A *measurement point* is a node of the test geometry (an accelerometer or a laser
spot) fixed to one body of the arm: :class:`Points` maps its node id to the body
(``0`` = base, ``i`` = link ``i``) and to its position in that body's link frame
``L_i`` [m] (the URDF link frame at zero joint angles).  A *DOF* of the test is a
node and a base-frame direction (``x``, ``y``, ``z``).

:class:`ShapeData` is a :class:`~flexarm.validation.data.measurements.ModalData` (one row
per pose and mode) that also holds the mode shapes at a list of DOFs, so everything
that reads frequencies reads it unchanged.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ...fe.typing import FloatArray, IntArray
from .measurements import DIRECTIONS, ModalData, _array

__all__ = ["Points", "ShapeData", "dof_labels"]


def dof_labels(nodes, dirs) -> list[str]:
    """``"<node><dir>"`` labels of DOFs, e.g. ``["101x", "101y"]``.

    Examples
    --------
    >>> dof_labels([101, 101, 7], ["x", "y", "z"])
    ['101x', '101y', '7z']
    """
    return [f"{int(n)}{d}" for n, d in zip(np.asarray(nodes).ravel(), np.asarray(dirs).ravel(),
                                           strict=True)]


@dataclass(frozen=True, eq=False)
class Points:
    """Measurement points: node id -> body and position in the body's link frame.

    Parameters
    ----------
    nodes : (k,) int
        Node ids of the test geometry (unique).
    links : (k,) int
        Body each point is fixed to: 0 = base, ``i`` = link ``i``.
    positions : (k, 3) float
        Position in that body's link frame ``L_i`` [m].

    Examples
    --------
    >>> p = Points(nodes=[10, 20], links=[2, 6], positions=[[0, 0, 0.5], [0.1, 0, 0]])
    >>> p.index([20, 10]).tolist(), p.n_points
    ([1, 0], 2)
    """

    nodes: IntArray
    links: IntArray
    positions: FloatArray

    def __post_init__(self) -> None:
        n = _array(self, "nodes", self.nodes, np.int64, (), None)
        _array(self, "links", self.links, np.int64, (), n)
        _array(self, "positions", self.positions, np.float64, (3,), n)
        uniq, counts = np.unique(self.nodes, return_counts=True)
        if np.any(counts > 1):
            raise ValueError(f"Points.nodes: node {uniq[counts > 1][0]} is listed twice")
        if np.any(self.links < 0):
            raise ValueError(f"Points.links must be >= 0 (0 = base), got {self.links.min()}")

    @property
    def n_points(self) -> int:
        """Number of points."""
        return len(self.nodes)

    def index(self, nodes) -> IntArray:
        """(m,) int: row of each node id in this table; an unknown node raises."""
        nodes = np.asarray(nodes, dtype=np.int64).ravel()
        order = np.argsort(self.nodes)
        pos = np.searchsorted(self.nodes, nodes, sorter=order)
        pos = np.clip(pos, 0, len(order) - 1)
        rows = order[pos]
        bad = self.nodes[rows] != nodes
        if np.any(bad):
            raise ValueError(f"node {nodes[bad][0]} is not in the measurement points table "
                             f"(has {', '.join(str(n) for n in np.sort(self.nodes))}): say "
                             f"where the file's nodes sit on the arm in <data>.points.csv "
                             f"next to it (columns node, link, x_mm, y_mm, z_mm)")
        return rows

    def __eq__(self, other) -> bool:
        if type(other) is not type(self):
            return NotImplemented
        return all(np.array_equal(getattr(self, f), getattr(other, f))
                   for f in ("nodes", "links", "positions"))

    __hash__ = None


@dataclass(frozen=True, eq=False, repr=False)
class ShapeData(ModalData):
    """Measured natural frequencies with mode shapes at measurement DOFs.

    Parameters
    ----------
    poses, q, modes, freq_hz, damping_ratio
        As for :class:`~flexarm.validation.data.measurements.ModalData` (one row per pose
        and mode).
    nodes : (m,) int
        Node id of each measured DOF.
    dirs : (m,) str
        Base-frame direction of each measured DOF, ``x``, ``y`` or ``z``.
    shapes : (n, m) float or complex
        Mode shape of each row at the DOFs (any scaling; MAC does not see it).

    Examples
    --------
    >>> s = ShapeData(poses=["P1", "P1"], q=np.zeros((2, 6)), modes=[1, 2],
    ...               freq_hz=[7.0, 12.0], nodes=[1, 1], dirs=["x", "y"],
    ...               shapes=[[1.0, 0.0], [0.0, 1.0]])
    >>> s.dofs, s.n_dofs
    (['1x', '1y'], 2)
    """

    nodes: IntArray | None = None
    dirs: np.ndarray | None = None
    shapes: np.ndarray | None = None

    def __post_init__(self) -> None:
        super().__post_init__()
        n = len(self.poses)
        m = _array(self, "nodes", self.nodes, np.int64, (), None)
        _array(self, "dirs", None if self.dirs is None else
               [str(d).lower() for d in np.asarray(self.dirs).ravel()], np.str_, (), m)
        bad = ~np.isin(self.dirs, DIRECTIONS)
        if bad.any():
            raise ValueError(f"ShapeData.dirs must be among {', '.join(DIRECTIONS)}, "
                             f"got {self.dirs[bad][0]!r}")
        dofs = dof_labels(self.nodes, self.dirs)
        if len(set(dofs)) != len(dofs):
            raise ValueError("ShapeData: each (node, dir) DOF may appear once")
        shapes = np.asarray(self.shapes)
        dtype = np.complex128 if np.iscomplexobj(shapes) else np.float64
        _array(self, "shapes", shapes, dtype, (m,), n)

    @property
    def dofs(self) -> list[str]:
        """``"<node><dir>"`` label of each measured DOF."""
        return dof_labels(self.nodes, self.dirs)

    @property
    def n_dofs(self) -> int:
        """Number of measured DOFs."""
        return len(self.nodes)

    def frequencies_only(self) -> ModalData:
        """The frequencies (and damping) without the shapes."""
        return ModalData(poses=self.poses, q=self.q, modes=self.modes, freq_hz=self.freq_hz,
                         damping_ratio=self.damping_ratio)

    def pose_rows(self, pose: str) -> IntArray:
        """(k,) int: rows of pose ``pose``."""
        return np.flatnonzero(self.poses == pose)
