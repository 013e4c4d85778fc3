"""Model mode shapes at measurement points, from any assembled arm model.

A point of :class:`~flexarm.validation.data.shape_data.Points` sits on body ``i`` at ``p``
(link frame ``L_i``).  Its base-frame translation from the arm's independent
coordinates ``x`` is ``R_i G_p Q_i^T T_i`` (:func:`point_map`), with ``T_i`` and
``Q_i`` of :func:`~flexarm.assembly.system.system_matrices` and ``G_p`` the point's
motion from the body's own coordinates:

- a rigid body (E-model link): rigid transport from its node, ``u + theta x (p - o)``;
- a superelement body (Guyan or Craig-Bampton link): the superelement's recovery
  matrix at the FE surface node nearest to ``p`` times the body's floating-frame
  coordinates (:func:`~flexarm.assembly.flexible.body_coordinates`), so the link's own
  bending is in the shape, plus the link's rotation times the offset from that node to
  ``p`` (a point inside a hollow casting, on a joint axis, moves rigidly with it).
  A superelement without a recovery matrix falls back to a rigid transport from its
  nearest interface node (how joints and the TCP attach);
- the full-FE arm (:class:`~flexarm.assembly.full_arm.FullFEArm`, unreduced links): the
  same nearest-surface-node rule on the link's own FE DOFs, as sparse rows
  (:mod:`~flexarm.validation.dynamic.shapes_full`).
"""

from __future__ import annotations

import numpy as np

from ...assembly.analyses import modes
from ...assembly.effects import at_pose
from ...assembly.flexible import body_coordinates
from ...assembly.full_arm import FullFEArm
from ...assembly.system import ArmModel, rotation_blocks, system_matrices
from ...fe.typing import ArrayLike, FloatArray
from ...reduction.couplings import rigid_transport
from ..data.measurements import DIRECTIONS
from ..data.shape_data import Points, ShapeData
from .point_geometry import link_ends

__all__ = ["body_point_map", "point_map", "model_shapes", "model_shape_data", "default_points"]


def body_point_map(body, positions: ArrayLike, superelement=None) -> FloatArray:
    """(k, 3, n_b) translation of points at ``positions`` (k, 3) [m] (link frame) from
    the body's coordinates.

    Examples
    --------
    >>> from flexarm.assembly.examples import two_link_arm
    >>> b = two_link_arm().bodies[1]
    >>> (body_point_map(b, [[1.0, 0, 0]])[0] @ [0, 0, 0, 0, 0, 0.1]).round(3).tolist()
    [0.0, 0.1, 0.0]
    """
    p = np.asarray(positions, float).reshape(-1, 3)
    if body.is_rigid or superelement is None:
        if not body.is_rigid:
            raise ValueError(f"{body.name}: a flexible body needs its superelement to give "
                             "shapes at points (pass the arm's builds)")
        return rigid_transport(p - body.node_positions[0])
    se = superelement
    S = body_coordinates(se.node_positions, body.node_positions[0], se.n_dofs)
    if se.T is None or se.surface_points is None:
        c = np.asarray(se.node_positions, float)
        k = np.argmin(np.linalg.norm(p[:, None] - c[None], axis=2), axis=1)
        rows = (6 * k[:, None] + np.arange(6)).ravel()
        return np.einsum("kij,kjn->kin", rigid_transport(p - c[k]),
                         S[rows].reshape(len(p), 6, -1))
    surface = np.asarray(se.surface_points, float)
    v = np.argmin(np.linalg.norm(p[:, None] - surface[None], axis=2), axis=1)
    node = np.asarray(se.surface_nodes)[v]
    rows = (3 * node[:, None] + np.arange(3)).ravel()
    T = se.T[rows]
    T = T.toarray() if hasattr(T, "toarray") else np.asarray(T, float)
    G = (T @ S).reshape(len(p), 3, -1)
    # the point is carried from its nearest node by the link's rotation (exact for the
    # rigid motion; the bending is the node's)
    G[:, :, 3:6] += rigid_transport(p - surface[v])[:, :, 3:6]
    return G


def point_map(arm: ArmModel, q: ArrayLike, points: Points, builds=None) -> FloatArray:
    """(k, 3, n_x) base-frame translation [m] of each point per unit of ``x`` at pose
    ``q`` (n,) [rad]; ``builds`` (the arm's :class:`~flexarm.assembly.build.LinkBuild` s)
    give flexible bodies their recovery.

    Examples
    --------
    >>> from flexarm.assembly.examples import two_link_arm
    >>> pts = Points(nodes=[1], links=[2], positions=[[1.0, 0, 0]])
    >>> point_map(two_link_arm(), [0.0, 0.0], pts).shape
    (1, 3, 2)
    """
    q = np.asarray(q, float)
    sm = system_matrices(arm, q)
    n_bodies = len(arm.bodies)
    if np.any(points.links >= n_bodies):
        bad = points.nodes[points.links >= n_bodies][0]
        raise ValueError(f"node {bad}: link {points.links.max()} does not exist (the arm has "
                         f"bodies 0..{n_bodies - 1})")
    D = np.zeros((points.n_points, 3, sm.K.shape[-1]))
    for i in np.unique(points.links):
        rows = np.flatnonzero(points.links == i)
        body = arm.bodies[i]
        se = None if builds is None else builds[i].superelement
        G = body_point_map(body, points.positions[rows], se)
        R = sm.frames[i, :3, :3]
        Q = rotation_blocks(R, body.n_dofs, body.n_nodes)
        D[rows] = R @ G @ Q.T @ sm.T[i]
    return D


def model_shapes(arm: ArmModel, q: ArrayLike, points: Points, nodes: ArrayLike,
                 dirs: ArrayLike, n_modes: int | None = None, builds=None):
    """Natural frequencies [Hz] (n,), damping ratios (n,) and mode shapes (n, m) of
    ``arm`` at pose ``q`` at the DOFs (``nodes``, ``dirs``) (mass-normalised, metres
    per unit modal coordinate).

    Examples
    --------
    >>> from flexarm.assembly.examples import two_link_arm
    >>> pts = Points(nodes=[1], links=[2], positions=[[1.0, 0, 0]])
    >>> f, z, phi = model_shapes(two_link_arm(), [0.0, 0.0], pts, [1, 1], ["x", "y"])
    >>> phi.shape, bool(abs(phi[0, 0]) < 1e-12)
    ((2, 2), True)
    """
    md = modes(arm, q)
    n = len(md.freq_hz) if n_modes is None else min(int(n_modes), len(md.freq_hz))
    rows = points.index(nodes)
    axes = np.searchsorted(np.array(DIRECTIONS), np.asarray(dirs))
    if isinstance(arm, FullFEArm):  # every FE DOF: sparse rows
        from .shapes_full import full_point_rows

        D = full_point_rows(arm, q, points, rows, axes)
    else:
        D = point_map(arm, q, points, builds)[rows, axes]
    return md.freq_hz[:n], md.damping[:n], np.asarray((D @ md.shapes[:, :n]).T)


def model_shape_data(arm: ArmModel, poses: dict, points: Points, n_modes: int = 6,
                     builds=None, effects=()) -> ShapeData:
    """Frequencies, damping and shapes at every point (x, y, z) of ``arm`` at ``poses``
    (label -> q [rad]), as measured data would hold them; ``effects`` may hold
    pose-dependent springs (:func:`~flexarm.assembly.effects.at_pose`)."""
    nodes = np.repeat(points.nodes, 3)
    dirs = np.tile(list(DIRECTIONS), points.n_points)
    rows = []
    for label, q in poses.items():
        f, z, phi = model_shapes(at_pose(arm, effects, q), q, points, nodes, dirs, n_modes,
                                 builds)
        rows.append((label, np.asarray(q, float), f, z, phi))
    k = [len(r[2]) for r in rows]
    q6 = np.zeros((sum(k), 6))
    q6[:, :arm.chain.n_joints] = np.concatenate([np.tile(r[1], (len(r[2]), 1)) for r in rows])
    return ShapeData(poses=np.repeat([r[0] for r in rows], k), q=q6,
                     modes=np.concatenate([np.arange(1, n + 1) for n in k]),
                     freq_hz=np.concatenate([r[2] for r in rows]),
                     damping_ratio=np.concatenate([r[3] for r in rows]),
                     nodes=nodes, dirs=dirs, shapes=np.concatenate([r[4] for r in rows]))


def default_points(robot) -> Points:
    """Measurement points of a robot: on every moving link, the origin of the next
    joint (or the TCP on the last link) and the midpoint between it and the link's own
    joint (node ``100 i + k``: link ``i``, point ``k``).

    Examples
    --------
    >>> from flexarm.robot.demo_arm import load_demo_robot
    >>> p = default_points(load_demo_robot())
    >>> p.n_points, int(p.nodes[-1])
    (12, 601)
    """
    nodes, links, pos = [], [], []
    for i in range(1, len(robot.links)):
        ends = link_ends(robot, i)
        own = [0.5 * ends[0]] + ends if ends else [np.zeros(3)]
        for k, p in enumerate(own):
            nodes.append(100 * i + k)
            links.append(i)
            pos.append(p)
    return Points(nodes=nodes, links=links, positions=pos)
