"""Process forces along a robot program: what the tool feels at every target and sample.

Four kinds, each a frozen dataclass, all giving the wrench on the programmed tool point
in the base frame (force [N], moment [N m]):

* :class:`ConstantWrench` with ``frame="base"``: the same wrench everywhere (a weight,
  a press);
* :class:`ConstantWrench` with ``frame="tool"``: fixed in the programmed tool frame (a
  spindle's cutting force), turning with the tool;
* :class:`BallBar`: a loaded double ball bar pushing (or pulling) the tool point along
  the bar from its pivot, as in the circle test
  (:mod:`flexarm.studies.contact.ball_bar`);
* :class:`TargetWrenches`: one wrench per target from a CSV file (``target, fx_N, fy_N,
  fz_N`` and optionally ``mx_Nm, my_Nm, mz_Nm``, e.g. milling forces from a CAM or
  cutting-force model), interpolated along the path by arc length between targets.

:func:`parse_force` reads the command-line form (``base:fz=-300``, ``tool:fz=300N``,
``ballbar:800N``, ``ballbar:800N,pull``, ``forces.csv``).
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ....fe.quantities import Quantity
from ....fe.typing import FloatArray, PathType
from ....validation.data.formats._table import Field, Schema, read_table, vector

__all__ = ["ConstantWrench", "BallBar", "TargetWrenches", "ForceSpec", "parse_force",
           "read_target_wrenches", "target_wrenches", "path_wrenches"]

_COMPONENTS = ("fx", "fy", "fz", "mx", "my", "mz")
#: Plausible process loads: a bare number is N (N m).
_FORCE = Quantity("force", "N", -1e6, 1e6)
_MOMENT = Quantity("moment", "Nm", -1e6, 1e6)


def _fmt(v: FloatArray, unit: str) -> str:
    return "(" + ", ".join(f"{x:g}" for x in v) + f") {unit}"


@dataclass(frozen=True)
class ConstantWrench:
    """A constant wrench in the base frame or in the programmed tool frame.

    Parameters
    ----------
    force : (3,) float
        [N].
    moment : (3,) float
        [N m].
    frame : {"base", "tool"}
    """

    force: tuple = (0.0, 0.0, 0.0)
    moment: tuple = (0.0, 0.0, 0.0)
    frame: str = "base"

    def __post_init__(self) -> None:
        if self.frame not in ("base", "tool"):
            raise ValueError(f"frame must be 'base' or 'tool', got '{self.frame}'")
        w = np.r_[self.force, self.moment].astype(float)
        if w.shape != (6,) or not np.all(np.isfinite(w)):
            raise ValueError(f"force and moment must be 3 finite numbers each, got {w}")

    @property
    def label(self) -> str:
        m = f", moment {_fmt(self.moment, 'N m')}" if np.any(self.moment) else ""
        return f"constant {self.frame}-frame force {_fmt(self.force, 'N')}{m}"

    def at(self, frames: FloatArray, pivot=None) -> FloatArray:
        """(n, 6) wrench at tool frames ``frames`` (n, 4, 4) [m]."""
        w = np.tile(np.r_[self.force, self.moment].astype(float), (len(frames), 1))
        if self.frame == "tool":
            R = np.asarray(frames)[:, :3, :3]
            w[:, :3] = np.einsum("nij,nj->ni", R, w[:, :3])
            w[:, 3:] = np.einsum("nij,nj->ni", R, w[:, 3:])
        return w


@dataclass(frozen=True)
class BallBar:
    """A loaded ball bar: ``force`` [N] along the bar, pushing (or pulling) the tool point.

    ``pivot`` (3,) [m] is the bar's fixed ball; None takes each procedure's default
    (:func:`~flexarm.studies.contact.ball_bar.default_pivot`: the sphere of the module's
    circles about one axis).
    """

    force: float
    pull: bool = False
    pivot: tuple | None = None

    def __post_init__(self) -> None:
        if not (np.isfinite(self.force) and self.force >= 0):
            raise ValueError(f"ball-bar force must be a finite number >= 0 N, got {self.force}")

    @property
    def label(self) -> str:
        return f"ball bar {self.force:g} N {'pull' if self.pull else 'push'}"

    def at(self, frames: FloatArray, pivot=None) -> FloatArray:
        """(n, 6) wrench at tool frames (n, 4, 4) [m]; ``pivot`` when ``self.pivot`` is None."""
        piv = self.pivot if self.pivot is not None else pivot
        if piv is None:
            raise ValueError("ball bar: no pivot (give pivot=, or --pivot x,y,z in mm)")
        d = np.asarray(frames)[:, :3, 3] - np.asarray(piv, dtype=float)
        u = d / np.linalg.norm(d, axis=1, keepdims=True)
        w = np.zeros((len(u), 6))
        w[:, :3] = (-1.0 if self.pull else 1.0) * self.force * u
        return w


@dataclass(frozen=True, eq=False)
class TargetWrenches:
    """One wrench per named target (base frame): ``names`` (k,), ``wrenches`` (k, 6)
    [N, N m], read from ``source``."""

    names: tuple
    wrenches: FloatArray
    source: str = ""

    @property
    def label(self) -> str:
        return f"per-target forces from {Path(self.source).name or 'a table'}"

    def of(self, names) -> FloatArray:
        """(len(names), 6) wrenches of the named targets (case-insensitive).

        Raises
        ------
        ValueError
            A target the table does not list.
        """
        index = {n.lower(): i for i, n in enumerate(self.names)}
        missing = [n for n in names if n.lower() not in index]
        if missing:
            raise ValueError(f"{self.source or 'force table'}: no row for target "
                             f"'{missing[0]}' (the program's targets need one each)")
        return np.asarray(self.wrenches, float)[[index[n.lower()] for n in names]]

    def at(self, frames: FloatArray, pivot=None) -> FloatArray:
        raise ValueError("per-target forces need target names (use target_wrenches)")


ForceSpec = ConstantWrench | BallBar | TargetWrenches

_SCHEMA = Schema("forces", (Field("target", "label"), *vector("f", "force", "N"),
                            *vector("m", "moment", "Nm", required=False)),
                 "a per-target force file")


def read_target_wrenches(path: PathType) -> TargetWrenches:
    """Read a per-target force CSV: ``target, fx_N, fy_N, fz_N[, mx_Nm, my_Nm, mz_Nm]``.

    Units may be any the measurement files accept (``fx_kN``); errors name the file,
    line and column.

    Examples
    --------
    >>> import tempfile, os
    >>> p = os.path.join(tempfile.mkdtemp(), "f.csv")
    >>> _ = open(p, "w").write("target,fx_N,fy_N,fz_kN\\nTarget_70,0,300,-0.1\\n")
    >>> read_target_wrenches(p).wrenches.tolist()
    [[0.0, 300.0, -100.0, 0.0, 0.0, 0.0]]
    """
    table = read_table(path, _SCHEMA.vocabulary)
    v = table.parse(_SCHEMA)
    n = len(v["target"])
    w = np.column_stack([v.get(c, np.zeros(n)) for c in _COMPONENTS])
    names = tuple(str(s) for s in v["target"])
    seen: dict[str, int] = {}
    for i, name in enumerate(names):
        if name.lower() in seen:
            raise table.error(i, "target", f"target '{name}' is listed twice")
        seen[name.lower()] = i
    return TargetWrenches(names, w, str(path))


def parse_force(text: str, pivot=None) -> ForceSpec:
    """A force spec from its command-line form.

    ``base:fx=..,fy=..,fz=..[,mx=..,my=..,mz=..]`` and ``tool:...`` (N, kN; N m),
    ``ballbar:800N[,pull]``, or a CSV file (``forces.csv`` or ``csv:forces.csv``).
    ``pivot`` (3,) [m] goes to a ball bar.

    Examples
    --------
    >>> parse_force("tool:fz=0.3kN").label
    'constant tool-frame force (0, 0, 300) N'
    >>> parse_force("ballbar:800N,pull").label
    'ball bar 800 N pull'
    """
    spec = text.strip()
    kind, _, rest = spec.partition(":")
    kind = kind.strip().lower()
    if kind == "csv" or spec.lower().endswith(".csv"):
        return read_target_wrenches(rest.strip() if kind == "csv" else spec)
    if kind == "ballbar":
        parts = [p.strip() for p in rest.split(",") if p.strip()]
        pull = any(p.lower() == "pull" for p in parts)
        values = [p.split("=", 1)[-1] for p in parts if p.lower() not in ("pull", "push")]
        if len(values) != 1:
            raise ValueError(f"--force '{text}': expected ballbar:FORCE[,pull], e.g. "
                             "ballbar:800N")
        return BallBar(_FORCE.parse(values[0], "--force ballbar"), pull,
                       None if pivot is None else tuple(float(x) for x in pivot))
    if kind in ("base", "tool"):
        w = dict.fromkeys(_COMPONENTS, 0.0)
        for part in (p.strip() for p in rest.split(",") if p.strip()):
            key, eq, value = part.partition("=")
            key = key.strip().lower()
            if not eq or key not in w:
                raise ValueError(f"--force '{text}': '{part}' is not one of "
                                 f"{', '.join(_COMPONENTS)}=VALUE")
            w[key] = (_FORCE if key[0] == "f" else _MOMENT).parse(value, f"--force {key}")
        return ConstantWrench(tuple(w[c] for c in _COMPONENTS[:3]),
                              tuple(w[c] for c in _COMPONENTS[3:]), kind)
    raise ValueError(f"--force '{text}': expected base:fx=..,fy=..,fz=.., tool:..., "
                     "ballbar:FORCE[,pull] or a CSV file of per-target forces")


def target_wrenches(spec: ForceSpec, pp, pivot=None) -> FloatArray:
    """(k, 6) wrench at every target occurrence of a program path ``pp``
    (:class:`~.program_path.ProgramPath`) [N, N m], base frame (an example: :func:`path_wrenches`).
    """
    if isinstance(spec, TargetWrenches):
        return spec.of(pp.targets)
    return spec.at(pp.target_frames, pivot)


def path_wrenches(spec: ForceSpec, pp, frames: FloatArray | None = None,
                  pivot=None) -> FloatArray:
    """(n, 6) wrench at every sample of ``pp``, or at ``frames`` (n, 4, 4) [m] near them
    (the loaded tool): per-target forces interpolated by arc length between the targets.

    Examples
    --------
    >>> from flexarm.robot.demo_arm import load_demo_robot
    >>> from flexarm.robot.formats.rapid import read_rapid
    >>> from flexarm.studies.compensation.program import program_paths
    >>> from flexarm.studies.contact.loaded_circle import THESIS_RAPID
    >>> (pp,) = program_paths(load_demo_robot(), read_rapid(THESIS_RAPID), ["Path_30"],
    ...                       step_mm=20)
    >>> path_wrenches(ConstantWrench((0.0, 0.0, -200.0)), pp).shape == (pp.path.n_points, 6)
    True
    >>> w = target_wrenches(BallBar(800.0), pp, pivot=[1.33334, 0.04778, 0.588])
    >>> np.linalg.norm(w[:, :3], axis=1).round(6).tolist()
    [800.0, 800.0, 800.0, 800.0, 800.0]
    """
    frames = pp.frames if frames is None else frames
    if not isinstance(spec, TargetWrenches):
        return spec.at(frames, pivot)
    arc = pp.path.arc_length_mm
    at = arc[pp.target_samples]
    w = spec.of(pp.targets)
    return np.column_stack([np.interp(arc, at, w[:, c]) for c in range(6)])
