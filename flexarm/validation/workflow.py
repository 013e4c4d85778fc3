"""The measurement workflows behind the ``compare`` and ``diagnose`` commands: one call
from a measurement file and a robot to a result with ``text()`` and writers.

Noise options keep the commands' units (tracker noise in µm, frequency noise in %) so
that a command passes its options through unchanged.  The virtual lab is
:func:`~flexarm.validation.lab.virtual_lab.run_lab`.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ..fe.typing import PathType
from ..robot.description import Robot, check_limits
from ..robot.formats import write as write_robot_file
from .data.formats import UffOptions, read_measurements
from .data.formats.csv_frf import check_lines
from .data.measurements import FrfData, ModalData, PathData, StaticData
from .data.shape_data import ShapeData
from .diagnosis.history import robot_with_effects, write_history
from .diagnosis.search import Diagnosis, diagnose
from .dynamic.compare import FrfComparison, ModalComparison, compare_frf, compare_modal
from .dynamic.compare_shapes import compare_with_models, measurement_points, shape_builds
from .dynamic.damping_check import DampingDiagnosis, diagnose_damping
from .dynamic.shape_fit import SHAPE_NOISE
from .models import DEFAULT_OPTIONS, ValidationModels, ValidationOptions, load, validation_models
from .static.compare import Comparison, compare_static

__all__ = ["compare", "DiagnosisRun", "run_diagnosis"]

Measurements = StaticData | ModalData | FrfData | PathData


def _read(data: Measurements | PathType, robot: Robot | None = None,
          uff: UffOptions | None = None) -> Measurements:
    """``data`` as read; its joint angles are checked against ``robot``'s limits (a
    file's by the reader, naming file, line and column)."""
    if isinstance(data, Measurements):
        _check_limits(data, robot)
        return data
    limits = None
    if robot is not None and len(robot.joints) == 6:  # the schemas carry q1..q6
        limits = np.column_stack([robot.lower, robot.upper])
    return read_measurements(data, limits=limits, uff=uff)


def _check_limits(data: Measurements, robot: Robot | None) -> None:
    """Raise ``ValueError`` naming the first reading, its series or pose, and the joint
    whose angle lies outside ``robot``'s limits (as a file's reader does)."""
    q = getattr(data, "q", None)
    if robot is None or q is None or np.shape(q)[1:] != (len(robot.joints),):
        return
    bad = np.flatnonzero(np.any(~np.isfinite(q) | (q < robot.lower) | (q > robot.upper),
                                axis=1))
    if bad.size:
        i = int(bad[0])
        labels = getattr(data, "series", getattr(data, "poses", None))
        owner = "" if labels is None else f" of '{labels[i]}'"
        check_limits(robot, q[i], f"{type(data).__name__} reading {i + 1}{owner}")


def compare(data: Measurements | PathType, robot: Robot | PathType | None = None,
            options: ValidationOptions = DEFAULT_OPTIONS, *, noise_um: float = 15.0,
            freq_noise_pct: float = 0.5, progress: Callable[[str], None] | None = None,
            pose: str | None = None, response: str | None = None, tcp_node: int | None = None
            ) -> Comparison | ModalComparison | FrfComparison:
    """Compare the model of ``robot`` with measurements of any kind.

    Parameters
    ----------
    data : StaticData, ModalData, FrfData or path
        The measurements, or their CSV file (the kind is recognised by the columns).
    robot : Robot, path or None
        The robot or its file (None: the demo arm); its ``[nonlinear]`` effects are
        part of the model, and so is link flexibility when ``options.flexible``.
    options : ValidationOptions
        Models of :func:`~flexarm.validation.models.validation_models`.
    noise_um : float
        Tracker noise [µm] of static rows without a ``sigma`` column.
    freq_noise_pct : float
        Relative noise of measured natural frequencies [%].
    progress : callable (str) -> None, optional
        Gets a line per step of a flexible-model build.
    pose, response, tcp_node
        What a universal file from another tool does not say: the pose it was measured
        at (a pose name or ``q1,...,q6`` [deg]), what a general ordinate is, the TCP node
        (:meth:`~.data.formats.uff.UffOptions.at`).

    Returns
    -------
    Comparison, ModalComparison or FrfComparison
        By the kind of ``data`` (:func:`~.compare.compare_static`,
        :func:`~.dynamic.compare.compare_modal`, :func:`~.dynamic.compare.compare_frf`);
        each has ``text()`` and ``write(folder)``.

    Examples
    --------
    >>> from flexarm.validation import example_path
    >>> cmp = compare(example_path("frf"))
    >>> [(r.pose, r.input, r.output) for r in cmp.table]
    [('c1', 'y', 'y'), ('c1', 'y', 'x')]
    """
    robot = load(robot)
    uff = UffOptions.at(robot, pose, response, tcp_node)
    data_path, data = (None if isinstance(data, Measurements) else data), _read(data, robot, uff)
    if isinstance(data, FrfData):  # a peak needs lines around it: no "0.000 %" from one
        check_lines(data, data_path)
    models = validation_models(robot, options, progress)
    effects = models.effects_with_links()
    if isinstance(data, ShapeData):  # mode shapes: pairing by MAC
        return compare_with_models(models, options, data, data_path)
    if isinstance(data, ModalData):
        return compare_modal(models.arm, data, effects, freq_noise_pct / 100, models.flexible)
    if isinstance(data, FrfData):
        return compare_frf(models.arm, data, effects, models.flexible, robot)
    if isinstance(data, StaticData):
        return compare_static(models.arm, data, effects, noise_um * 1e-6, models.flexible)
    raise ValueError(f"cannot compare a model with {type(data).__name__} (static, modal or "
                     "FRF data only)")


@dataclass(frozen=True, eq=False)
class DiagnosisRun:
    """A diagnosis (:func:`run_diagnosis`) with the models it ran on.

    Attributes
    ----------
    diagnosis : Diagnosis
        Steps, identifiability, accepted effects (SI parameters), notes.
    models : ValidationModels
        The robot, the diagnosed E-model and the flexible model (if any).
    sigma : float or None
        The stated tracker noise [m] (mean over the readings): the noise floor of the
        history picture.
    damping : DampingDiagnosis or None
        Joints missing damping, judged by the modal data's damping ratios (when given).
    what : str
        The robot, model and measured poses, for the history picture's title.
    """

    diagnosis: Diagnosis
    models: ValidationModels
    sigma: float | None = None
    damping: DampingDiagnosis | None = None
    what: str = ""

    def text(self) -> str:
        """The diagnosis as ``diagnose`` prints it (then the damping check, if any)."""
        text = self.diagnosis.text()
        return text if self.damping is None else text + "\n" + self.damping.text()

    def updated_robot(self) -> Robot:
        """The robot with the final model's effects and fitted parameters
        (:func:`~.history.robot_with_effects`)."""
        return robot_with_effects(self.models.robot, self.models.arm,
                                  self.diagnosis.final_effects)

    def write_history(self, folder: PathType) -> list[Path]:
        """``history.csv``, ``history.json`` and ``history.png`` of the model versions
        (:func:`~.history.write_history`)."""
        return write_history(folder, self.diagnosis, sigma=self.sigma, what=self.what)

    def write_robot(self, path: PathType, force: bool = False) -> Path:
        """:meth:`updated_robot` as a robot file (``.toml``), atomically.

        Refuses (``ValueError``, nothing written) when the diagnosis ends with an
        unexplained misfit, unless ``force``: the accepted effects would then tell a
        physical story the data do not support."""
        if self.diagnosis.unexplained and not force:
            raise ValueError(f"not writing {path}: the diagnosis ends with an unexplained "
                             f"misfit ({', '.join(self.diagnosis.misfit.structures)}); "
                             f"--force writes it anyway")
        return Path(write_robot_file(path, self.updated_robot()))


def run_diagnosis(data: StaticData | PathType, robot: Robot | PathType | None = None,
                  options: ValidationOptions = DEFAULT_OPTIONS, *, noise_um: float = 15.0,
                  noise_model: str = "shared", modal: ModalData | PathType | None = None,
                  freq_noise_pct: float = 0.5, damping_noise_pct: float = 5.0,
                  progress: Callable[[str], None] | None = None,
                  shape_noise_pct: float = 100 * SHAPE_NOISE, pose: str | None = None,
                  response: str | None = None) -> DiagnosisRun:
    """Diagnose which effects the E-model of ``robot`` misses in static ``data``
    (:func:`~.diagnosis.search.diagnose`).

    Parameters
    ----------
    data : StaticData or path
        Static measurements, or their CSV file.
    robot : Robot, path or None
        A linear robot (no ``[nonlinear]`` table) or its file (None: the demo arm).
    options : ValidationOptions
        Models; with ``options.flexible`` link flexibility is a candidate (the E-model
        needs no seats, so modal data alone do not build the flexible model).
    noise_um : float
        Tracker noise [µm] of rows without a ``sigma`` column.
    noise_model : {"shared", "independent"}
        Shared reference reading (GLS) or independent rows.
    modal : ModalData, path or None
        Measured natural frequencies, joining every fit; with damping ratios, also the
        check for joints missing damping (:func:`~.damping_check.diagnose_damping`).
    freq_noise_pct : float
        Their relative noise [%].
    damping_noise_pct : float
        Relative scatter of an identified damping ratio [%].
    shape_noise_pct : float
        Scatter of a measured shape entry, in % of the shape's largest entry: modal data
        with shapes are paired with the model's modes by MAC and their shapes join
        every fit (:class:`~.shape_fit.ShapeProblem`; points from
        :func:`~.compare_shapes.measurement_points`).
    progress : callable (str) -> None, optional
        Gets a line per step of a flexible-model build.
    pose, response
        The pose a universal ``modal`` file from another tool was measured at, and what
        its general ordinates are (:meth:`~.data.formats.uff.UffOptions.at`).
    """
    robot = load(robot)
    if robot.effects:
        raise ValueError("diagnose starts from a linear model: the robot file already has "
                         "a [nonlinear] table")
    data = _read(data, robot)
    modal_path = None if modal is None or isinstance(modal, Measurements) else modal
    modal = None if modal is None else _read(modal, robot, UffOptions.at(robot, pose, response))
    damping = _damping_check(modal, robot, options, damping_noise_pct)
    models = validation_models(robot, options, progress)
    shapes = {}
    if isinstance(modal, ShapeData):
        shapes = dict(points=measurement_points(modal_path, robot, modal.nodes,
                                                (str(modal.poses[0]), modal.q[0])),
                      shape_noise=shape_noise_pct / 100, builds=shape_builds(models, options))
    dg = diagnose(models.arm, data, noise_um * 1e-6, noise_model, poses=robot.poses,
                  modal=modal, flexible=models.flexible, freq_noise=freq_noise_pct / 100,
                  **shapes)
    sigma = data.sigma if getattr(data, "sigma", None) is not None else None
    poses = ", ".join(sorted({str(s).split("_")[0] for s in data.series}))
    label = {"emodel": "E-model", "guyan": "Guyan arm", "cb": "CB arm"}.get(options.model,
                                                                         options.model)
    extra = "" if modal is None else f" (+ {len(modal.freq_hz)} measured modes)"
    what = f"{robot.name} {label} at {poses}{extra}"
    return DiagnosisRun(dg, models, noise_um * 1e-6 if sigma is None else float(np.mean(sigma)),
                        damping, what)


def _damping_check(modal, robot: Robot, options: ValidationOptions, noise_pct: float):
    """The missing-damper check of modal data that carry damping ratios, else None."""
    ratios = None if modal is None else getattr(modal, "damping_ratio", None)
    if ratios is None or not np.all(np.isfinite(ratios)) or not np.any(ratios > 0):
        return None
    return diagnose_damping(modal, robot, sigma_rel=noise_pct / 100, options=options)
