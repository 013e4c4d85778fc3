"""The result of :func:`~.workflow.compensate`: the new targets, the predicted gain, the limits.

:class:`CompensationResult` prints the summary the ``compensate`` command shows
(:meth:`~CompensationResult.text`) and writes the compensated module, the per-target
CSV and the picture (:meth:`~CompensationResult.write`).
"""

from __future__ import annotations

import csv
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from ...fe.files import atomic_path
from ...fe.typing import FloatArray, PathType
from .program.rapid_out import write_module_text
from .solve.limits import Limits
from .solve.runs import PathRun

__all__ = ["TargetShift", "CompensationResult", "CSV_COLUMNS"]

#: Columns of the per-target CSV, in order.
CSV_COLUMNS = ("target", "procedure", "x_mm", "y_mm", "z_mm",
               "dx_before_mm", "dy_before_mm", "dz_before_mm", "rot_before_mrad",
               "dx_after_mm", "dy_after_mm", "dz_after_mm", "rot_after_mrad",
               "shift_x_mm", "shift_y_mm", "shift_z_mm", "shift_rot_mrad")


@dataclass(frozen=True, eq=False)
class TargetShift:
    """One compensated robtarget.

    Attributes
    ----------
    name, procedure : str
        The robtarget and the procedure whose run set it (its first use).
    programmed_mm, written_mm : (3,) float
        Position before and after, as written in the module [mm].
    programmed_quat, written_quat : (4,) float
        Orientation ``[w, x, y, z]`` before and after, as written.
    before, after : (6,) float
        Predicted deviation of the loaded tool from the programmed pose [m, rad], with
        the programmed and with the written target.
    shift : (6,) float
        Written minus programmed pose [m, rad], base frame.
    spread : float
        Largest difference [m] between the shifts the target's other uses ask for (the
        same target in procedures with other loads).
    """

    name: str
    procedure: str
    programmed_mm: FloatArray
    written_mm: FloatArray
    programmed_quat: FloatArray
    written_quat: FloatArray
    before: FloatArray
    after: FloatArray
    shift: FloatArray
    spread: float = 0.0

    def row(self) -> list[str]:
        mm = [f"{v:.6f}" for v in self.programmed_mm]

        def part(d):
            return [f"{v * 1e3:.6f}" for v in d[:3]] + [f"{np.linalg.norm(d[3:]) * 1e3:.6f}"]

        return [self.name, self.procedure, *mm, *part(self.before), *part(self.after),
                *part(self.shift)]


@dataclass(frozen=True, eq=False)
class CompensationResult:
    """A compensated program.

    Attributes
    ----------
    source : str
        The program file ("" when given in memory).
    module_text : str
        The compensated module, ready to write.
    encoding : str
        The source file's text encoding (kept).
    shifts : tuple of TargetShift
        Every compensated robtarget, in order of first use.
    runs_before, runs_after : tuple of PathRun
        Predicted loaded path of each procedure, programmed and compensated.
    limits : Limits
        Where compensation cannot help.
    model, force : str
        What the prediction used, for reports.
    iterations : int
        Fixed-point iterations of the slowest procedure.
    notes : tuple of str
        What was left alone, and why.
    force_spec : ForceSpec or None
        The force (:mod:`.forces`), for running the program elsewhere (the lab).
    pivots : dict
        Procedure -> ball-bar pivot (3,) [m] the prediction used.
    split_mm : float or None
        Longest motion kept [mm] when long motions were split (:mod:`.densify`).
    header : tuple of str
        The comment lines written into the program (model, force, what changed).
    joints : dict
        Lower-case robtarget -> (joint angles (6,) [rad], ABB ``cfx``) the arm takes at
        the compensated target (other controllers' configuration data).
    tools : dict
        Procedure -> (4, 4) programmed tool frame on the flange (``tool0``) [m].
    """

    source: str
    module_text: str
    encoding: str
    shifts: tuple[TargetShift, ...]
    runs_before: tuple[PathRun, ...]
    runs_after: tuple[PathRun, ...]
    limits: Limits
    model: str
    force: str
    iterations: int = 0
    notes: tuple[str, ...] = ()
    force_spec: object = None
    pivots: dict = field(default_factory=dict)
    split_mm: float | None = None
    header: tuple[str, ...] = ()
    joints: dict = field(default_factory=dict)
    tools: dict = field(default_factory=dict)

    @property
    def largest_shift(self) -> tuple[float, float]:
        """(translation [m], rotation [rad]) of the largest target shift."""
        if not self.shifts:
            return 0.0, 0.0
        S = np.array([s.shift for s in self.shifts])
        return (float(np.linalg.norm(S[:, :3], axis=1).max()),
                float(np.linalg.norm(S[:, 3:], axis=1).max()))

    def text(self) -> str:
        """The summary the ``compensate`` command prints (mm, mrad)."""
        t, r = self.largest_shift
        lines = [f"{len(self.shifts)} targets shifted (largest {t * 1e3:.3f} mm, "
                 f"{r * 1e3:.3f} mrad) with the {self.model}; force: {self.force}"]
        lines.append("predicted deviation from the programmed path [mm] "
                     "(RMS radial for circles, else RMS distance; max distance):")
        for b, a in zip(self.runs_before, self.runs_after, strict=True):
            what = "radial" if b.circle is not None else "distance"
            lines.append(f"  {b.name:12s} before RMS {what} {b.rms() * 1e3:8.4f}, max "
                         f"{b.peak * 1e3:8.4f}; after {a.rms() * 1e3:8.4f}, max "
                         f"{a.peak * 1e3:8.4f}")
        after_t = max((float(np.abs(s.after[:3]).max()) for s in self.shifts), default=0.0)
        lines.append(f"at the targets the loaded tool is within {after_t * 1e6:.3g} µm of the "
                     "program")
        limit_lines = self.limits.lines() + self._between_targets()
        lines.append("limits: none found" if not limit_lines else "limits:")
        lines += [f"  {x}" for x in limit_lines]
        lines += [f"note: {n}" for n in self.notes]
        return "\n".join(lines)

    def _between_targets(self) -> list[str]:
        """Procedures whose compensated path keeps over a tenth of the deviation between
        the targets (the deflection changes along a motion; no jump explains it)."""
        out = []
        for b, a in zip(self.runs_before, self.runs_after, strict=True):
            if a.rms() <= 0.1 * b.rms():
                continue
            split = ("split them shorter" if self.split_mm is not None
                     else "split long motions (--split 30 mm) to follow it")
            out.append(f"{b.name}: between the targets the compensated path keeps "
                       f"{100 * a.rms() / b.rms():.0f} % of the deviation (the deflection "
                       f"changes along the motions); {split}")
        return out

    def write_module(self, path: PathType) -> Path:
        """The compensated module (atomic, in the source's encoding)."""
        return write_module_text(path, self.module_text, self.encoding)

    def write_csv(self, path: PathType) -> Path:
        """Per-target CSV (:data:`CSV_COLUMNS`): programmed position, predicted deviation
        before and after, and the shift written (mm, mrad), atomically."""
        path = Path(path)
        with atomic_path(path) as tmp, open(tmp, "w", newline="", encoding="utf-8") as fh:
            w = csv.writer(fh, lineterminator="\n")
            fh.write(f"# flexarm compensate: {self.model}; force: {self.force}\n")
            w.writerow(CSV_COLUMNS)
            w.writerows(s.row() for s in self.shifts)
        return path

    def write_plot(self, path: PathType) -> Path:
        """Top view and polar deviation before/after (:func:`~.plots.plot_compensation`)."""
        from .plots import plot_compensation

        return plot_compensation(self, path)

    def write_program(self, path: PathType, fmt: str | None = None,
                      template: PathType | None = None,
                      ptp_percent: float | None = None) -> list[Path]:
        """The compensated program as RAPID, KUKA KRL or a CSV of poses, by the suffix
        or ``fmt`` (:func:`~.program_out.write_program`)."""
        from .program.program_out import write_program

        return write_program(self, path, fmt, template, ptp_percent)

    def write(self, module: PathType, csv_path: PathType | None = None,
              png: PathType | None = None, fmt: str | None = None,
              template: PathType | None = None,
              ptp_percent: float | None = None) -> list[Path]:
        """The program (:meth:`write_program`), and the CSV and picture next to it
        (default names :func:`~.program_out.report_paths`), all or none of them
        (:func:`~.program_out.write_outputs`); returns the paths written."""
        from .program.program_out import write_outputs

        return write_outputs(self, module, csv_path, png, fmt, template, ptp_percent)
