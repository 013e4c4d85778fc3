"""Each flexible link as the data of a floating-frame reduced-order body (Exudyn's
``ObjectFFRFreducedOrder``): mesh points, a nodal mass matrix, an elastic mode basis and
the reduced stiffness, all in the link frame.  Pure NumPy; no Exudyn needed.

The floating frame is the link frame at the proximal joint point with the proximal seat
clamped to it (the superelement body's coordinates, see
:func:`~flexarm.assembly.flexible.body_coordinates`): the elastic basis is the recovery
matrix of the Craig-Bampton superelement times the non-rigid body coordinates, so the
body sees exactly our constraint and fixed-interface modes, and the reduced stiffness is
our superelement's.  Two kinds of extra points are appended to the FE nodes, each moving
rigidly with the seat that carries it (the same rigid transport as the arm model):

- the lumped masses (motors, gearboxes, tool), each as six point masses at
  ``c +- d_i e_i`` on its principal axes, which have its mass, centre and inertia tensor;
- for every named point (distal joints, the TCP) a massless star of seven nodes, the
  point itself and ``p +- a e_i``, whose average is the point: a rigid marker there.

So the reduced mass matrix the floating-frame body assembles from these points is our
link body's mass matrix (to the float32 precision of the stored recovery matrix).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import scipy.sparse as sp

from ...assembly.bodies import Body, rigid_transport
from ...assembly.flexible import body_coordinates
from ...fe.mass_properties import MassProperties
from ...fe.typing import FloatArray
from ...reduction import Superelement

__all__ = ["FFRFLink", "ffrf_link", "point_masses", "body_mass_matrix"]

#: Arm of the massless marker stars [m]: any size works (they move rigidly).
MARKER_ARM = 0.05


@dataclass(frozen=True, eq=False)
class FFRFLink:
    """One link as a floating-frame reduced-order body (link frame, SI units).

    Attributes
    ----------
    name : str
    positions : (N, 3) float
        FE nodes, then lumped-mass points, then marker stars [m].
    M : (3N, 3N) sparse CSR
        Nodal mass matrix [kg] (the FE consistent mass, then point masses).
    Psi : (3N, m) float
        Elastic mode basis: nodal displacements [m] per unit body coordinate.
    K : (m, m) float
        Reduced stiffness of the elastic coordinates.
    points : dict str -> (7,) int
        Node indices of each named point's marker star (the point itself first).
    damping_ratio : float
        Modal damping ratio [-] of the link's strain energy.
    """

    name: str
    positions: FloatArray
    M: sp.csr_matrix
    Psi: FloatArray
    K: FloatArray
    points: dict
    damping_ratio: float = 0.01

    def point_position(self, name: str) -> FloatArray:
        """(3,) position of named point ``name`` [m], link frame."""
        return self.positions[self.points[name][0]]


def point_masses(mp: MassProperties) -> tuple[FloatArray, FloatArray]:
    """Six point masses with the mass, centre and inertia tensor of ``mp``.

    Returns positions (6, 3) [m] and masses (6,) [kg]: ``m / 6`` at ``c +- d_i e_i`` on
    the principal axes ``e_i``, with ``d_i = sqrt(3 s_i / m)`` and ``s_i`` the principal
    second moments.

    Examples
    --------
    >>> mp = MassProperties(6.0, np.zeros(3), np.diag([2.0, 3.0, 4.0]))
    >>> x, m = point_masses(mp)
    >>> J = sum(mi * (xi @ xi * np.eye(3) - np.outer(xi, xi)) for xi, mi in zip(x, m))
    >>> np.round(np.diag(J), 12).tolist(), float(m.sum())
    ([2.0, 3.0, 4.0], 6.0)
    """
    lam, R = np.linalg.eigh(np.asarray(mp.inertia, dtype=float))
    s = np.clip(0.5 * lam.sum() - lam, 0.0, None)  # second moments along the principal axes
    d = np.sqrt(3.0 * s / mp.mass) if mp.mass > 0 else np.zeros(3)
    offsets = np.concatenate([R * d, -(R * d)], axis=1).T  # columns e_i d_i, then -e_i d_i
    return np.asarray(mp.center_of_mass, float) + offsets, np.full(6, mp.mass / 6.0)


def _point_of(G: FloatArray) -> FloatArray:
    """Position [m] of a named point from its rigid transport ``G[:3, 3:6] = -skew(p)``."""
    return np.array([G[1, 5], G[2, 3], G[0, 4]])


def ffrf_link(body: Body, se: Superelement, M_fe: sp.spmatrix, fe_points: FloatArray,
              lumped: list[MassProperties] = ()) -> FFRFLink:
    """The :class:`FFRFLink` of a flexible link body built from ``se`` (origin at the link
    frame origin, as :func:`~flexarm.assembly.flexible.flexible_bodies` builds it).

    ``M_fe`` (3n, 3n) is the link's FE mass matrix [kg] and ``fe_points`` (n, 3) its nodes
    [m]; ``lumped`` the link's lumped masses.  Raises ``ValueError`` when the
    superelement has no recovery matrix.
    """
    if se.T is None:
        raise ValueError(f"{body.name}: the superelement has no recovery matrix (needed to "
                         "give the floating-frame body its mode shapes)")
    S = body_coordinates(se.node_positions, np.zeros(3), se.n_dofs)
    Psi = [np.asarray(se.T, dtype=float) @ S[:, 6:]]
    positions, masses = [np.asarray(fe_points, dtype=float)], []
    nodes = np.asarray(se.node_positions, dtype=float)
    for mp in lumped:
        k = int(np.argmin(np.linalg.norm(nodes - mp.center_of_mass, axis=1)))
        x, m = point_masses(mp)
        Sk = S[6 * k : 6 * k + 6]
        Psi.append((rigid_transport(x - nodes[k])[:, :3] @ Sk[:, 6:]).reshape(-1, Sk.shape[1] - 6))
        positions.append(x)
        masses.append(m)
    points, n = {}, sum(len(p) for p in positions)
    star = np.vstack([np.zeros(3), MARKER_ARM * np.eye(3), -MARKER_ARM * np.eye(3)])
    for name, G in body.points.items():
        x = _point_of(G) + star
        Psi.append((rigid_transport(star)[:, :3] @ G[:, 6:]).reshape(-1, G.shape[1] - 6))
        positions.append(x)
        masses.append(np.zeros(7))
        points[name] = np.arange(n, n + 7)
        n += 7
    diag = np.repeat(np.concatenate(masses), 3) if masses else np.zeros(0)
    M = sp.block_diag([sp.csr_matrix(M_fe), sp.diags(diag)], format="csr")
    return FFRFLink(body.name, np.vstack(positions), M, np.vstack(Psi),
                    np.asarray(body.K, dtype=float)[6:, 6:], points, body.damping_ratio)


def body_mass_matrix(link: FFRFLink) -> FloatArray:
    """(6 + m, 6 + m) mass matrix of the floating-frame body on (origin motion, elastic
    coordinates), assembled from its points: ``R^T M R`` with ``R = [rigid, Psi]``.

    Equal to the link :class:`~flexarm.assembly.bodies.Body`'s ``M`` when the points
    reproduce it (the check of this module).
    """
    R = np.hstack([rigid_transport(link.positions)[:, :3].reshape(-1, 6), link.Psi])
    return R.T @ (link.M @ R)
