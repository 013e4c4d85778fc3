"""Results of the whole-arm accuracy study (:mod:`flexarm.studies.arm_study`): one row per
variant, the full-FE reference and the verdict."""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path

from ..fe.text import text_table
from ..fe.typing import FloatArray

__all__ = ["StudyRow", "Reference", "DiscretisationEstimate", "StudyResult"]


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
class DiscretisationEstimate:
    """Mesh (discretisation) error of the finest size, two ways.

    *p-refinement* (``p_refined``, per mode, ``f_k / f_(k+1) - 1`` [-]): the full FE on
    the finest mesh with order-``k`` elements against the same mesh with order ``k+1``.
    The order-k space lies inside the order-(k+1) space, so by the min-max principle
    every order-k frequency is at least its order-(k+1) counterpart, which is at least
    the exact one: the change is a *lower bound* of the order-k error (close to it when
    the higher order's own error is small).

    *Richardson* (``change`` [-], the largest relative frequency change between the two
    finest sizes, ``ratio`` their effective edge-length ratio from the FE DOF counts):
    ``change / (ratio^(2k) - 1)`` assumes the asymptotic rate ``h^(2k)``.  Thin walls
    meshed coarser than their thickness are far from it (Tet4 locks in bending), and
    fTetWild's edge-length target hardly changes a mesh that its features already fine:
    the p-refinement is the estimate to trust where both exist.

    Examples
    --------
    >>> e = DiscretisationEstimate(0.03, 1, "CB(10)", "rbe2", change=0.05, ratio=1.5,
    ...                            h_coarse=0.045, p_refined=(0.01, 0.2, 0.12))
    >>> round(e.richardson, 4), e.lower, e.worst_mode
    (0.04, 0.2, 2)
    """

    h_fine: float
    order: int
    label: str = ""
    coupling: str = ""
    change: float | None = None
    ratio: float | None = None
    h_coarse: float | None = None
    p_refined: tuple = ()

    @property
    def richardson(self) -> float | None:
        """Relative error of the finest size at the asymptotic rate ``h^(2k)`` [-]
        (None without two sizes that differ)."""
        if self.change is None or self.ratio is None or self.ratio <= 1.0:
            return None
        return self.change / (self.ratio ** (2 * self.order) - 1)

    @property
    def lower(self) -> float | None:
        """The largest p-refinement change: the order-k error is at least this [-]."""
        return max(self.p_refined) if self.p_refined else None

    @property
    def worst_mode(self) -> int | None:
        """1-based mode of :attr:`lower`."""
        return int(max(range(len(self.p_refined)), key=self.p_refined.__getitem__)) + 1 \
            if self.p_refined else None

    def text(self) -> str:
        """One line for the verdict."""
        tet, hi = f"Tet{4 if self.order == 1 else 10}", f"Tet{10 if self.order == 1 else 20}"
        head = f"discretisation error at {self.h_fine * 1e3:.0f} mm ({tet})"
        parts = []
        if self.p_refined:
            parts.append(f"at least {100 * self.lower:.2g}% (mode {self.worst_mode}; f1 "
                         f"{100 * self.p_refined[0]:.2g}%) against the full FE with {hi} "
                         "elements on the same mesh")
        r = self.richardson
        if r is not None:
            rich = (f"Richardson from {self.h_coarse * 1e3:.0f} and {self.h_fine * 1e3:.0f} mm "
                    f"(effective edge ratio {self.ratio:.2f}, {self.label} {self.coupling}) "
                    f"{'says' if self.p_refined else 'gives'} about {100 * r:.2g}%")
            if self.p_refined and r < 0.5 * self.lower:
                rich += ", far below: the meshes are not in the asymptotic range"
            parts.append(rich)
        if not parts:
            return (f"{head}: not estimated (give two mesh sizes or a {hi} reference); the "
                    f"errors above are against the full FE model at that size")
        return (f"{head}: " + "; ".join(parts) + "; the reduction errors above are against "
                f"the full FE ({tet}) at {self.h_fine * 1e3:.0f} mm")


@dataclass(frozen=True)
class StudyResult:
    """All rows, the reference, the verdict text, the mesh-error estimate (None with one
    mesh size) and the written files."""

    rows: tuple[StudyRow, ...]
    reference: Reference
    pose: str
    verdict: str
    files: tuple[Path, ...] = field(default=())
    discretisation: DiscretisationEstimate | None = None

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
