"""The compensated program for other controllers: RAPID, KUKA KRL or a CSV of poses.

The compensated targets are the same whatever the controller: :func:`write_program`
writes the RAPID text :func:`~.workflow.compensate` made (``rapid``), or reads it back
and writes its compensated procedures as a KRL ``.src``/``.dat`` pair
(:func:`~flexarm.robot.formats.krl.write_krl`, ``krl``) or as a plain CSV of poses
(:func:`~flexarm.robot.formats.poses_csv.write_poses`, ``csv``).  The format follows the
output's suffix (:func:`program_format`).

KRL needs each target's status and turn: they are derived from the joint angles the
arm takes at the compensated target (:attr:`~.result.CompensationResult.joints`,
:func:`~flexarm.robot.formats.krl.status_turn`), else kept from a template ``.dat``
(:func:`~flexarm.robot.formats.krl.read_status_turn`), else ``S 2 T 0``.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping
from pathlib import Path

import numpy as np

from ....fe.files import atomic_files
from ....fe.typing import PathType
from ....robot.formats.krl import check_krl_name, read_status_turn, status_turn, write_krl
from ....robot.formats.poses_csv import module_poses, write_poses
from .rapid_out import module_of_text, write_module_text

__all__ = ["FORMATS", "program_format", "program_files", "report_paths", "output_files",
           "write_program", "write_outputs"]

#: Program format -> the output suffixes that imply it.
FORMATS = {"rapid": (".mod", ".modx", ".prg"), "krl": (".src",), "csv": (".csv",)}


def program_format(path: PathType, fmt: str | None = None) -> str:
    """The format (``rapid``, ``krl``, ``csv``) a program written to ``path`` takes:
    ``fmt`` when given (it must agree with a known suffix), else the suffix's.

    Raises
    ------
    ValueError
        An unknown or contradicting suffix, or a KRL file name KRL cannot hold (naming
        the option).

    Examples
    --------
    >>> program_format("out.src"), program_format("out.txt", "csv")
    ('krl', 'csv')
    """
    path = Path(path)
    implied = next((f for f, sfx in FORMATS.items() if path.suffix.lower() in sfx), None)
    if fmt is None and implied is None:
        raise ValueError(f"-o {path.name}: cannot tell the program format from the suffix; "
                         "end the name in .mod (RAPID), .src (KUKA KRL) or .csv (poses), or "
                         "give --format")
    if fmt is not None and fmt not in FORMATS:
        raise ValueError(f"--format {fmt}: expected one of {', '.join(FORMATS)}")
    if fmt is not None and implied is not None and fmt != implied:
        raise ValueError(f"--format {fmt} contradicts -o {path.name} (a {implied} name)")
    fmt = fmt or implied
    if fmt == "krl":
        check_krl_name(path.stem, "-o: KRL module")
    return fmt


def report_paths(path: PathType, fmt: str, csv_path=None, png=None) -> tuple[Path, Path]:
    """(per-target CSV, picture) next to the program ``path``: ``<stem>.csv`` and
    ``<stem>.png``, or ``<stem>_deviation.csv`` when the program itself is a CSV.

    Examples
    --------
    >>> [p.name for p in report_paths("c.csv", "csv")]
    ['c_deviation.csv', 'c.png']
    """
    path = Path(path)
    if csv_path is None:
        csv_path = path.with_name(f"{path.stem}_deviation.csv") if fmt == "csv" \
            else path.with_suffix(".csv")
    return Path(csv_path), path.with_suffix(".png") if png is None else Path(png)


def program_files(path: PathType, fmt: str) -> list[Path]:
    """The files a program of format ``fmt`` written to ``path`` makes: ``path``, and the
    ``.dat`` beside a KRL ``.src``.

    Examples
    --------
    >>> [p.name for p in program_files("out.src", "krl")]
    ['out.src', 'out.dat']
    """
    path = Path(path)
    return [path, path.with_suffix(".dat")] if fmt == "krl" else [path]


def _status(res, template) -> dict[str, tuple[int, int]]:
    """Lower-case target -> (S, T): the template's, overridden where the joints are known."""
    if template is None or isinstance(template, Mapping):
        out = {k.lower(): v for k, v in (template or {}).items()}
    else:
        out = read_status_turn(template)
    if res.joints:
        keys = list(res.joints)
        q = np.degrees(np.array([res.joints[k][0] for k in keys]))
        S, T = status_turn(q, [res.joints[k][1] for k in keys])
        out.update({k: (int(s), int(t)) for k, s, t in zip(keys, S, T, strict=True)})
    return out


def _write_program(res, path: Path, fmt: str, status, ptp_percent) -> None:
    if fmt == "rapid":
        write_module_text(path, res.module_text, res.encoding)
        return
    module = module_of_text(res.module_text, res.encoding, res.source or "compensated.mod")
    procs = [r.name for r in res.runs_before]
    if fmt == "csv":  # one procedure keeps its name when the CSV is read as a program
        named = [f"procedure: {procs[0]}"] if len(procs) == 1 else []
        write_poses(path, module_poses(module, procs), [*res.header, *named])
        return
    tools = {p: np.diag([1e3, 1e3, 1e3, 1.0]) @ T for p, T in res.tools.items()}
    write_krl(path, module, procs, tools, status, res.header, ptp_percent)


def _naming(tmp: Path, write: Callable[[Path], object]) -> None:
    """``write(tmp)``, an OS error that names no file (a full disk's ``write``) naming
    ``tmp``: the temporary folder's writer then names the file at its final place."""
    try:
        write(tmp)
    except OSError as exc:
        if exc.filename is not None or exc.strerror is None:
            raise
        raise OSError(exc.errno, exc.strerror, str(tmp)) from exc


def write_program(res, path: PathType, fmt: str | None = None,
                  template: PathType | Mapping | None = None,
                  ptp_percent: float | None = None) -> list[Path]:
    """Write the compensated program of ``res`` (:class:`~.result.CompensationResult`).

    The files appear together or not at all (:func:`~flexarm.fe.files.atomic_files`).

    Parameters
    ----------
    res : CompensationResult
    path : path
        The program: ``.mod`` (RAPID, the whole module), ``.src`` (KRL; the ``.dat`` is
        written beside it) or ``.csv`` (poses), see :func:`program_format`.
    fmt : {"rapid", "krl", "csv"}, optional
        Overrides the suffix.
    template : path or mapping, optional
        A KRL ``.dat`` (or its :func:`~flexarm.robot.formats.krl.read_status_turn`)
        whose ``S``/``T`` are kept where the joints do not tell them.
    ptp_percent : float, optional
        KRL: ``$VEL_AXIS`` of the point-to-point moves [%] (default: a slow first run,
        :data:`~flexarm.robot.formats.krl.DEFAULT_PTP_PERCENT`).

    Returns
    -------
    list of Path
        The files written.

    Examples
    --------
    >>> import tempfile, pathlib
    >>> from flexarm.studies.compensation import compensate
    >>> from flexarm.studies.contact.loaded_circle import THESIS_RAPID
    >>> res = compensate(THESIS_RAPID, force="ballbar:800N", procs=["Path_30"], step_mm=10)
    >>> out = pathlib.Path(tempfile.mkdtemp()) / "comp.src"
    >>> [p.name for p in write_program(res, out)]
    ['comp.src', 'comp.dat']
    """
    return write_outputs(res, path, fmt=fmt, template=template, ptp_percent=ptp_percent,
                         reports=False)


def output_files(path: PathType, fmt: str | None = None, csv_path: PathType | None = None,
                 png: PathType | None = None) -> list[Path]:
    """Every file :func:`write_outputs` writes: the program's, the CSV and the picture.

    Raises
    ------
    ValueError
        A file named twice (``--csv`` the program itself ...), or a name that is a folder:
        found before any work.

    Examples
    --------
    >>> [p.name for p in output_files("c.csv")]
    ['c.csv', 'c_deviation.csv', 'c.png']
    """
    fmt = program_format(path, fmt)
    files = [*program_files(path, fmt), *report_paths(path, fmt, csv_path, png)]
    seen = [p.absolute() for p in files]
    for k, p in enumerate(files):
        if seen[k] in seen[:k]:
            raise ValueError(f"{p}: named twice among the outputs (the program, --csv, --png)")
        if p.is_dir():
            raise ValueError(f"{p}: is a folder, not a file name")
    return files


def write_outputs(res, path: PathType, csv_path: PathType | None = None,
                  png: PathType | None = None, fmt: str | None = None,
                  template: PathType | Mapping | None = None,
                  ptp_percent: float | None = None, reports: bool = True) -> list[Path]:
    """The program (:func:`write_program`) and, with ``reports``, the per-target CSV and
    the picture (default names :func:`report_paths`), all through one temporary folder
    per output folder (:func:`~flexarm.fe.files.atomic_files`): every file appears, or
    none (Ctrl-C, a full disk) and older ones are kept.  Returns the paths written.
    """
    fmt = program_format(path, fmt)
    status = _status(res, template) if fmt == "krl" else None  # a bad template: nothing made
    files = output_files(path, fmt, csv_path, png) if reports else program_files(path, fmt)
    jobs: list[tuple[int, Callable[[Path], object]]] = [
        (0, lambda p: _write_program(res, p, fmt, status, ptp_percent))]  # .dat with .src
    if reports:
        jobs += [(len(files) - 2, res.write_csv), (len(files) - 1, res.write_plot)]
    with atomic_files(*files) as tmps:
        for k, write in jobs:
            _naming(tmps[k], write)
    return files
