"""The loaded circle test (LDBB) as one job: RAPID path, arm models, prediction, overlay.

:func:`run_circle` solves the IK along a procedure of a RAPID module, builds each arm
model (:func:`~flexarm.assembly.arm.build_arm`) with the robot's joint effects and any
extra ones, predicts the load-point deviation under the bar forces
(:func:`~flexarm.studies.contact.ball_bar.predict_circle`, nonlinear when an effect has
a law) and reads a measured run to overlay.  :class:`CircleResult` prints the summary
(:meth:`~CircleResult.text`) and writes the CSV and the plots (:meth:`~CircleResult.write`).
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass, replace
from importlib.resources import files
from os import PathLike
from pathlib import Path

import numpy as np

from ...assembly.arm import ArmSpec, build_arm
from ...assembly.effects import apply_effects
from ...fe.files import writes_folder
from ...fe.typing import ArrayLike, FloatArray
from ...robot.formats.rapid import read_rapid
from ...validation import PathData, StaticData, read_measurements
from ...validation.tolerances import tol as data_tol
from .ball_bar import (
    CirclePrediction,
    CircleSetup,
    circle_offsets,
    measured_deviation,
    predict_circle,
    rapid_circle,
)
from .circle_data import static_circle_readings, write_circle_csv
from .circle_models import nonlinear_solver
from .plots import plot_circle_polar, plot_circle_top, plot_circle_z

__all__ = ["THESIS_RAPID", "CircleRun", "CircleResult", "run_circle"]

#: The thesis's appendix-B module (Path_10 ... Path_60).
THESIS_RAPID = files("flexarm") / "data" / "rapid" / "ldbb_thesis.mod"


@dataclass(frozen=True, eq=False)
class CircleRun:
    """The prediction of one arm model.

    Attributes
    ----------
    label : str
        ``E-model``, ``CB`` or ``Guyan``.
    prediction : CirclePrediction
    law_joints : tuple of int
        Joints (0-based) with a nonlinear law (backlash, hardening, hysteresis).
    """

    label: str
    prediction: CirclePrediction
    law_joints: tuple[int, ...] = ()

    def lines(self) -> list[str]:
        """Header and one line per bar force: largest bar and normal deviation [mm]."""
        p = self.prediction
        laws = ", laws on joints " + ",".join(str(j + 1) for j in self.law_joints)
        lines = [f"{self.label} ({p.method}{laws if self.law_joints else ''}):"]
        ang = np.degrees(p.setup.angles)
        for F, b, z in zip(p.loads, p.bar, p.normal, strict=True):
            k = int(np.argmax(np.abs(b)))
            lines.append(f"  {F:6.0f} N: max |bar| {np.abs(b).max() * 1e3:.4f} mm at "
                         f"{ang[k]:7.1f} deg, max |normal| {np.abs(z).max() * 1e3:.4f} mm")
        return lines


@dataclass(frozen=True, eq=False)
class CircleResult:
    """A loaded circle test: the setup, one prediction per arm model, a measured overlay.

    Attributes
    ----------
    setup : CircleSetup
        Path, IK, pivot and fitted circle; ``setup.name`` is the RAPID procedure.
    tool : str
        Load point: ``"tool0"`` (flange) or ``"robot"`` (the robot's TCP).
    runs : tuple of CircleRun
        One per model, the first drawn solid, the others dashed.
    measured : tuple of 4 arrays or None
        (angle [rad], bar [m], normal [m], force [N]) of the measured readings
        (:func:`~flexarm.studies.contact.ball_bar.measured_deviation`).
    """

    setup: CircleSetup
    tool: str
    runs: tuple[CircleRun, ...]
    measured: tuple[FloatArray, FloatArray, FloatArray, FloatArray] | None = None

    def text(self) -> str:
        """The summary the ``circle`` command prints (mm, deg, N)."""
        s, conf = self.setup, self.setup.ik.is_conf_met
        lines = [f"{s.name}: {len(s.points)} samples, load point {self.tool}, pivot "
                 f"{np.round(s.pivot * 1e3, 3).tolist()} mm, bar {s.bar_length.mean() * 1e3:.3f}"
                 f" mm, circle R {s.radius * 1e3:.3f} mm; conf met at "
                 f"{int(conf.sum())}/{len(conf)} targets"]
        lines += [f"  note: {note}" for note in s.ik.notes]
        for run in self.runs:
            lines += run.lines()
        if self.measured is not None:
            _ang, bar, _nrm, force = self.measured
            lines.append(f"measured: {len(force)} readings at {np.unique(force).tolist()} N, "
                         f"max |bar| {np.abs(bar).max() * 1e3:.4f} mm")
        return "\n".join(lines)

    @writes_folder()
    def write(self, folder) -> list[Path]:
        """``circle_<procedure>.csv`` (:func:`~flexarm.studies.contact.circle_data.
        write_circle_csv`), ``circle_top.png``, ``circle_polar.png`` and ``circle_z.png``
        in ``folder`` (created)."""
        folder = Path(folder)
        folder.mkdir(parents=True, exist_ok=True)
        pairs = [(r.label, r.prediction) for r in self.runs]
        csv = write_circle_csv(folder / f"circle_{self.setup.name}.csv", pairs)
        (label, pred), rest = pairs[0], pairs[1:]
        kw = {"label": label if rest else "", "compare": rest}
        return [csv, plot_circle_top(pred, folder / "circle_top.png", **kw),
                plot_circle_polar(pred, folder / "circle_polar.png", self.measured, **kw),
                plot_circle_z(pred, folder / "circle_z.png", self.measured, **kw)]


def _measured(setup: CircleSetup, chain, measured):
    """(angle, bar, normal, force) of a path or static-schema file (or its data), whose
    readings must lie near the programmed circle (:func:`_check_on_path`)."""
    is_file = isinstance(measured, str | PathLike)
    data = read_measurements(measured) if is_file else measured
    source = str(measured) if is_file else "measured circle"
    if isinstance(data, PathData):
        _check_on_path(setup, data.points, source, lambda k: f"step {data.steps[k]}")
        return measured_deviation(setup, data.points, data.force)
    if isinstance(data, StaticData):
        points, force, rows = static_circle_readings(setup, chain, data, rows=True)
        _check_on_path(setup, points, source, lambda k: (
            f"series '{data.series[rows[k]]}', step {data.steps[rows[k]]}"))
        return measured_deviation(setup, points, force)
    raise ValueError(f"measured circle: got {type(data).__name__}; give a path CSV (step, x_mm, "
                     "y_mm, z_mm, f_N) or a static CSV (series, step, q1_deg.., fx_N.., dx_mm..)")


def _check_on_path(setup: CircleSetup, points, source: str, where) -> None:
    """Refuse readings farther than ``path_max_offset`` from the programmed circle,
    naming the farthest (``where(k)``) and its distance: a run of another circle, or a
    typo, would otherwise be overlaid as a deviation."""
    offsets = circle_offsets(setup, points)
    k = int(np.argmax(offsets)) if len(offsets) else 0
    if len(offsets) and not offsets[k] <= data_tol.path_max_offset:
        p = np.asarray(points[k]) * 1e3
        c = setup.centre * 1e3
        raise ValueError(
            f"{source}, {where(k)}: the reading ({p[0]:.1f}, {p[1]:.1f}, {p[2]:.1f}) mm lies "
            f"{offsets[k] * 1e3:.1f} mm from the programmed circle {setup.name} (centre "
            f"({c[0]:.1f}, {c[1]:.1f}, {c[2]:.1f}) mm, radius {setup.radius * 1e3:.1f} mm; at "
            f"most {data_tol.path_max_offset * 1e3:g} mm): measured on another path, or a "
            "typo?")


def run_circle(robot, effects: Sequence = (), models: Sequence[str] = ("emodel",),
               rapid=None, proc: str = "Path_30",
               loads: ArrayLike = (0.0, 200.0, 400.0, 800.0), pull: bool = False,
               pivot: ArrayLike | None = None, tool: str = "tool0", step: float = 2.0,
               measured=None, spec: ArmSpec = ArmSpec(),  # noqa: B008 (frozen dataclass)
               progress: Callable[[str], None] | None = None) -> CircleResult:
    """Loaded circle test of ``robot`` along RAPID procedure ``proc``.

    Parameters
    ----------
    robot : Robot
    effects : sequence of Effect
        Joint effects on top of ``robot.effects`` (its ``[nonlinear]`` table), e.g. from
        :func:`~flexarm.robot.effects.parse_effect`.
    models : sequence of {"emodel", "cb", "guyan"}
        Arm models to predict with, the first drawn solid.
    rapid : path, optional
        RAPID module (default: the thesis's appendix B, :data:`THESIS_RAPID`).
    proc : str
        Procedure of the module.
    loads : (k,) float
        Bar forces [N] (>= 0).
    pull : bool
        The bar pulls (default: pushes).
    pivot : (3,) float, optional
        Bar pivot [m] (default: fitted to the module's circles).
    tool : {"tool0", "robot"}
        Load point: the flange (as programmed) or the robot's TCP.
    step : float
        Path sampling step [mm].
    measured : path, PathData or StaticData, optional
        Measured run to overlay: a path CSV or a circle run in the static schema
        (:mod:`~flexarm.studies.contact.circle_data`).
    spec : ArmSpec
        Mass method, mesh size, modes and coupling of the models (its ``model`` is
        replaced by each of ``models``).
    progress : callable, optional
        Receives progress lines of flexible-link builds.

    Returns
    -------
    CircleResult

    Examples
    --------
    >>> from flexarm.robot import load_robot
    >>> res = run_circle(load_robot(), loads=[0.0, 800.0], step=20.0)
    >>> print(res.text().splitlines()[-1])
         800 N: max |bar| 2.6199 mm at   -90.0 deg, max |normal| 0.0621 mm
    """
    mod = read_rapid(THESIS_RAPID if rapid is None else rapid)
    if proc not in mod.procedures:
        raise ValueError(f"no procedure {proc} (module has {sorted(mod.procedures)})")
    setup = rapid_circle(robot, mod, proc, pivot, tool, step)
    meas = None if measured is None else _measured(setup, robot.chain, measured)
    effects = [*robot.effects, *effects]
    F = np.asarray(loads, dtype=float)
    runs = []
    for name in models:
        arm = build_arm(robot, replace(spec, model=name), progress=progress)
        model, laws = apply_effects(arm.model, effects)
        pred = predict_circle(model, setup, F, pull, nonlinear_solver(laws))
        runs.append(CircleRun(arm.spec.label, pred, tuple(sorted(laws))))
    return CircleResult(setup, tool, tuple(runs), meas)
