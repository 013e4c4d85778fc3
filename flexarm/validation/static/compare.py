"""Predictions vs measurements: error tables like thesis Table 5, chi^2_red, plots.

Error per series (thesis eqs. 4.1-4.2): the absolute error is the mean over the
loaded readings of ``|d_meas - d_pred|`` along the load direction; the relative error
divides by the mean ``|d_meas|``.  The table groups series by pose and load direction.
chi^2_red uses the GLS noise model of :mod:`flexarm.validation.static.fit` with the *stated*
noise (no fitted parameters: dof = number of observations).
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ...assembly.system import ArmModel
from ...fe.text import text_table
from ..data.measurements import StaticData
from ..tolerances import tol
from .fit import Problem, chi2_band
from .report import write_report, write_rows

__all__ = ["SeriesError", "Comparison", "compare_static", "write_report", "write_rows"]


@dataclass(frozen=True)
class SeriesError:
    """Error of the model on one load series (a row of ``errors.csv``).

    Attributes
    ----------
    series : str
        Series label, ``"<pose>_<dir>"``.
    pose : str
        Pose label.
    dir : str
        Load direction, ``"+x"`` ... ``"-z"`` (the force component that dominates).
    mean_abs_mm, max_abs_mm : float
        Mean and largest ``|d_meas - d_pred|`` along the load direction over the loaded
        readings [mm].
    relative : float
        ``mean_abs_mm`` over the mean ``|d_meas|`` along the load direction
        (dimensionless).
    max_meas_mm : float
        Largest measured ``|d_meas|`` along the load direction [mm].
    """

    series: str
    pose: str
    dir: str
    mean_abs_mm: float
    max_abs_mm: float
    relative: float
    max_meas_mm: float


@dataclass(frozen=True)
class Comparison:
    """Result of :func:`compare_static`.

    Attributes
    ----------
    predicted : (n, 3) float
        Predicted relative deflections [m].
    table : tuple of SeriesError
        One row per series, in the order of the data.
    chi2_red : float
        GLS chi^2 per observation with the stated noise.
    band : (float, float)
        Acceptance band of ``chi2_red``.
    rms : float
        RMS of ``d_meas - d_pred`` over loaded readings [m].
    problem : Problem
        The data with the noise model and kinematics the comparison used.
    model : str
        Which model was compared (``"E-model"``, or ``"flexible model"`` with the
        links' flexibility), for titles.
    """

    predicted: np.ndarray
    table: tuple[SeriesError, ...]
    chi2_red: float
    band: tuple
    rms: float
    problem: Problem
    model: str = "E-model"

    @property
    def poses(self) -> str:
        """The measured poses, e.g. ``"P1, P2, P3"`` (the first few of many, with their
        count)."""
        names = sorted(set(self.pose_groups()[0]))
        shown = tol.plot_max_panels // 3
        return ", ".join(names[:shown]) + (f", ... ({len(names)} poses)"
                                           if len(names) > shown else "")

    def pose_groups(self) -> tuple[list[str], np.ndarray]:
        """The poses the series are grouped by in summaries and pictures: names, and
        (n_series,) the group of each series.

        The label's pose (``"P1"`` of ``"P1_y"``) while there are at most
        ``tol.plot_max_panels`` of them; else the measured joint angles, named by the
        label's pose where every series at those angles shares one, else by the angles
        [deg] (series labels that do not follow the ``<pose>_<dir>`` convention).
        """
        labels = [r.pose for r in self.table]
        distinct = dict.fromkeys(labels)
        if len(distinct) <= tol.plot_max_panels or self.problem is None:
            index = {p: i for i, p in enumerate(distinct)}
            return list(distinct), np.array([index[p] for p in labels], dtype=np.int64)
        pb = self.problem
        at = pb.pose_index[[g[0] for g in pb.groups]]
        distinct, first, inverse = np.unique(at, return_index=True, return_inverse=True)
        seen = np.argsort(first)  # groups in order of appearance
        of_series = np.argsort(seen)[inverse.ravel()]
        names = []
        for k, q in enumerate(pb.uq[distinct[seen]]):
            own = {labels[i] for i in np.flatnonzero(of_series == k)}
            names.append(own.pop() if len(own) == 1 else
                         "q=" + "/".join(f"{a:g}" for a in np.degrees(q).round(3)))
        return names, of_series

    def text(self) -> str:
        """The error table [mm], chi2_red with its band and the RMS [µm], as ``compare``
        prints them.  Past ``tol.table_max_rows`` series the table has one row per pose
        and load direction (:meth:`summary`; every series is in ``errors.csv``)."""
        lo, hi = self.band
        head = ["series", "mean_abs_mm", "max_abs_mm", "relative", "max_meas_mm"]
        rows = [[r.series, r.mean_abs_mm, r.max_abs_mm, r.relative, r.max_meas_mm]
                for r in self.table]
        note = []
        if len(self.table) > tol.table_max_rows:
            head = ["pose", "dir", "series"] + head[1:]
            rows = [list(r) for r in self.summary()]
            note = [f"{len(self.table):,d} series: one row per pose and load direction "
                    "(mean of the series' mean and relative errors, largest maxima); every "
                    "series in errors.csv (-o)"]
        return "\n".join([
            text_table(head, rows, "{:.4f}"), *note,
            f"chi2_red = {self.chi2_red:.3f} (band {lo:.3f}-{hi:.3f} for the stated noise), "
            f"RMS = {self.rms * 1e6:.1f} µm"])

    def summary(self) -> list[tuple[str, str, int, float, float, float, float]]:
        """One row per pose (:meth:`pose_groups`) and load direction, in order of
        appearance: pose, direction, number of series, mean of their ``mean_abs_mm``,
        largest ``max_abs_mm``, mean ``relative``, largest ``max_meas_mm``.

        Examples
        --------
        >>> rows = (SeriesError("P1_y", "P1", "+y", 0.125, 0.25, 0.5, 4.0),
        ...         SeriesError("P1_y2", "P1", "+y", 0.375, 0.5, 0.25, 4.5))
        >>> Comparison(np.zeros((0, 3)), rows, 1.0, (0.9, 1.1), 0.0, None).summary()
        [('P1', '+y', 2, 0.25, 0.5, 0.375, 4.5)]
        """
        names, of_series = self.pose_groups()
        groups: dict[tuple[str, str], list[SeriesError]] = {}
        for r, k in zip(self.table, of_series.tolist(), strict=True):
            groups.setdefault((names[k], r.dir), []).append(r)
        return [(pose, d, len(rs), float(np.mean([r.mean_abs_mm for r in rs])),
                 max(r.max_abs_mm for r in rs), float(np.mean([r.relative for r in rs])),
                 max(r.max_meas_mm for r in rs)) for (pose, d), rs in groups.items()]

    def write(self, folder) -> list[Path]:
        """:func:`~.report.write_report` into ``folder``: all files or none."""
        return write_report(folder, self)

    def write_errors(self, path) -> Path:
        """``errors.csv``: :attr:`table`, one row per series."""
        write_rows(path, SeriesError, self.table)
        return Path(path)


def compare_static(arm: ArmModel, data: StaticData, effects=(),
                   sigma: float = tol.tracker_sigma, flexible: ArmModel | None = None
                   ) -> Comparison:
    """Compare ``arm`` (plus ``effects``) with static ``data``.

    Examples
    --------
    >>> from flexarm.assembly.examples import two_link_arm
    >>> import numpy as np
    >>> d = StaticData(series=["a"] * 3, steps=[0, 1, 2], q=np.zeros((3, 6)),
    ...                force=np.zeros((3, 3)), disp=np.zeros((3, 3)))
    """
    pb = Problem(arm, data, sigma, flexible=flexible)
    pred = pb.predict(list(effects))
    r = pb.whiten(data.disp - pred)
    chi2_red = float(r @ r / max(pb.n_obs, 1))
    rows = [SeriesError(series=label, pose=label.split("_")[0], dir=direction, mean_abs_mm=e,
                        max_abs_mm=e_max, relative=rel, max_meas_mm=m_max)
            for label, direction, e, e_max, rel, m_max in zip(*_series_errors(pb, pred),
                                                                 strict=True)]
    res = (data.disp - pred)[~pb.is_ref]
    return Comparison(pred, tuple(rows), chi2_red, chi2_band(max(pb.n_obs, 1)),
                      float(np.sqrt(np.mean(res**2))) if res.size else 0.0, pb,
                      "E-model" if flexible is None else "flexible model")


def _series_errors(pb: Problem, pred: np.ndarray) -> tuple[list, ...]:
    """Per series (vectorised over the series, which are runs of rows): label, load
    direction, mean and largest error [mm] along it over the loaded readings, relative
    error, largest measured deflection [mm]."""
    data = pb.data
    starts = np.array([g[0] for g in pb.groups], dtype=np.int64)
    counts = np.array([len(g) - 1 for g in pb.groups], dtype=np.int64)  # loaded readings
    loaded = ~pb.is_ref
    f = np.where(loaded[:, None], data.force, 0.0)
    k = np.argmax(np.add.reduceat(np.abs(f), starts, axis=0), axis=1)  # dominant component
    row_k = k[pb.series_id]
    rows = np.arange(len(f))
    negative = np.add.reduceat(f[rows, row_k], starts) < 0
    err = np.where(loaded, np.abs(data.disp[rows, row_k] - pred[rows, row_k]), 0.0)
    meas = np.where(loaded, np.abs(data.disp[rows, row_k]), 0.0)
    n = np.maximum(counts, 1)
    mean_err, mean_meas = np.add.reduceat(err, starts) / n, np.add.reduceat(meas, starts) / n
    some = counts > 0
    labels = [str(x) for x in data.series[starts]]
    directions = [("-" if s else "+") + "xyz"[j] for s, j in zip(negative, k, strict=True)]
    return (labels, directions, np.where(some, mean_err * 1e3, 0.0).tolist(),
            np.where(some, np.maximum.reduceat(err, starts) * 1e3, 0.0).tolist(),
            np.where(some, mean_err / np.maximum(mean_meas, 1e-12), 0.0).tolist(),
            np.where(some, np.maximum.reduceat(meas, starts) * 1e3, 0.0).tolist())
