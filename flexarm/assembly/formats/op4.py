"""The arm's matrices at a pose as Nastran binary OP4, with a CSV table of its DOFs.

Matrices ``KAAX``, ``MAAX``, ``BAAX`` (viscous damping equal to the modal damping) on
the arm's independent coordinates, taken as ``SPOINT`` s ``1..n`` in order
(``K2GG = KAAX``, ``M2GG = MAAX``, ``B2GG = BAAX``), and ``GTCP`` (6 x n), the TCP
motion in the base frame (u_x, u_y, u_z [m], theta_x, theta_y, theta_z [rad]).
``<stem>_dofs.csv`` next to the file names each SPOINT (``spoint,name,unit``).
SI units.  Written bit for bit by :func:`~flexarm.reduction.formats.op4.write_matrices`.
"""

from __future__ import annotations

from pathlib import Path

from ...fe.files import atomic_path
from ...reduction.formats.op4 import write_matrices
from ..arm_matrices import ArmMatrices

__all__ = ["write", "dof_table_path"]


def dof_table_path(path) -> Path:
    """The DOF table written next to the OP4 file ``path``: ``<stem>_dofs.csv``."""
    path = Path(path)
    return path.with_name(f"{path.stem}_dofs.csv")


def write(path, am: ArmMatrices) -> None:
    """Write ``am`` to ``path`` (.op4) and its DOF table, each atomically."""
    rows = [f"{k + 1},{n},{u}" for k, (n, u) in
            enumerate(zip(am.coordinate_names, am.coordinate_units, strict=True))]
    with atomic_path(dof_table_path(path)) as tmp:
        tmp.write_text("spoint,name,unit\n" + "\n".join(rows) + "\n")
    write_matrices(path, {"KAAX": am.K, "MAAX": am.M, "BAAX": am.C, "GTCP": am.G_tcp})
