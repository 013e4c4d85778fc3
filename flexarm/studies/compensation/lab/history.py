"""The loop's error history: the measured path at every step, against the original program.

The loop a user runs (measure, ``diagnose --apply``, ``compensate``, measure, ``compare``)
ends with a few measured paths of the same procedure: the program as written, the program
compensated with the nominal model, and compensated with the identified one.
:func:`path_history` sets each against the *original* program's path
(:func:`~.measured.compare_path`: no model involved) and gives, per step and procedure,
the RMS and the peak of the radial deviation (a circle, as a ball bar reads it) or of the
distance from the path (any other path), and the gain over the first step.
:class:`PathHistory` prints them, writes them as a CSV and draws them
(:func:`~flexarm.studies.compensation.plots.plot_history`: bars per step, and the polar
deviation of each step).
"""

from __future__ import annotations

import csv
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ....fe.files import atomic_files, atomic_path
from ....fe.typing import PathType
from .measured import MeasuredPath, compare_path

__all__ = ["PathHistory", "path_history", "HISTORY_COLUMNS", "PICTURE_SUFFIXES"]

#: Columns of the history CSV, in order (lengths in mm).
HISTORY_COLUMNS = ("step", "procedure", "data", "readings", "measure", "rms_mm", "peak_mm",
                   "peak_distance_mm", "gain")
#: Picture formats the history is drawn in.
PICTURE_SUFFIXES = (".png", ".svg", ".pdf")


def _mm(x: float) -> str:
    """A length [m] in mm, as the shortest text that reads back to the same number."""
    return repr(float(x) * 1e3)


@dataclass(frozen=True, eq=False)
class PathHistory:
    """Measured paths of the loop's steps against the original program.

    Attributes
    ----------
    steps : tuple of str
        The step label of each measured path (several paths may share one: the
        procedures of a step).
    measured : tuple of MeasuredPath
        Each path against its procedure of the original program.
    program : str
        The original program (for the report).
    """

    steps: tuple[str, ...]
    measured: tuple[MeasuredPath, ...]
    program: str

    @property
    def labels(self) -> tuple[str, ...]:
        """The steps, each once, in the order given."""
        return tuple(dict.fromkeys(self.steps))

    @property
    def procedures(self) -> tuple[str, ...]:
        """The procedures, each once, in the order met."""
        return tuple(dict.fromkeys(m.run.name for m in self.measured))

    def figures(self) -> list[dict]:
        """One row per measured path: :data:`HISTORY_COLUMNS`, lengths in m, ``gain`` the
        first step's RMS of the same procedure over this one's (NaN for a zero RMS)."""
        rows = []
        first: dict[str, float] = {}
        for step, m in zip(self.steps, self.measured, strict=True):
            r = m.run
            rms = r.rms()
            first.setdefault(r.name, rms)
            rows.append({"step": step, "procedure": r.name, "data": m.data,
                         "readings": len(r.points),
                         "measure": "radial" if r.circle is not None else "distance",
                         "rms": rms, "peak": float(np.abs(r.radial).max()),
                         "peak_distance": r.peak,
                         "gain": first[r.name] / rms if rms > 0 else float("nan")})
        return rows

    def text(self) -> str:
        """What the ``history`` command prints (mm)."""
        lines = [f"error history against {self.program} [mm] (radial deviation for circles, "
                 "else distance from the path):",
                 f"  {'step':30s} {'procedure':12s} {'readings':>8s} {'RMS':>9s} {'peak':>9s}"
                 f" {'gain':>7s}"]
        for f in self.figures():
            lines.append(f"  {f['step'][:30]:30s} {f['procedure'][:12]:12s} {f['readings']:8d} "
                         f"{f['rms'] * 1e3:9.4f} {f['peak'] * 1e3:9.4f} {f['gain']:6.1f}x")
        return "\n".join(lines)

    def write_csv(self, path: PathType) -> Path:
        """The figures (:data:`HISTORY_COLUMNS`, mm), atomically."""
        path = Path(path)
        with atomic_path(path) as tmp, open(tmp, "w", newline="", encoding="utf-8") as fh:
            fh.write(f"# flexarm history: measured paths against {self.program}\n")
            w = csv.writer(fh, lineterminator="\n")
            w.writerow(HISTORY_COLUMNS)
            for f in self.figures():
                w.writerow([f["step"], f["procedure"], f["data"], f["readings"], f["measure"],
                            _mm(f["rms"]), _mm(f["peak"]), _mm(f["peak_distance"]),
                            repr(f["gain"])])
        return path

    def write_plot(self, path: PathType) -> Path:
        """Bars per step and the polar deviation of each
        (:func:`~flexarm.studies.compensation.plots.plot_history`)."""
        from ..plots import plot_history

        return plot_history(self, path)

    def write(self, picture: PathType, csv_path: PathType | None = None) -> list[Path]:
        """The picture and the CSV (default: the picture's name with ``.csv``), both or
        neither (:func:`~flexarm.fe.files.atomic_files`); returns their paths."""
        picture = Path(picture)
        csv_path = picture.with_suffix(".csv") if csv_path is None else Path(csv_path)
        with atomic_files(picture, csv_path) as (png_tmp, csv_tmp):
            self.write_plot(png_tmp)
            self.write_csv(csv_tmp)
        return [picture, csv_path]


def path_history(paths: Sequence[PathType], program: PathType,
                 labels: Sequence[str] | None = None, proc: str | None = None,
                 step_mm: float = 1.0, krl_config: PathType | None = None) -> PathHistory:
    """The measured ``paths`` (path CSVs) of the loop's steps against ``program``.

    Parameters
    ----------
    paths : sequence of path
        Path CSVs (``step, x_mm, y_mm, z_mm, f_N``, what ``lab --program`` writes), in
        the order of the steps.
    program : path
        The original program (what the part needs), not a compensated one: a RAPID
        module or a CSV of poses.
    labels : sequence of str, optional
        The step of each path (default: the file names without suffix).  Paths of
        several procedures with the same label form one step.
    proc : str, optional
        The procedure of every path (default: the one nearest to each path's readings).
    step_mm : float
        Sampling step of the programmed path [mm].
    krl_config : path, optional
        The controller's ``$config.dat`` of a KRL program.

    Returns
    -------
    PathHistory

    Raises
    ------
    ValueError
        No path, labels not one per path, or the same procedure twice in one step.

    Examples
    --------
    >>> import tempfile, pathlib
    >>> from flexarm.robot.formats.rapid import read_rapid
    >>> from flexarm.robot.paths import sample_procedure
    >>> from flexarm.studies.contact.loaded_circle import THESIS_RAPID
    >>> from flexarm.validation.data.formats import write_path
    >>> from flexarm.validation.data.measurements import PathData
    >>> p = sample_procedure(read_rapid(THESIS_RAPID).procedure("Path_30")).points_m
    >>> folder = pathlib.Path(tempfile.mkdtemp())
    >>> files = [write_path(folder / f"{name}.csv", PathData(steps=np.arange(len(p)),
    ...          points=p * s, force=np.zeros(len(p)))) for name, s in (("before", 1.0002),
    ...                                                                 ("after", 1.00001))]
    >>> h = path_history(files, THESIS_RAPID)
    >>> [(f["step"], f["procedure"], round(f["gain"])) for f in h.figures()]
    [('before', 'Path_30', 1), ('after', 'Path_30', 20)]
    """
    paths = list(paths)
    if not paths:
        raise ValueError("history needs the measured path of at least one step")
    if labels is None:
        labels = [Path(p).stem for p in paths]
    labels = [str(x) for x in labels]
    if len(labels) != len(paths):
        raise ValueError(f"--label: {len(labels)} labels for {len(paths)} measured paths "
                         "(give one per path, in order)")
    measured = [compare_path(p, program, proc, step_mm, krl_config) for p in paths]
    seen: dict[tuple[str, str], str] = {}
    for label, m, p in zip(labels, measured, paths, strict=True):
        key = (label, m.run.name.lower())
        if key in seen:
            raise ValueError(f"{p}: a second measured path of {m.run.name} in step '{label}' "
                             f"(the first: {seen[key]}); give each step its own --label")
        seen[key] = str(p)
    return PathHistory(tuple(labels), tuple(measured), Path(program).name)
