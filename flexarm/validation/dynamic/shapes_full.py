"""Mode shapes at measurement points of the full-FE arm (unreduced links).

A point ``p`` on link ``i`` moves as the link's FE surface node nearest to it
(:attr:`~flexarm.assembly.full_fe.SparseBody.recovery`, couplings included) plus the
link's rotation times the offset from that node to ``p``: the recovery the
Craig-Bampton bodies use through their ``T``
(:func:`~flexarm.validation.dynamic.shapes.body_point_map`), so the shapes of both models are
compared point by point.  Rows are sparse: the full model has every FE DOF.
"""

from __future__ import annotations

import numpy as np
import scipy.sparse as sp

from ...assembly.full_arm import FullFEArm
from ...assembly.full_fe import SparseBody
from ...fe.typing import ArrayLike
from ...reduction.couplings import rigid_transport
from ...robot.kinematics import link_frames
from ..data.shape_data import Points

__all__ = ["sparse_body_point_map", "full_point_rows"]


def sparse_body_point_map(body: SparseBody, positions: ArrayLike) -> sp.csr_matrix:
    """(3 k, n_b) sparse translation [m] of points at ``positions`` (k, 3) [m] (link
    frame) from the body's floating-frame coordinates (rows x, y, z per point): the FE
    surface node nearest each point, plus the link's rotation times the offset to the
    point; a rigid body (no recovery) carries its joint point's motion rigidly."""
    p = np.asarray(positions, float).reshape(-1, 3)
    k, n_b = len(p), body.n_dofs
    if body.recovery is None:
        rigid = rigid_transport(p)[:, :3, :].reshape(3 * k, 6)
        return sp.csr_matrix((rigid.ravel(), (np.repeat(np.arange(3 * k), 6),
                                              np.tile(np.arange(6), 3 * k))),
                             shape=(3 * k, n_b))
    nodes, U = body.recovery
    near = np.argmin(np.linalg.norm(p[:, None] - nodes[None], axis=2), axis=1)
    G = U[(3 * near[:, None] + np.arange(3)).ravel()]
    turn = rigid_transport(p - nodes[near])[:, :3, 3:6].reshape(3 * k, 3)
    R = sp.csr_matrix((turn.ravel(), (np.repeat(np.arange(3 * k), 3),
                                      np.tile(np.arange(3, 6), 3 * k))), shape=(3 * k, n_b))
    return (G + R).tocsr()


def full_point_rows(fa: FullFEArm, q: ArrayLike, points: Points, rows: ArrayLike,
                    axes: ArrayLike) -> sp.csr_matrix:
    """(m, n_x) sparse base-frame translation [m] of the DOFs (point ``rows[r]``,
    direction ``axes[r]``) per unit of the full arm's coordinates at pose ``q`` [rad]."""
    q = np.asarray(q, float)
    mdl = fa.pose(q).model
    F = link_frames(fa.chain, q)
    rows, axes = np.asarray(rows, int), np.asarray(axes, int)
    if np.any(points.links >= len(fa.bodies)):
        bad = points.nodes[points.links >= len(fa.bodies)][0]
        raise ValueError(f"node {bad}: link {points.links.max()} does not exist (the arm has "
                         f"bodies 0..{len(fa.bodies) - 1})")
    blocks = [None] * points.n_points
    for i in np.unique(points.links):
        at = np.flatnonzero(points.links == i)
        G = sparse_body_point_map(fa.bodies[i], points.positions[at])
        R = sp.block_diag([F[i, :3, :3]] * len(at), format="csr")
        D = (R @ G @ mdl.body_maps[i]).tocsr()
        for n, a in enumerate(at):
            blocks[a] = D[3 * n:3 * n + 3]
    return sp.vstack([blocks[r][a] for r, a in zip(rows, axes, strict=True)]).tocsr()
