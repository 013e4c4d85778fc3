"""Mass properties of a solid tetrahedral mesh (exact volume integrals)."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .geometry import skew
from .mesh import TetMesh

__all__ = ["MassProperties", "mass_properties", "rigid_body_mass_matrix"]


@dataclass(frozen=True)
class MassProperties:
    """Mass, centre of mass and inertia of a rigid body.

    Attributes
    ----------
    mass : float
        [kg]
    center_of_mass : (3,) float
        [m], in the frame of the mesh.
    inertia : (3, 3) float
        Inertia tensor about the centre of mass, axes of the mesh frame [kg m^2].
    """

    mass: float
    center_of_mass: np.ndarray
    inertia: np.ndarray

    def inertia_about(self, point) -> np.ndarray:
        """(3, 3) inertia about ``point`` [m] by the parallel-axis theorem [kg m^2]."""
        d = np.asarray(point, dtype=float) - self.center_of_mass
        return self.inertia + self.mass * (d @ d * np.eye(3) - np.outer(d, d))


def mass_properties(mesh: TetMesh, rho: float) -> MassProperties:
    """Mass properties of the solid (corner tetrahedra; exact for straight-sided elements).

    Parameters
    ----------
    mesh : TetMesh
    rho : float
        Density [kg/m^3].

    Examples
    --------
    >>> mp = mass_properties(TetMesh.box((2.0, 1.0, 1.0), (4, 2, 2)), rho=1000.0)
    >>> round(mp.mass, 9), [round(c, 12) for c in mp.center_of_mass]
    (2000.0, [1.0, 0.5, 0.5])
    >>> round(float(mp.inertia[0, 0]), 9)  # m (b^2 + c^2) / 12
    333.333333333
    """
    p = mesh.points[mesh.corner_tets]  # (m, 4, 3)
    vol = mesh.volumes()
    mass_e = rho * vol
    mass = float(mass_e.sum())
    centroids = p.mean(axis=1)
    com = (mass_e[:, None] * centroids).sum(axis=0) / mass
    # Second moments of a tetrahedron about the origin shifted to the COM:
    # int x_i x_j dV = V/20 (sum_a x_ai x_aj + s_i s_j), s = sum of the four corners.
    q = p - com
    s = q.sum(axis=1)
    second = np.einsum("e,eai,eaj->ij", mass_e, q, q) + np.einsum("e,ei,ej->ij", mass_e, s, s)
    second /= 20.0
    inertia = np.trace(second) * np.eye(3) - second
    return MassProperties(mass, com, inertia)


def rigid_body_mass_matrix(mp: MassProperties, reference_point) -> np.ndarray:
    """(6, 6) mass matrix of a rigid body for the motion of ``reference_point``.

    DOF order (u_x, u_y, u_z, theta_x, theta_y, theta_z) of the reference point [m, rad].
    """
    S = skew(mp.center_of_mass - np.asarray(reference_point, dtype=float))
    M = np.zeros((6, 6))
    M[:3, :3] = mp.mass * np.eye(3)
    M[:3, 3:] = -mp.mass * S
    M[3:, :3] = mp.mass * S
    M[3:, 3:] = mp.inertia - mp.mass * S @ S
    return M
