"""Bodies of the arm: matrices in the link frame plus named attachment points.

A :class:`Body` has ``n_nodes`` six-DOF nodes (u_x, u_y, u_z, theta_x, theta_y,
theta_z) first, then scalar modal coordinates that do not rotate.  DOFs 0..5 are
the *proximal* node, where the joint from the parent attaches (the foundation
point for the base).  A rigid link is a one-node body with ``K = 0``; a
Craig–Bampton superelement is a body with several nodes, modal DOFs and real ``K``.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, field
from types import MappingProxyType

import numpy as np

from ..fe.geometry import rigid_transport, skew
from ..fe.mass_properties import MassProperties, rigid_body_mass_matrix
from ..fe.typing import ArrayLike, FloatArray

__all__ = [
    "Body",
    "skew",
    "rigid_transport",
    "rigid_body",
    "combine_mass_properties",
    "point_mass_properties",
]


@dataclass(frozen=True, eq=False)
class Body:
    """One body of the arm in its link frame at zero joint angles.

    Parameters
    ----------
    name : str
    M, K : (n_b, n_b) float
        Mass [kg, kg m, kg m^2] and stiffness matrices; symmetric.
    node_positions : (n_nodes, 3) float
        Positions of the six-DOF nodes [m] in the link frame; node 0 is proximal.
    points : mapping of str to (6, n_b) float
        ``G`` of each named attachment point: its six DOFs (link frame) from the body DOFs.
    damping_ratio : float
        Modal damping ratio [-] of the strain energy stored in ``K``.
    """

    name: str
    M: FloatArray
    K: FloatArray
    node_positions: FloatArray
    points: Mapping[str, FloatArray] = field(default_factory=dict)
    damping_ratio: float = 0.01

    def __post_init__(self) -> None:
        M = np.asarray(self.M, dtype=float)
        K = np.asarray(self.K, dtype=float)
        nodes = np.asarray(self.node_positions, dtype=float).reshape(-1, 3)
        n = M.shape[0]
        if M.shape != (n, n) or K.shape != (n, n):
            raise ValueError(f"body '{self.name}': M and K must be square and equal, "
                             f"got {M.shape} and {K.shape}")
        if n < 6 * len(nodes) or len(nodes) < 1:
            raise ValueError(f"body '{self.name}': {len(nodes)} nodes need >= {6 * len(nodes)} "
                             f"DOFs, got {n}")
        pts = {}
        for key, G in self.points.items():
            G = np.array(G, dtype=float)
            if G.shape != (6, n):
                raise ValueError(f"body '{self.name}' point '{key}': G must be (6, {n}), "
                                 f"got {G.shape}")
            G.setflags(write=False)
            pts[key] = G
        for arr in (M, K, nodes):
            arr.setflags(write=False)
        object.__setattr__(self, "M", M)
        object.__setattr__(self, "K", K)
        object.__setattr__(self, "node_positions", nodes)
        object.__setattr__(self, "points", MappingProxyType(pts))

    @property
    def n_dofs(self) -> int:
        return self.M.shape[0]

    @property
    def n_nodes(self) -> int:
        return len(self.node_positions)

    @property
    def is_rigid(self) -> bool:
        """One node and no stiffness: a rigid body."""
        return self.n_dofs == 6 and not np.any(self.K)

    def G(self, name: str) -> FloatArray:
        """(6, n_b) DOFs of the named point in the link frame."""
        try:
            return self.points[name]
        except KeyError:
            raise KeyError(f"body '{self.name}' has no point '{name}' "
                           f"(has {sorted(self.points)})") from None

    def translation_modes(self) -> FloatArray:
        """(n_b, 3) body DOFs of a unit rigid translation along x, y, z."""
        U = np.zeros((self.n_dofs, 3))
        for k in range(self.n_nodes):
            U[6 * k : 6 * k + 3] = np.eye(3)
        return U


def rigid_body(
    name: str,
    mp: MassProperties,
    reference_point: ArrayLike,
    points: Mapping[str, ArrayLike] | None = None,
) -> Body:
    """One-node rigid :class:`Body` moving with ``reference_point`` [m] (link frame).

    ``points`` maps names to positions [m]; each gets ``G = rigid_transport(p - ref)``.

    Examples
    --------
    >>> mp = MassProperties(2.0, np.zeros(3), np.eye(3))
    >>> b = rigid_body("rod", mp, [0, 0, 0], {"tip": [1.0, 0, 0]})
    >>> (b.G("tip") @ [0, 0, 0, 0, 0, 0.1])[:3].tolist()  # theta_z = 0.1 moves the tip in y
    [0.0, 0.1, 0.0]
    """
    ref = np.asarray(reference_point, dtype=float)
    G = {k: rigid_transport(np.asarray(p, dtype=float) - ref) for k, p in (points or {}).items()}
    M = rigid_body_mass_matrix(mp, ref)
    return Body(name, M, np.zeros((6, 6)), ref[None, :], G, damping_ratio=0.0)


def point_mass_properties(mass: float, position: ArrayLike, inertia: ArrayLike = None):
    """:class:`MassProperties` of a lumped mass [kg] at ``position`` [m].

    ``inertia`` about its own centre: (3, 3), (3,) principal values, or None (point).
    """
    if mass < 0:
        raise ValueError(f"lumped mass must be >= 0 kg, got {mass}")
    J = np.zeros((3, 3)) if inertia is None else np.asarray(inertia, dtype=float)
    if J.shape == (3,):
        J = np.diag(J)
    if J.shape != (3, 3):
        raise ValueError(f"lumped inertia must be (3,) or (3, 3), got {J.shape}")
    return MassProperties(float(mass), np.asarray(position, dtype=float), J)


def combine_mass_properties(parts: list[MassProperties]) -> MassProperties:
    """Mass properties of rigidly joined parts (same frame), by the parallel-axis theorem."""
    mass = float(sum(p.mass for p in parts))
    if mass <= 0:
        raise ValueError("combined body has no mass")
    com = sum(p.mass * np.asarray(p.center_of_mass) for p in parts) / mass
    inertia = sum(p.inertia_about(com) for p in parts)
    return MassProperties(mass, com, inertia)
