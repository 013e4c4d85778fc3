"""A measured path against the program: how far the tool really was from where it should be.

The last step of the loop (measure, diagnose, compensate, measure, compare): a path CSV
(``step, x_mm, y_mm, z_mm, f_N``, what the lab or a tracker writes) is read and set
against the programmed path of a procedure of the *original* program: the deviation of
each reading from the nearest point of the programmed path and, when the program is a
circle, the radial deviation a ball bar reads (:class:`~.runs.PathRun`).  No model is
involved: it is the figure the shop floor sees.  The procedure is the one asked for, else
the one the file names in a ``# procedure: NAME`` comment (``lab --program`` writes it:
two procedures may run the same circle; :func:`~.path_in.named_procedure`), else the one
nearest to the readings.  The program is a RAPID module or a CSV of poses
(:func:`~.path_in.read_program`).
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ....fe.typing import PathType
from ....robot.paths import sample_procedure
from ....validation.data.formats import read_measurements
from ....validation.data.measurements import PathData
from ..program.path_in import named_procedure, read_program
from ..solve.runs import PathRun, circle_of, path_deviation

__all__ = ["MeasuredPath", "compare_path", "named_procedure"]


@dataclass(frozen=True, eq=False)
class MeasuredPath:
    """A measured path set against a programmed procedure.

    Attributes
    ----------
    run : PathRun
        The readings [m] against the programmed path.
    data, program : str
        The files compared (for the report).
    chosen : bool
        The procedure was picked as the one nearest to the readings (neither given nor
        named in the file).
    named : bool
        The procedure is the one the file names (:func:`named_procedure`).
    """

    run: PathRun
    data: str
    program: str
    chosen: bool = False
    named: bool = False

    def text(self) -> str:
        """What ``compare --program`` prints (mm)."""
        r = self.run
        how = " (the nearest to the readings)" if self.chosen else \
            " (named in the file)" if self.named else ""
        what = "radial deviation from the programmed circle" if r.circle is not None \
            else "distance from the programmed path"
        lines = [f"{self.data}: {len(r.points)} readings against {r.name}{how} of "
                 f"{self.program}",
                 f"RMS {what} {r.rms() * 1e3:.4f} mm, peak distance {r.peak * 1e3:.4f} mm"]
        if r.circle is not None:
            lines.append(f"programmed circle: radius {r.circle[2] * 1e3:.3f} mm; radial "
                         f"deviation from {r.radial.min() * 1e3:+.4f} to "
                         f"{r.radial.max() * 1e3:+.4f} mm")
        return "\n".join(lines)


def _run(name: str, programmed: np.ndarray, points: np.ndarray) -> PathRun:
    return PathRun(name, programmed, points, path_deviation(points, programmed),
                   circle_of(programmed))


def compare_path(data: PathData | PathType, program: PathType, proc: str | None = None,
                 step_mm: float = 1.0, krl_config: PathType | None = None) -> MeasuredPath:
    """Set a measured path against the programmed path of procedure ``proc``.

    Parameters
    ----------
    data : PathData or path
        The readings (a path CSV).
    program : path
        The program as written (the original, not its compensated version): a RAPID
        module or a CSV of poses (:func:`~.path_in.read_program`).
    proc : str, optional
        The procedure; default: the one the file names (:func:`named_procedure`), else
        the one whose programmed path the readings lie nearest to (RMS distance).
    step_mm : float
        Sampling step of the programmed path [mm].
    krl_config : path, optional
        The controller's ``$config.dat`` of a KRL program.

    Returns
    -------
    MeasuredPath

    Raises
    ------
    ValueError
        ``data`` is not a path measurement, or no procedure of ``program`` has motions.

    Examples
    --------
    >>> from flexarm.robot.formats.rapid import read_rapid
    >>> from flexarm.robot.paths import sample_procedure
    >>> from flexarm.studies.contact.loaded_circle import THESIS_RAPID
    >>> p = sample_procedure(read_rapid(THESIS_RAPID).procedure("Path_30")).points_m
    >>> on = PathData(steps=np.arange(len(p)), points=p * 1.0001, force=np.zeros(len(p)))
    >>> m = compare_path(on, THESIS_RAPID)
    >>> m.run.name, m.chosen, bool(m.run.peak < 0.2e-3)
    ('Path_30', True, True)
    """
    where = str(data) if not isinstance(data, PathData) else "readings"
    named = None
    if not isinstance(data, PathData):
        named = named_procedure(data) if proc is None else None
        data = read_measurements(data)
    if not isinstance(data, PathData):
        raise ValueError(f"{where}: a {type(data).__name__} file; --program compares a path "
                         "CSV (step, x_mm, y_mm, z_mm, f_N) with the program")
    module = read_program(program, krl_config=krl_config)[2]  # the path: no robot needed
    if named is not None and named.lower() not in {p.lower() for p in module.procedures}:
        named = None  # another program's procedure: the readings pick one
    proc = named if proc is None else proc
    try:
        names = [proc] if proc is not None else \
            [p for p, pr in module.procedures.items() if pr.motions]
        paths = {n: sample_procedure(module.procedure(n), step_mm=step_mm) for n in names}
    except KeyError as exc:
        raise ValueError(f"{program}: {exc.args[0]}") from None
    if not paths:
        raise ValueError(f"{program}: no procedure with motions")
    runs = [_run(p.name, p.points_m, data.points) for p in paths.values()]
    best = min(runs, key=lambda r: float(np.sqrt(np.mean(np.sum(r.deviation**2, axis=1)))))
    return MeasuredPath(best, where if where == "readings" else Path(where).name,
                        Path(program).name, len(runs) > 1, named is not None)
