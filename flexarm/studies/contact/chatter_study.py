"""The chatter jobs: the arm at one pose against a CNC machine, and the map's outputs.

:func:`run_chatter` puts the arm's 2-DOF plane model
(:func:`~flexarm.studies.contact.chatter.plane_model`) and a typed-in CNC machine of the
same mass under one cutting process: the closed-form verdict, the limit ``K_c b`` and a
simulated free response of each (thesis §4.4, Figs 4.30/4.31).  :func:`write_chatter_map`
writes a :class:`~flexarm.studies.contact.chatter_map.ChatterMap` as CSV and heat map.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ...assembly.system import ArmModel
from ...fe.files import writes_folder
from ...fe.typing import ArrayLike, FloatArray
from .chatter import ChatterResult, analyse, cnc_model, plane_model, process_vectors, simulate
from .chatter_map import ChatterMap, critical_kcb, worst_normal
from .plots import plot_chatter_map, plot_chatter_orbit, plot_chatter_time

__all__ = ["ChatterStudy", "run_chatter", "write_chatter_map"]

#: Disturbance along the surface normal that starts the simulated free responses [m].
DISTURBANCE = 1e-5

#: A simulated response that grows past this (100x the disturbance) is chattering; it is
#: drawn and tabulated up to there, not on to metres of orbit [m].
ORBIT_LIMIT = 100 * DISTURBANCE


@dataclass(frozen=True, eq=False)
class ChatterStudy:
    """The robot and a CNC machine under the same cutting process.

    Attributes
    ----------
    results : tuple of ChatterResult
        Robot (``results[0].structure`` is its plane model) and CNC machine.
    limits : tuple of float
        Limit ``K_c b`` [N/m] of each for this normal and force direction (``inf``: none).
    normal_deg : float
        Surface-normal angle from ``e1`` [deg] (the robot's worst unless given).
    dir_deg : float
        Force angle from the normal [deg].
    t : (m,) float
        Times of the simulated free responses [s].
    x : (2, m, 2) float
        Plane coordinates [m] of robot and CNC after a :data:`DISTURBANCE` along the normal.
    """

    results: tuple[ChatterResult, ChatterResult]
    limits: tuple[float, float]
    normal_deg: float
    dir_deg: float
    t: FloatArray
    x: FloatArray

    @property
    def kcb(self) -> float:
        """Process stiffness ``K_c b`` [N/m]."""
        return self.results[0].kcb

    @property
    def limit(self) -> float:
        """The robot's limit ``K_c b`` [N/m]."""
        return self.limits[0]

    def text(self) -> str:
        """The summary the ``chatter`` command prints (N/m, kg, 1/s, deg)."""
        axes = self.results[0].structure.axes
        lines = [f"plane e1={np.round(axes[0], 3).tolist()} e2={np.round(axes[1], 3).tolist()}; "
                 f"normal {self.normal_deg:.1f} deg, force {self.dir_deg:.1f} deg from it, "
                 f"K_c b {self.kcb:.3g} N/m"]
        for res, lim in zip(self.results, self.limits, strict=True):
            m = res.structure
            ks = np.linalg.eigvalsh(m.K)
            lines.append(f"{m.name:5s}: K principal {ks[0]:.3g}/{ks[1]:.3g} N/m, M diag "
                         f"{np.diag(m.M).round(1).tolist()} kg, growth {res.growth_rate:+.3f} "
                         f"1/s, limit K_c b {lim:.3g} N/m -> "
                         f"{'stable' if res.is_stable else 'UNSTABLE'}")
        verdict = "; ".join(f"{r.structure.name} "
                            f"{'stable' if r.is_stable else 'CHATTERS (mode coupling)'}"
                            for r in self.results)
        return "\n".join(lines + [f"verdict: {verdict}"])

    def shown(self) -> FloatArray:
        """(2, m, 2) plane coordinates [m] as drawn and tabulated: :attr:`x`, NaN from
        the first sample where a run leaves :data:`ORBIT_LIMIT` (a chattering run grows
        exponentially; its later samples are out of any physical range)."""
        amp = np.linalg.norm(self.x, axis=-1)
        past = np.maximum.accumulate(amp > ORBIT_LIMIT, axis=1)
        return np.where(past[..., None], np.nan, self.x)

    @writes_folder()
    def write(self, folder, label: str = "") -> list[Path]:
        """``chatter_time.csv`` (``t_s`` and the plane coordinates ``<run>_x1_m``,
        ``<run>_x2_m`` of :meth:`shown`), ``chatter_time.png`` (time histories) and
        ``chatter_orbit.png`` (tool orbits in the plane) in ``folder`` (created);
        ``label`` (model and pose) heads the titles."""
        from ...fe.files import atomic_path

        folder = Path(folder)
        folder.mkdir(parents=True, exist_ok=True)
        shown = self.shown()
        runs = []
        for r, x in zip(self.results, shown, strict=True):
            left = np.isnan(x[:, 0])
            note = (f", left ±{ORBIT_LIMIT * 1e3:g} mm at {self.t[np.argmax(left)]:.2f} s"
                    if left.any() else "")
            runs.append((f"{label + ' ' if label else ''}{r.structure.name}: "
                         f"{'stable' if r.is_stable else 'chatter'}, growth "
                         f"{r.growth_rate:+.2f} 1/s{note}", self.t, x))
        csv = folder / "chatter_time.csv"
        cols = ["t_s"] + [f"{r.structure.name.strip().lower()}_x{i}_m"
                          for r in self.results for i in (1, 2)]
        rows = np.column_stack([self.t] + [x[:, i] for x in shown for i in (0, 1)])
        with atomic_path(csv) as tmp:
            np.savetxt(tmp, rows, delimiter=",", comments="", fmt="%.10g",
                       header=",".join(cols))
        return [csv, plot_chatter_time(runs, folder / "chatter_time.png"),
                plot_chatter_orbit(runs, folder / "chatter_orbit.png")]


def run_chatter(arm: ArmModel, q: ArrayLike, kcb: float, dir_deg: float = 30.0,
                normal_deg: float | None = None, cnc_stiffness: float = 5e7,
                duration: float = 2.0) -> ChatterStudy:
    """Mode-coupling chatter of ``arm`` at pose ``q`` (6,) [rad] vs a CNC machine.

    Parameters
    ----------
    arm : ArmModel
    q : (6,) float
        Pose [rad].
    kcb : float
        Process stiffness ``K_c b`` [N/m].
    dir_deg : float
        Force angle from the surface normal [deg].
    normal_deg : float, optional
        Surface-normal angle from ``e1`` in the plane [deg]; default: the orientation
        with the robot's smallest limit (:func:`~.chatter_map.worst_normal`).
    cnc_stiffness : float
        CNC stiffness [N/m] (:func:`~flexarm.studies.contact.chatter.cnc_model`, mass: the
        mean of the robot's plane-model diagonal masses).
    duration : float
        Simulated time [s].

    Examples
    --------
    >>> from flexarm.assembly import emodel
    >>> from flexarm.robot import load_robot
    >>> r = load_robot()
    >>> st = run_chatter(emodel(r), r.pose("P1"), 5e5, 30.0, duration=0.1)
    >>> print(st.text().splitlines()[-1])
    verdict: robot CHATTERS (mode coupling); CNC stable
    >>> round(st.limit / 1e5, 2)  # [1e5 N/m], below K_c b = 5e5 N/m
    2.54
    """
    pm = plane_model(arm, q)
    normal = (float(worst_normal(pm.M, pm.C, pm.K, dir_deg)[1]) if normal_deg is None
              else float(normal_deg))
    cnc = cnc_model(cnc_stiffness, float(np.trace(pm.M)) / 2, axes=pm.axes)
    n, f = process_vectors(normal, dir_deg)
    results = tuple(analyse(m, kcb, dir_deg, normal) for m in (pm, cnc))
    limits = tuple(float(critical_kcb(m.M, m.C, m.K, n, f)) for m in (pm, cnc))
    sims = [simulate(r.structure.M, r.structure.C, r.K_total, DISTURBANCE * n, duration)
            for r in results]
    return ChatterStudy(results, limits, normal, float(dir_deg), sims[0][0],
                        np.stack([x for _t, x in sims]))


@writes_folder()
def write_chatter_map(folder, cm: ChatterMap, label: str = "") -> list[Path]:
    """``chatter_map.csv`` (:meth:`ChatterMap.write_csv`) and ``chatter_map.png`` (heat map
    of the limit over q2, q3, ``label`` naming model and pose) in ``folder`` (created)."""
    folder = Path(folder)
    folder.mkdir(parents=True, exist_ok=True)
    return [cm.write_csv(folder / "chatter_map.csv"),
            plot_chatter_map(cm, folder / "chatter_map.png", label)]
