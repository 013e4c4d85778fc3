"""The reduced arm at a pose as plain matrices (``K``, ``M``, a viscous damping matrix and
the TCP map) on its independent coordinates, for external solvers (Nastran OP4).

The damping matrix reproduces the model's modal damping exactly:
``C_v = M Phi diag(2 zeta_r omega_r) Phi^T M`` with the mass-normalised shapes ``Phi``
of every mode, so ``Phi^T C_v Phi = diag(2 zeta omega)``.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..fe.typing import ArrayLike, FloatArray
from .analyses import modes
from .full_arm import FullFEArm
from .system import ArmModel, system_matrices

__all__ = ["ArmMatrices", "arm_matrices"]

_UNITS = {"axial": "m", "radial1": "m", "radial2": "m", "torsion": "rad", "tilt1": "rad",
          "tilt2": "rad", "ux": "m", "uy": "m", "uz": "m", "rx": "rad", "ry": "rad",
          "rz": "rad"}


@dataclass(frozen=True, eq=False)
class ArmMatrices:
    """The assembled arm at one pose (SI units, base frame).

    Attributes
    ----------
    K, M, C : (n_x, n_x) float
        Stiffness, mass and viscous damping on the independent coordinates.
    G_tcp : (6, n_x) float
        TCP motion (u_x, u_y, u_z [m], theta_x, theta_y, theta_z [rad]) from them.
    coordinate_names : tuple of str
        ``joint_2.torsion`` (joint deflections [rad or m]), ``foundation.ux``, and each
        link's own coordinates ``<link>.q<k>`` (elastic seat motions, then modal amplitudes).
    coordinate_units : tuple of str
        ``m``, ``rad``, or ``-`` for link coordinates (mixed; see the superelement).
    q : (n,) float
        The pose [rad].
    model : str
    """

    K: FloatArray
    M: FloatArray
    C: FloatArray
    G_tcp: FloatArray
    coordinate_names: tuple[str, ...]
    coordinate_units: tuple[str, ...]
    q: FloatArray
    model: str = ""


def arm_matrices(arm: ArmModel, q: ArrayLike, model: str = "") -> ArmMatrices:
    """``K``, ``M``, the modal-damping matrix and the TCP map of a reduced arm at ``q``
    (n,) [rad].

    Examples
    --------
    >>> from flexarm.assembly.examples import two_link_arm
    >>> am = arm_matrices(two_link_arm(), [0.0, 0.5])
    >>> am.coordinate_names, am.coordinate_units
    (('joint_1.torsion', 'joint_2.torsion'), ('rad', 'rad'))
    """
    if isinstance(arm, FullFEArm):
        raise ValueError("the full-FE arm has tens of thousands of coordinates: export a "
                         "reduced model (emodel, guyan, cb) or its links' superelements")
    q = np.asarray(q, dtype=float)
    sm = system_matrices(arm, q)
    md = modes(arm, q)
    MPhi = sm.M @ md.shapes
    C = (MPhi * (2 * md.damping * md.omega)) @ MPhi.T
    names = tuple(arm.coordinate_names)
    units = tuple(_UNITS.get(n.rsplit(".", 1)[-1], "-") for n in names)
    return ArmMatrices(sm.K, sm.M, 0.5 * (C + C.T), sm.G_tcp, names, units, q, model)
