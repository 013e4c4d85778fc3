"""Measurement data sets as frozen dataclasses of arrays, in SI units.

One class per kind of file: :class:`StaticData` (load-deflection series),
:class:`ModalData` (natural frequencies per pose), :class:`FrfData` (receptances per
pose) and :class:`PathData` (loaded circle tests).  Arrays are read-only; use
``dataclasses.replace`` to derive a modified copy.  Two objects compare equal when
every array is identical (``np.array_equal``), which is what the file round trip
guarantees.

The constructors check shapes only.  The file readers check the meaning as well
(steps increasing, reference rows, limits, ...): see :mod:`flexarm.validation.data.formats`.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, fields

import numpy as np

from ...fe.notebook import names, span
from ...fe.typing import FloatArray, IntArray

__all__ = ["StaticData", "ModalData", "FrfData", "PathData", "DIRECTIONS", "TABLES"]

#: Allowed FRF input/output directions (base frame), in axis order.
DIRECTIONS = ("x", "y", "z")

#: Data class -> ``to_dataframe(data)`` of its file kind, filled by
#: :func:`flexarm.validation.data.formats.register_kind` when the package is imported (the
#: file kinds import this module, so it cannot import them).
TABLES: dict[type, Callable] = {}


def _array(obj, name: str, value, dtype, tail: tuple[int, ...], n: int | None,
           optional: bool = False):
    """Coerce field ``name`` to a read-only array of shape (n, *tail); return n."""
    if value is None:
        if optional:
            return n
        raise ValueError(f"{type(obj).__name__}.{name} is required")
    arr = value if _read_only(value, dtype) else np.array(value, dtype=dtype)
    expected = str(("n",) + tail if n is None else (n,) + tail).replace("'", "")
    if arr.ndim != 1 + len(tail) or arr.shape[1:] != tail or (n is not None and len(arr) != n):
        raise ValueError(f"{type(obj).__name__}.{name} must have shape "
                         f"{expected}, got {arr.shape}")
    if arr.dtype.kind in "fc" and not np.all(np.isfinite(arr)):
        raise ValueError(f"{type(obj).__name__}.{name} must be finite")
    arr.setflags(write=False)
    object.__setattr__(obj, name, arr)
    return len(arr)


#: Code points ``str.strip`` removes (blanks and line breaks of any script).
_BLANKS = np.array([c for c in range(0x3001) if chr(c).isspace()], dtype=np.uint32)


def _read_only(value, dtype) -> bool:
    """``value`` is an array of ``dtype`` that nothing can write to (the file readers'
    columns): shared, not copied (a million rows are hundreds of MB)."""
    base = value
    while isinstance(base, np.ndarray):
        if base.flags.writeable:
            return False
        base = base.base
    return isinstance(value, np.ndarray) and value.dtype == np.dtype(dtype)


def _labels(obj, name: str, value, n: int | None) -> int:
    """Labels: non-empty strings, no surrounding blanks, no line breaks, no leading '#'."""
    if value is not None:
        value = np.asarray(value)
        value = value.ravel() if value.dtype.kind == "U" else [str(v) for v in value.ravel()]
    n = _array(obj, name, value, np.str_, (), n)
    labels = getattr(obj, name)
    if not len(labels):  # no rows (a band with no mode in it): nothing to check
        return n
    # checked on the code points, a million labels at once (a trailing NUL is no character)
    codes = labels.view(np.uint32).reshape(len(labels), -1)
    last = np.maximum(np.count_nonzero(codes, axis=1) - 1, 0)
    wrong = ((codes[:, 0] == 0) | (codes[:, 0] == ord("#")) | np.isin(codes[:, 0], _BLANKS)
             | np.isin(codes[np.arange(len(codes)), last], _BLANKS)
             | ((codes == 10) | (codes == 13)).any(axis=1))
    if wrong.any():
        label = str(labels[np.argmax(wrong)])
        raise ValueError(f"{type(obj).__name__}.{name}: label {label!r} must be non-empty, "
                         "without surrounding blanks or line breaks, not starting with '#'")
    return n


def first_rows(labels: np.ndarray) -> IntArray:
    """(k,) int: index of the first row of each run of equal labels."""
    if len(labels) == 0:
        return np.zeros(0, dtype=np.int64)
    return np.flatnonzero(np.r_[True, labels[1:] != labels[:-1]]).astype(np.int64)


class _Arrays:
    """Equality by array content for the frozen dataclasses below."""

    def __eq__(self, other) -> bool:
        if type(other) is not type(self):
            return NotImplemented
        for f in fields(self):
            a, b = getattr(self, f.name), getattr(other, f.name)
            if (a is None) != (b is None):
                return False
            if a is not None and (a.shape != b.shape or not np.array_equal(a, b)):
                return False
        return True

    __hash__ = None  # mutable-looking content; not hashable

    @property
    def n_rows(self) -> int:
        """Number of measurement rows."""
        return len(getattr(self, fields(self)[0].name))

    def _optional(self) -> str:
        """``", with moment, rot"``: the optional fields present."""
        present = [f.name for f in fields(self)
                   if f.default is None and getattr(self, f.name) is not None]
        return f", with {', '.join(present)}" if present else ""

    def to_dataframe(self):
        """``pandas.DataFrame``, one row per reading, with the columns and units of the
        file writer (``q1_deg``, ``fx_N``, ``dx_mm``, ``freq_Hz``, ``re_m_per_N``, …;
        see :mod:`flexarm.validation.data.formats`)."""
        table = next(TABLES[c] for c in type(self).__mro__ if c in TABLES)
        return table(self)


@dataclass(frozen=True, eq=False)
class StaticData(_Arrays):
    """Static load-deflection series (one row per load step).

    Parameters
    ----------
    series : (n,) str
        Series label of each row; the rows of one series are contiguous.
    steps : (n,) int
        Step number; increases within a series, in measurement order.
    q : (n, 6) float
        Joint angles [rad].
    force : (n, 3) float
        Load at the TCP, base frame [N].
    disp : (n, 3) float
        TCP displacement relative to the series' first row, base frame [m].
    moment : (n, 3) float or None
        Moment at the TCP, base frame [N m].
    rot : (n, 3) float or None
        TCP rotation (small rotation vector) relative to the series' first row [rad].
    sigma : (n,) float or None
        Standard uncertainty of each displacement component [m].

    Examples
    --------
    >>> import numpy as np
    >>> d = StaticData(series=["a", "a", "b"], steps=[0, 1, 0], q=np.zeros((3, 6)),
    ...                force=[[0, 0, 0], [0, 100, 0], [0, 0, 0]], disp=np.zeros((3, 3)))
    >>> d.n_series, d.series_slices()
    (2, {'a': slice(0, 2, None), 'b': slice(2, 3, None)})
    >>> d.reference_rows().tolist()
    [0, 2]
    >>> d
    StaticData(3 readings, 2 series a, b, 1 pose, load 0–100 N, displacement up to 0 mm)
    >>> d.to_dataframe()[["series", "step", "fy_N", "dy_mm"]].values.tolist()
    [['a', 0, 0.0, 0.0], ['a', 1, 100.0, 0.0], ['b', 0, 0.0, 0.0]]
    """

    series: np.ndarray
    steps: IntArray
    q: FloatArray
    force: FloatArray
    disp: FloatArray
    moment: FloatArray | None = None
    rot: FloatArray | None = None
    sigma: FloatArray | None = None

    def __post_init__(self) -> None:
        n = _labels(self, "series", self.series, None)
        _array(self, "steps", self.steps, np.int64, (), n)
        _array(self, "q", self.q, np.float64, (6,), n)
        _array(self, "force", self.force, np.float64, (3,), n)
        _array(self, "disp", self.disp, np.float64, (3,), n)
        _array(self, "moment", self.moment, np.float64, (3,), n, optional=True)
        _array(self, "rot", self.rot, np.float64, (3,), n, optional=True)
        _array(self, "sigma", self.sigma, np.float64, (), n, optional=True)

    def reference_rows(self) -> IntArray:
        """(n_series,) int: the first row of each series, its reference reading."""
        return first_rows(self.series)

    def series_slices(self) -> dict[str, slice]:
        """Series label -> slice of its rows, in file order."""
        starts = self.reference_rows()
        stops = np.r_[starts[1:], len(self.series)]
        pairs = zip(starts.tolist(), stops.tolist(), strict=True)
        return {str(self.series[a]): slice(a, b) for a, b in pairs}

    @property
    def n_series(self) -> int:
        """Number of series."""
        return len(self.reference_rows())

    def __repr__(self) -> str:
        n_poses = len(np.unique(self.q, axis=0))
        disp = np.linalg.norm(self.disp, axis=1).max(initial=0.0) * 1e3
        return (f"StaticData({self.n_rows} readings, {self.n_series} series "
                f"{names(self.series_slices())}, {n_poses} pose{'s' * (n_poses != 1)}, "
                f"load {span(np.linalg.norm(self.force, axis=1), 'N')}, displacement up to "
                f"{disp:.4g} mm{self._optional()})")


class _Posed(_Arrays):
    """Helpers shared by data sets with one joint pose per ``poses`` label."""

    def pose_labels(self) -> list[str]:
        """Distinct pose labels in order of first appearance."""
        _, first = np.unique(self.poses, return_index=True)
        return [str(self.poses[i]) for i in np.sort(first)]

    @property
    def n_poses(self) -> int:
        """Number of distinct poses."""
        return len(np.unique(self.poses))

    def _poses_text(self) -> str:
        """``"2 poses P1, P2"``: the count and labels of the poses, for a ``repr``."""
        return f"{self.n_poses} pose{'s' * (self.n_poses != 1)} {names(self.pose_labels())}"


@dataclass(frozen=True, eq=False)
class ModalData(_Posed):
    """Measured natural frequencies (one row per pose and mode).

    Parameters
    ----------
    poses : (n,) str
        Pose label of each row.
    q : (n, 6) float
        Joint angles of the pose [rad].
    modes : (n,) int
        Mode number (1 = lowest) within the pose.
    freq_hz : (n,) float
        Natural frequency [Hz].
    damping_ratio : (n,) float or None
        Modal damping ratio [-].

    Examples
    --------
    >>> import numpy as np
    >>> m = ModalData(poses=["p1", "p1"], q=np.zeros((2, 6)), modes=[1, 2],
    ...               freq_hz=[12.5, 17.0])
    >>> m.n_poses, m.omega.round(2).tolist()
    (1, [78.54, 106.81])
    >>> m
    ModalData(2 modes at 1 pose p1, modes 1–2, 12.5–17 Hz)
    >>> m.to_dataframe()[["pose", "mode", "freq_Hz"]].values.tolist()
    [['p1', 1, 12.5], ['p1', 2, 17.0]]
    """

    poses: np.ndarray
    q: FloatArray
    modes: IntArray
    freq_hz: FloatArray
    damping_ratio: FloatArray | None = None

    def __post_init__(self) -> None:
        n = _labels(self, "poses", self.poses, None)
        _array(self, "q", self.q, np.float64, (6,), n)
        _array(self, "modes", self.modes, np.int64, (), n)
        _array(self, "freq_hz", self.freq_hz, np.float64, (), n)
        _array(self, "damping_ratio", self.damping_ratio, np.float64, (), n, optional=True)

    @property
    def omega(self) -> FloatArray:
        """(n,) float: angular frequencies [rad/s]."""
        return 2 * np.pi * self.freq_hz

    def __repr__(self) -> str:
        zeta = self.damping_ratio
        damping = "" if zeta is None else f", damping {span(zeta * 100, '%', '{:.3g}')}"
        return (f"{type(self).__name__}({self.n_rows} modes at {self._poses_text()}, modes "
                f"{span(self.modes, fmt='{:.0f}')}, {span(self.freq_hz, 'Hz')}{damping})")


@dataclass(frozen=True, eq=False)
class FrfData(_Posed):
    """Measured receptances, displacement per force (one row per frequency line).

    Parameters
    ----------
    poses : (n,) str
        Pose label of each row.
    q : (n, 6) float
        Joint angles of the pose [rad].
    inputs, outputs : (n,) str
        Force and response directions at the TCP, base frame, among ``x, y, z``.
    freq_hz : (n,) float
        Frequency [Hz].
    receptance : (n,) complex
        Displacement over force [m/N].
    coherence : (n,) float or None
        Ordinary coherence ``gamma^2`` [-] of each line, when measured: weights the
        comparison (:func:`~flexarm.validation.dynamic.frf_weights.coherence_weight`).

    Examples
    --------
    >>> import numpy as np
    >>> f = FrfData(poses=["p1"], q=np.zeros((1, 6)), inputs=["y"], outputs=["z"],
    ...             freq_hz=[10.0], receptance=[1e-6 - 2e-7j])
    >>> f.input_axes.tolist(), f.output_axes.tolist()
    ([1], [2])
    >>> f
    FrfData(1 frequency line at 1 pose p1, paths y->z, 10 Hz, |H| up to 1.02e-06 m/N)
    >>> f.to_dataframe()[["freq_Hz", "re_m_per_N", "im_m_per_N"]].values.tolist()
    [[10.0, 1e-06, -2e-07]]
    """

    poses: np.ndarray
    q: FloatArray
    inputs: np.ndarray
    outputs: np.ndarray
    freq_hz: FloatArray
    receptance: np.ndarray
    coherence: FloatArray | None = None

    def __post_init__(self) -> None:
        n = _labels(self, "poses", self.poses, None)
        _array(self, "q", self.q, np.float64, (6,), n)
        for name in ("inputs", "outputs"):
            _array(self, name, getattr(self, name), np.str_, (), n)
            bad = ~np.isin(getattr(self, name), DIRECTIONS)
            if bad.any():
                raise ValueError(f"FrfData.{name} must be among {', '.join(DIRECTIONS)}, "
                                 f"got {str(getattr(self, name)[bad][0])!r}")
        _array(self, "freq_hz", self.freq_hz, np.float64, (), n)
        _array(self, "receptance", self.receptance, np.complex128, (), n)
        _array(self, "coherence", self.coherence, np.float64, (), n, optional=True)

    @property
    def input_axes(self) -> IntArray:
        """(n,) int: input direction as axis index 0, 1, 2."""
        return np.searchsorted(np.array(DIRECTIONS), self.inputs).astype(np.int64)

    @property
    def output_axes(self) -> IntArray:
        """(n,) int: output direction as axis index 0, 1, 2."""
        return np.searchsorted(np.array(DIRECTIONS), self.outputs).astype(np.int64)

    def __repr__(self) -> str:
        paths = dict.fromkeys(f"{i}->{o}" for i, o in zip(self.inputs.tolist(),
                                                          self.outputs.tolist(), strict=True))
        h = np.abs(self.receptance).max(initial=0.0)
        return (f"FrfData({self.n_rows} frequency line{'s' * (self.n_rows != 1)} at "
                f"{self._poses_text()}, paths {names(paths)}, {span(self.freq_hz, 'Hz')}, "
                f"|H| up to {h:.3g} m/N)")


@dataclass(frozen=True, eq=False)
class PathData(_Arrays):
    """Loaded path test (circle under a constant bar force), one row per tracker reading.

    Parameters
    ----------
    steps : (n,) int
        Reading number, increasing.
    points : (n, 3) float
        Measured TCP position, base frame [m].
    force : (n,) float
        Load magnitude along the loading bar [N].

    Examples
    --------
    >>> p = PathData(steps=[0, 1], points=[[1.3, 0.0, 0.6], [1.3, 0.01, 0.6]],
    ...              force=[400.0, 400.0])
    >>> p.n_rows
    2
    >>> p
    PathData(2 readings, force 400 N, span 10 mm)
    """

    steps: IntArray
    points: FloatArray
    force: FloatArray

    def __post_init__(self) -> None:
        n = _array(self, "steps", self.steps, np.int64, (), None)
        _array(self, "points", self.points, np.float64, (3,), n)
        _array(self, "force", self.force, np.float64, (), n)

    def __repr__(self) -> str:
        extent = np.ptp(self.points, axis=0).max(initial=0.0) * 1e3 if self.n_rows else 0.0
        return (f"PathData({self.n_rows} readings, force {span(self.force, 'N')}, "
                f"span {extent:.4g} mm)")
