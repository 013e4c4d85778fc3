"""Test geometry of a universal file: nodes (15/2411) and tracelines (82), pose by pose.

A test of an arm measures the same points at several poses, each time somewhere else
in the base frame.  flexarm keeps the poses apart by numbering: pose ``j`` (0-based, in
the file's order) adds ``j * stride`` to every point's node id, ``stride`` being the
power of ten above the largest point id (1000 for points 100 ... 601), so the first
pose keeps the point ids and a one-pose file is numbered like its points table.  Each
pose has its own 2411 block (its coordinates at that pose) and its own 82 traceline,
and its 55 and 58 sets use its node ids; their ID line 5 says the offset
(``flexarm nodes+=1000``).  A reader that combines every node of a
file into one geometry, as SDynPy and pyuff do, thus gets every pose side by side and
plots each pose's shapes on that pose's nodes; :func:`pose_geometries` takes the
numbering back apart.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ....fe.typing import FloatArray, IntArray
from ..shape_data import Points

__all__ = ["PoseGeometry", "node_stride", "pose_offsets", "stick_figure", "pose_geometries"]


@dataclass(frozen=True, eq=False)
class PoseGeometry:
    """The test geometry at one pose, in point ids.

    Attributes
    ----------
    pose : str or None
        Pose label (None: a file without flexarm's pose marks, whatever pose it was
        measured at).
    nodes : (k,) int
        Point (node) ids.
    coordinates : (k, 3) float
        Their positions in the base frame at the pose [m].
    lines : (m,) int
        Tracelines through them (UFF 82 convention: 0 lifts the pen).
    """

    pose: str | None
    nodes: IntArray
    coordinates: FloatArray
    lines: IntArray


def node_stride(nodes) -> int:
    """The power of ten above the largest node id: the step between two poses' ids.

    Examples
    --------
    >>> node_stride([100, 601]), node_stride([1, 9]), node_stride([1000])
    (1000, 10, 10000)
    """
    return 10 ** len(str(int(np.max(np.abs(np.asarray(nodes, np.int64))))))


def pose_offsets(poses, nodes) -> dict:
    """Pose label -> the offset added to its node ids: ``j * node_stride(nodes)``.

    Examples
    --------
    >>> pose_offsets(["P1", "P2", "P1"], [100, 601])
    {'P1': 0, 'P2': 1000}
    """
    stride = node_stride(nodes)
    return {str(p): j * stride for j, p in enumerate(dict.fromkeys(map(str, poses)))}


def stick_figure(points: Points) -> IntArray:
    """The points in chain order, a traceline that draws the arm as a stick figure: by
    body (base first), then by distance from the body's frame origin (its joint).

    Examples
    --------
    >>> p = Points(nodes=[201, 101, 200], links=[2, 1, 2],
    ...            positions=[[0, 0, 0.9], [0.2, 0, 0], [0, 0, 0.45]])
    >>> stick_figure(p).tolist()
    [101, 200, 201]
    """
    order = np.lexsort((np.linalg.norm(points.positions, axis=1), points.links))
    return points.nodes[order]


def _traces_of(traces: list, lo: int, hi: int) -> IntArray:
    """The tracelines whose nodes all lie in ``[lo, hi)``, joined by pen lifts (0)."""
    mine = [t for t in traces if np.all((t == 0) | ((t >= lo) & (t < hi)))]
    joined = [np.r_[t, 0] for t in mine]
    out = np.concatenate(joined)[:-1] if joined else np.zeros(0, np.int64)
    return np.where(out == 0, 0, out - lo).astype(np.int64)


def pose_geometries(nodes, coordinates, traces, offsets: dict) -> tuple[PoseGeometry, ...]:
    """The file's nodes (raw ids, (k,) and (k, 3) [m]) and tracelines (list of (m,) int)
    split into one :class:`PoseGeometry` per pose of ``offsets`` (pose -> node offset,
    from the pose marks); without offsets (another tool's file), one geometry of
    pose None with every node.

    Examples
    --------
    >>> g = pose_geometries([1, 2, 1001, 1002], np.eye(4, 3), [np.array([1, 2]),
    ...                     np.array([1001, 1002])], {"P1": 0, "P2": 1000})
    >>> [(x.pose, x.nodes.tolist(), x.lines.tolist()) for x in g]
    [('P1', [1, 2], [1, 2]), ('P2', [1, 2], [1, 2])]
    """
    nodes = np.asarray(nodes, np.int64)
    coordinates = np.asarray(coordinates, float).reshape(-1, 3)
    traces = [np.asarray(t, np.int64) for t in traces]
    if not offsets or len(set(offsets.values())) < 2:
        only = next(iter(offsets), None) if len(offsets) == 1 else None
        return (PoseGeometry(only, nodes, coordinates, _traces_of(traces, 0, 2**62)),)
    stride = min(v for v in offsets.values() if v > 0)
    out = []
    for pose, lo in offsets.items():
        mine = (nodes >= lo) & (nodes < lo + stride)
        out.append(PoseGeometry(pose, nodes[mine] - lo, coordinates[mine],
                                _traces_of(traces, lo, lo + stride)))
    return tuple(out)
