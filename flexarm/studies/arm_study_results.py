"""Results of the whole-arm accuracy study (:mod:`flexarm.studies.arm_study`): one row per
variant, the full-FE reference and the verdict."""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path

from ..fe.text import text_table
from ..fe.typing import FloatArray

__all__ = ["StudyRow", "Reference", "StudyResult"]


@dataclass(frozen=True)
class StudyRow:
    """One variant (errors relative [-], times [s], compliance base frame)."""

    mesh_size: float
    coupling: str
    n_modes: int
    label: str
    n_reduced: int
    n_fe_dofs: int
    freq_err_max: float
    freq_err_mean: float
    C_err_max: float
    C_err_mean: float
    build_seconds: float
    solve_seconds: float
    mesh_seconds: float = 0.0
    freq_hz: tuple = ()
    C_diag: tuple = ()

    @property
    def error(self) -> float:
        """The larger of the worst frequency and the worst compliance error [-]."""
        return max(self.freq_err_max, self.C_err_max)

    @property
    def seconds(self) -> float:
        """Build plus solve time [s]."""
        return self.build_seconds + self.solve_seconds


@dataclass(frozen=True)
class Reference:
    """Full-FE reference: ``freq_hz`` (n,) [Hz], ``C_diag`` (6,) [m/N, rad/(N m)]."""

    freq_hz: FloatArray
    C_diag: FloatArray
    n_dofs: int
    mesh_size: float
    coupling: str
    seconds: float


@dataclass(frozen=True)
class StudyResult:
    """All rows, the reference, the verdict text and the written files."""

    rows: tuple[StudyRow, ...]
    reference: Reference
    pose: str
    verdict: str
    files: tuple[Path, ...] = field(default=())

    def text(self) -> str:
        """The reference, one table row per variant, and the verdict."""
        ref = self.reference
        head = (f"reference: full FE, {ref.n_dofs} DOF at {ref.mesh_size * 1e3:.0f} mm "
                f"({ref.coupling}), {ref.seconds:.1f} s")
        table = text_table(
            ["size_mm", "coupling", "model", "DOF", "FE_DOF", "f_err_max_%", "f_err_mean_%",
             "C_err_max_%", "build_s", "solve_ms"],
            [[f"{r.mesh_size * 1e3:.0f}", r.coupling, r.label, r.n_reduced, r.n_fe_dofs,
              100 * r.freq_err_max, 100 * r.freq_err_mean, 100 * r.C_err_max,
              r.build_seconds, 1e3 * r.solve_seconds] for r in self.rows], floatfmt="{:.3g}")
        return f"{head}\n{table}\n{self.verdict}"
