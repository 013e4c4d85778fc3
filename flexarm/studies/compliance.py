"""The TCP compliance of an arm at a pose: deflections, full vs diagonal stiffness
(thesis eqs. 3.9 and 3.12) and the gravity sag."""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ..assembly.analyses import gravity_sag, identify_stiffness, tcp_compliance
from ..assembly.system import ArmModel
from ..fe.files import atomic_path
from ..fe.notebook import data_frame
from ..fe.typing import ArrayLike, FloatArray

__all__ = ["ComplianceReport", "compliance_report"]

_XYZ = "xyz"


@dataclass(frozen=True, eq=False)
class ComplianceReport:
    """TCP compliance of an arm at one pose (base frame).

    Attributes
    ----------
    C : (6, 6) float
        TCP compliance [m/N, rad/(N m)].
    force : float
        Load per direction of the identification and the deflections [N].
    K_full, K_diag : (3, 3) float
        Translational stiffness identified from three load cases (eq. 3.12) and its
        diagonal-only model (eq. 3.9) [N/m].
    error_diag : (3,) float
        Relative error of the diagonal model per load case (+x, +y, +z) [-].
    sag : (6,) float
        TCP displacement under the arm's own weight [m, rad].
    """

    C: FloatArray
    force: float
    K_full: FloatArray
    K_diag: FloatArray
    error_diag: FloatArray
    sag: FloatArray

    @property
    def deflection(self) -> FloatArray:
        """(3,) TCP deflection [m] under ``force`` along x, y, z."""
        return self.force * np.diag(self.C)[:3]

    @property
    def weakest(self) -> str:
        """The least stiff translation direction: ``"x"``, ``"y"`` or ``"z"``."""
        return _XYZ[int(np.argmax(np.diag(self.C)[:3]))]

    def __repr__(self) -> str:
        """One line: deflections under ``force`` [mm], the least stiff direction, the
        largest error of the diagonal stiffness model [%] and the gravity sag [mm]."""
        defl = ", ".join(f"{d} {v * 1e3:.4g}" for d, v in zip(_XYZ, self.deflection,
                                                               strict=True))
        sag = ", ".join(f"{d} {v * 1e3:.4g}" for d, v in zip(_XYZ, self.sag[:3], strict=True))
        return (f"ComplianceReport(deflection under {self.force:g} N: {defl} mm; weakest "
                f"{self.weakest}; diagonal-model error up to "
                f"{np.abs(self.error_diag).max() * 100:.3g} %; gravity sag {sag} mm)")

    def to_dataframe(self):
        """``pandas.DataFrame``, one row per translation direction x, y, z (base frame):

        ``direction``; ``C_x_m_per_N`` … (its row of the translational compliance
        [m/N]); ``deflection_mm`` under ``force_N``; ``K_x_N_per_m`` … (its row of the
        identified stiffness, eq. 3.12); ``K_diag_N_per_m`` (the diagonal model, eq.
        3.9); ``error_diag`` (relative error of that model for the load case along the
        direction [-]); ``sag_mm`` (gravity sag along the direction).
        """
        columns = {"direction": list(_XYZ)}
        columns.update({f"C_{d}_m_per_N": self.C[:3, j] for j, d in enumerate(_XYZ)})
        columns["force_N"] = np.full(3, self.force)
        columns["deflection_mm"] = self.deflection * 1e3
        columns.update({f"K_{d}_N_per_m": self.K_full[:, j] for j, d in enumerate(_XYZ)})
        columns["K_diag_N_per_m"] = np.diag(self.K_diag)
        columns["error_diag"] = self.error_diag
        columns["sag_mm"] = self.sag[:3] * 1e3
        return data_frame(columns)

    def text(self) -> str:
        """The report as the ``compliance`` command prints it (mm, N, mm/kN, N/mm)."""
        C = self.C
        lines = ["TCP compliance, translations [mm/kN] (base frame):"]
        lines += [f"  {d}  " + " ".join(f"{C[i, j] * 1e6:10.4f}" for j in range(3))
                  for i, d in enumerate(_XYZ)]
        lines.append(f"deflection under {self.force:g} N [mm]: " + "  ".join(
            f"{d}={v * 1e3:.3f}" for d, v in zip(_XYZ, self.deflection, strict=True)))
        lines.append(f"least stiff direction: {self.weakest}")
        lines.append("stiffness [N/mm]: full (eq. 3.12)            diagonal (eq. 3.9)")
        lines += ["  " + " ".join(f"{self.K_full[i, j] * 1e-3:9.1f}" for j in range(3)) + "    "
                  + " ".join(f"{self.K_diag[i, j] * 1e-3:9.1f}" for j in range(3))
                  for i in range(3)]
        lines.append("diagonal-model error per load case [%]: " + "  ".join(
            f"{d}+={e * 100:.1f}" for d, e in zip(_XYZ, self.error_diag, strict=True)))
        lines.append("gravity sag of the TCP [mm]: " + "  ".join(
            f"{d}={self.sag[i] * 1e3:.3f}" for i, d in enumerate(_XYZ)))
        return "\n".join(lines)

    def write_csv(self, path) -> Path:
        """The 6 x 6 compliance as CSV in its four blocks, one unit per column, written
        atomically.

        One row per axis ``x``, ``y``, ``z`` of the response (base frame); per load axis
        ``j``: ``C_u_Fj_m_per_N`` (TCP translation per force), ``C_rot_Fj_rad_per_N``
        (rotation per force), ``C_u_Mj_m_per_Nm`` (translation per moment [m/(N m)]) and
        ``C_rot_Mj_rad_per_Nm`` (rotation per moment [rad/(N m)]).  The first three
        columns after ``axis`` are the translational block the ``compliance`` command
        prints.
        """
        blocks = [("u", "F", "m_per_N", self.C[:3, :3]), ("rot", "F", "rad_per_N", self.C[3:, :3]),
                  ("u", "M", "m_per_Nm", self.C[:3, 3:]),
                  ("rot", "M", "rad_per_Nm", self.C[3:, 3:])]
        head = ["axis"] + [f"C_{r}_{f}{d}_{unit}" for r, f, unit, _ in blocks for d in _XYZ]
        values = np.hstack([B for *_, B in blocks])
        lines = [",".join(head)] + [f"{d}," + ",".join(f"{v:.10g}" for v in row)
                                    for d, row in zip(_XYZ, values, strict=True)]
        with atomic_path(path) as tmp:
            tmp.write_text("\n".join(lines) + "\n")
        return Path(path)


def compliance_report(arm: ArmModel, q: ArrayLike, force: float = 800.0) -> ComplianceReport:
    """TCP compliance, stiffness identification from three load cases of ``force`` [N]
    along +x, +y, +z, and gravity sag, at pose ``q`` (n,) [rad].

    Examples
    --------
    >>> from flexarm.assembly import emodel
    >>> from flexarm.robot import load_robot
    >>> robot = load_robot()
    >>> rep = compliance_report(emodel(robot), robot.pose("P1"))
    >>> rep.weakest, round(float(rep.deflection[1]) * 1e3, 1)  # [mm] at 800 N
    ('y', 6.2)
    >>> rep.to_dataframe().set_index("direction")["deflection_mm"].round(1).tolist()
    [0.1, 6.2, 1.5]
    >>> compliance_report(emodel(robot), np.radians([0, 260, 0, 0, 0, 0]))
    Traceback (most recent call last):
    ...
    ValueError: pose: joint_2 = 260 deg is outside its limits [-90, 150] deg
    """
    # as the command line checks --pose (a full-FE arm is built for a pose already checked)
    if hasattr(arm, "check_pose"):
        arm.check_pose(q)
    C = tcp_compliance(arm, q)
    ident = identify_stiffness(arm, q, force * np.eye(3))
    return ComplianceReport(C, float(force), ident.K_full, ident.K_diag, ident.error_diag,
                            gravity_sag(arm, q))
