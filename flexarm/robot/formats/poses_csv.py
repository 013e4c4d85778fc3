"""A plain CSV of tool poses: ``target, x_mm, y_mm, z_mm, qw, qx, qy, qz``.

One row per target: the position [mm] and the unit quaternion ``[qw, qx, qy, qz]``
(scalar first: RAPID's ``[q1, q2, q3, q4]``) of the tool frame in the base frame
(``wobj0``).  ``#`` lines are comments.  :func:`module_poses` lists the targets of a
RAPID module's procedures in the order they are first used; :func:`write_poses` writes
them as the shortest decimals that read back to the same numbers, and :func:`read_poses`
reads them back exactly.
"""

from __future__ import annotations

import csv
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ...fe.errors import ReadError
from ...fe.files import atomic_path
from ...fe.typing import FloatArray, PathType
from .rapid_data import RapidModule, RobTarget

__all__ = ["COLUMNS", "Poses", "module_poses", "write_poses", "read_poses"]

#: The header row.
COLUMNS = ("target", "x_mm", "y_mm", "z_mm", "qw", "qx", "qy", "qz")


@dataclass(frozen=True, eq=False)
class Poses:
    """Named tool poses.

    Attributes
    ----------
    names : tuple of str
    points_mm : (n, 3) float
        Positions [mm], base frame.
    quats : (n, 4) float
        Orientations ``[w, x, y, z]``.
    """

    names: tuple[str, ...]
    points_mm: FloatArray
    quats: FloatArray

    def __post_init__(self) -> None:
        for attr, width in (("points_mm", 3), ("quats", 4)):
            arr = np.array(getattr(self, attr), dtype=np.float64).reshape(-1, width)
            if len(arr) != len(self.names):
                raise ValueError(f"Poses.{attr} needs one row per name ({len(self.names)}), "
                                 f"got {len(arr)}")
            arr.setflags(write=False)
            object.__setattr__(self, attr, arr)


def module_poses(module: RapidModule, procs: Sequence[str] | None = None) -> Poses:
    """The robtargets the procedures ``procs`` (default: all) move through, each once, in
    the order of first use (circle points included; joint targets are not poses).

    Examples
    --------
    >>> from flexarm.robot.formats.rapid import read_rapid
    >>> from flexarm.studies.contact.loaded_circle import THESIS_RAPID
    >>> module_poses(read_rapid(THESIS_RAPID), ["Path_30"]).names
    ('Target_70', 'Target_80', 'Target_90', 'Target_100', 'Target_110')
    """
    names = list(module.procedures) if procs is None else procs
    seen: dict[str, RobTarget] = {}
    for p in names:
        for m in module.procedure(p).motions:
            for t in m.targets:
                if isinstance(t, RobTarget) and t.name.lower() not in seen:
                    seen[t.name.lower()] = t
    ts = list(seen.values())
    return Poses(tuple(t.name for t in ts), [t.pos_mm for t in ts], [t.quat for t in ts])


def _num(x: float) -> str:
    """The shortest text of ``x`` that reads back to it ("0" for either zero)."""
    s = repr(float(x) + 0.0)
    return s[:-2] if s.endswith(".0") else s


def write_poses(path: PathType, poses: Poses, comments: Sequence[str] = ()) -> Path:
    """Write ``poses`` atomically, ``comments`` as ``#`` lines first.

    Examples
    --------
    >>> import tempfile, pathlib
    >>> p = pathlib.Path(tempfile.mkdtemp()) / "poses.csv"
    >>> _ = write_poses(p, Poses(("p1",), [[1000.5, 0, 500]], [[0, 0, 1, 0]]))
    >>> print(p.read_text(), end="")
    # tool poses in the base frame: position [mm], quaternion [qw, qx, qy, qz] (RAPID's q1..q4)
    target,x_mm,y_mm,z_mm,qw,qx,qy,qz
    p1,1000.5,0,500,0,0,1,0
    """
    path = Path(path)
    lines = ["tool poses in the base frame: position [mm], quaternion [qw, qx, qy, qz] "
             "(RAPID's q1..q4)", *comments]
    with atomic_path(path) as tmp, open(tmp, "w", newline="", encoding="utf-8") as fh:
        fh.write("".join(f"# {c}\n" for c in lines))
        w = csv.writer(fh, lineterminator="\n")
        w.writerow(COLUMNS)
        for n, p, q in zip(poses.names, poses.points_mm, poses.quats, strict=True):
            w.writerow([n, *(_num(v) for v in p), *(_num(v) for v in q)])
    return path


def read_poses(path: PathType) -> Poses:
    """Read a poses CSV (:data:`COLUMNS`, any order, extra columns ignored).

    Raises
    ------
    ReadError
        A missing column or a value that is not a finite number, naming file and line.

    Examples
    --------
    >>> import tempfile, pathlib
    >>> p = pathlib.Path(tempfile.mkdtemp()) / "poses.csv"
    >>> _ = write_poses(p, Poses(("p1",), [[1000.5, 0, 500]], [[0, 0, 1, 0]]))
    >>> read_poses(p).points_mm.tolist()
    [[1000.5, 0.0, 500.0]]
    """
    path = Path(path)
    try:
        text = path.read_text(encoding="utf-8")
    except (OSError, UnicodeDecodeError) as exc:
        raise ReadError(f"{path}: {getattr(exc, 'strerror', None) or exc}") from None
    rows = [(i + 1, r) for i, r in enumerate(csv.reader(text.splitlines()))
            if r and not r[0].lstrip().startswith("#")]
    if not rows:
        raise ReadError(f"{path}: no header row ({', '.join(COLUMNS)})")
    line, head = rows[0]
    head = [h.strip().lower() for h in head]
    missing = [c for c in COLUMNS if c not in head]
    if missing:
        raise ReadError(f"{path}, line {line}: missing column(s) {', '.join(missing)} "
                        f"(expected {', '.join(COLUMNS)})")
    at = [head.index(c) for c in COLUMNS]
    names, values = [], []
    for line, r in rows[1:]:
        try:
            v = [float(r[k]) for k in at[1:]]
        except (IndexError, ValueError):
            raise ReadError(f"{path}, line {line}: expected {len(head)} values with numbers "
                            f"in {', '.join(COLUMNS[1:])}") from None
        if not np.all(np.isfinite(v)) or not np.any(v[3:]):
            raise ReadError(f"{path}, line {line}: positions must be finite and the "
                            "quaternion non-zero")
        names.append(r[at[0]].strip())
        values.append(v)
    V = np.array(values, dtype=np.float64).reshape(-1, 7)
    return Poses(tuple(names), V[:, :3], V[:, 3:])
