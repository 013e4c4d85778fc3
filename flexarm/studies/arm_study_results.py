"""Results of the whole-arm accuracy study (:mod:`flexarm.studies.arm_study`): one row per
variant, the full-FE reference and the verdict."""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path

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
