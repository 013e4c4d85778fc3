"""Loaded circle tests in the static schema: readings to the overlay, and synthetic data.

A circle run is stored like a static series (the validation issue's schema): one
series per bar force, rows = path points with the joint angles ``q``, the bar force on
the load point ``f`` and the displacement ``d`` of the load point (the ball).  Because
the pose moves along the path, ``d`` is the *deflection*: the ball's deviation from
its commanded position, relative to the series' first row, the **reference reading**
(taken at the first path point with the bar unloaded, so it reads 0, 0, 0).  Then

* ``points = FK(q) + d`` are readings with the reference put on the nominal path
  (:func:`static_circle_readings`);
* every series gets its load level (the largest ``|f|`` of its rows); the reference
  row of a loaded series is dropped (it is an unloaded reading);
* :func:`~flexarm.studies.contact.ball_bar.measured_deviation` then subtracts the
  0-N series (interpolated at the same angle), so the overlay is ``d(F) - d(0)``,
  the definition the prediction uses, and gravity sag and the unknown reference
  offset (common to all series) cancel.

:func:`synthetic_static_circle` makes such data from a model (gravity sag + the
predicted deviation + Gaussian noise), used for the shipped example file.
"""

from __future__ import annotations

import logging
from dataclasses import replace
from pathlib import Path

import numpy as np

from ...assembly.analyses import GRAVITY, gravity_sag
from ...assembly.statics import series_starts
from ...assembly.system import ArmModel
from ...fe.files import atomic_path
from ...fe.typing import ArrayLike, FloatArray
from ...robot.kinematics import tcp_frame
from .ball_bar import CircleSetup, StaticSolver, _transfer, predict_circle

__all__ = ["static_circle_readings", "synthetic_static_circle", "write_circle_csv"]

log = logging.getLogger(__name__)


def static_circle_readings(setup: CircleSetup, chain, data, rows: bool = False) -> tuple:
    """Absolute readings and load levels of a circle run stored in the static schema.

    Parameters
    ----------
    setup : CircleSetup
        Gives the load point on the last body (``setup.ik.tool``).
    chain : Chain
        The robot's kinematics (``robot.chain``).
    data : StaticData
        Rows with ``series``, ``q`` (m, 6) [rad], ``force`` (m, 3) [N] on the load point
        and ``disp`` (m, 3) [m] relative to the series' first row.
    rows : bool
        Also return the kept rows' indices into ``data``.

    Returns
    -------
    points : (r, 3) float
        ``FK(q) + d`` of the kept rows [m].
    force : (r,) float
        The load level of each kept row's series [N].
    kept : (r,) int
        With ``rows``: the rows of ``data`` they come from.

    Examples
    --------
    >>> import numpy as np
    >>> from types import SimpleNamespace
    >>> from flexarm.assembly.examples import two_link_arm
    >>> arm = two_link_arm()
    >>> ik = SimpleNamespace(tool=np.eye(4))
    >>> s = SimpleNamespace(ik=ik)
    >>> d = SimpleNamespace(series=np.array(["a", "a"]), q=np.zeros((2, 2)),
    ...                     force=np.array([[0.0, 0, 0], [0, 0, 50]]), disp=np.zeros((2, 3)))
    >>> P, f = static_circle_readings(s, arm.chain, d)
    >>> P.shape, f.tolist()
    ((1, 3), [50.0])
    """
    q = np.asarray(data.q, dtype=float)
    force = np.linalg.norm(np.asarray(data.force, dtype=float), axis=1)
    disp = np.asarray(data.disp, dtype=float)
    if disp.shape != (len(q), 3) or force.shape != (len(q),):
        raise ValueError(f"q (m, n), force (m, 3) and disp (m, 3) differ: {q.shape}, "
                         f"{np.shape(data.force)}, {disp.shape}")
    ref = series_starts(data.series)
    level = np.zeros(len(q))
    np.maximum.at(level, ref, force)
    level = np.round(level[ref], 3)  # [N]: a file round trip leaves 1e-13 N
    is_ref = np.arange(len(q)) == ref
    keep = ~(is_ref & (level > 0))
    nominal = tcp_frame(replace(chain, tool=np.asarray(setup.ik.tool, float)), q)[:, :3, 3]
    log.info("static circle data: %d rows, %d series, levels %s N", len(q), len(np.unique(ref)),
             np.unique(level).tolist())
    if rows:
        return (nominal + disp)[keep], level[keep], np.flatnonzero(keep)
    return (nominal + disp)[keep], level[keep]


def _load_point_sag(arm: ArmModel, q: FloatArray, lever: FloatArray) -> FloatArray:
    """(n, 3) gravity sag of the load point [m] (linear model, all bodies' weight)."""
    return np.einsum("nij,nj->ni", _transfer(lever), gravity_sag(arm, q, GRAVITY))


def synthetic_static_circle(arm: ArmModel, setup: CircleSetup, loads: ArrayLike,
                            sigma: float = 5e-6, n_points: int = 24, seed: int = 0,
                            solver: StaticSolver | None = None) -> dict:
    """Static-schema rows of a simulated circle test: model + Gaussian noise.

    Parameters
    ----------
    arm : ArmModel
    setup : CircleSetup
    loads : (k,) float
        Bar forces [N] (push); one series each, 0 N first is advised.
    sigma : float
        Noise standard deviation per displacement component [m].
    n_points : int
        Path points per series (evenly spaced samples of ``setup``).
    seed : int
        Seed of ``numpy.random.default_rng``.
    solver : StaticSolver, optional
        See :func:`~flexarm.studies.contact.ball_bar.predict_circle`.

    Returns
    -------
    dict
        ``series`` (m,) str, ``steps`` (m,) int, ``q`` (m, 6) [rad], ``force`` (m, 3) [N],
        ``disp`` (m, 3) [m], ``sigma`` (m,) [m]: the fields of a ``StaticData``.  Each series
        starts with the unloaded reference reading at the first point.
    """
    F = np.atleast_1d(np.asarray(loads, dtype=float))
    idx = np.linspace(0, len(setup.points), n_points, endpoint=False).astype(int)
    sub = replace(setup, ik=replace(setup.ik, q=setup.ik.q[idx], frames=setup.ik.frames[idx]),
                  points=setup.points[idx])
    q = sub.ik.q
    lever = sub.points - tcp_frame(arm.chain, q)[:, :3, 3]
    sag = _load_point_sag(arm, q, lever)
    dev = predict_circle(arm, sub, F, solver=solver).deviation  # (k, n, 3)
    rng = np.random.default_rng(seed)
    rows: dict[str, list] = {k: [] for k in ("series", "steps", "q", "force", "disp")}
    for Fk, d in zip(F, dev, strict=True):
        reading = sag + d - sag[0]  # relative to the unloaded first point
        reading = reading + rng.normal(0.0, sigma, reading.shape)
        reading = np.vstack([np.zeros(3), reading])
        f = np.vstack([np.zeros(3), Fk * sub.bar_dirs])
        rows["series"] += [f"F{Fk:.0f}N"] * (len(q) + 1)
        rows["steps"] += list(range(len(q) + 1))
        rows["q"].append(np.vstack([q[:1], q]))
        rows["force"].append(f)
        rows["disp"].append(reading)
    out = {"series": np.array(rows["series"]), "steps": np.array(rows["steps"]),
           "q": np.vstack(rows["q"]), "force": np.vstack(rows["force"]),
           "disp": np.vstack(rows["disp"])}
    out["sigma"] = np.full(len(out["steps"]), float(sigma))
    return out


def write_circle_csv(path, runs) -> Path:
    """CSV of predicted deviations: one row per path sample, columns per model and load.

    ``runs`` = ``[(label, CirclePrediction)]`` on the same setup; columns
    ``bar_mm_<label>_<F>N``, ``radial_mm_…``, ``normal_mm_…`` after ``step, angle_deg,
    x_mm, y_mm, z_mm`` (the nominal load point).  Written atomically; returns ``path``.
    """
    setup = runs[0][1].setup
    cols = [np.arange(len(setup.points)), np.degrees(setup.angles), *(setup.points * 1e3).T]
    head = ["step", "angle_deg", "x_mm", "y_mm", "z_mm"]
    for label, pred in runs:
        tag = f"{label}_" if len(runs) > 1 else ""
        for F, b, r, z in zip(pred.loads, pred.bar, pred.radial, pred.normal, strict=True):
            cols += [b * 1e3, r * 1e3, z * 1e3]
            head += [f"{kind}_mm_{tag}{F:.0f}N" for kind in ("bar", "radial", "normal")]
    with atomic_path(path) as tmp:
        np.savetxt(tmp, np.column_stack(cols), delimiter=",", header=",".join(head),
                   comments="", fmt="%.9g")
    return Path(path)
