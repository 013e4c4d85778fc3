"""Virtual lab: static load-deflection series from a model plus hidden effects and noise.

The lab reproduces the thesis's LDBB + laser-tracker procedure (chapter 3.4): at each
pose and load direction a series of readings at increasing load (optionally loading
then unloading); the tracker measures the TCP position with independent noise at each
reading, and the file holds the displacement relative to the series' first reading, so
the *reference reading's* noise is shared by every row of its series.  The truth
(effects, stiffness errors, seed) goes to a separate JSON file that ``diagnose``
never reads.
"""

from __future__ import annotations

import json
import logging
from collections.abc import Callable, Sequence
from dataclasses import astuple, dataclass, replace
from pathlib import Path

import numpy as np

from ...assembly.effects import ADDED, added_deflection, apply_effects, measured
from ...assembly.linkflex import links_arm, split_links
from ...assembly.statics import joint_moments, relative_deflection
from ...assembly.system import ArmModel
from ...fe.files import atomic_files
from ...fe.quantities import Quantity
from ...fe.typing import ArrayLike, PathType
from ...robot.description import Robot, pose_from_string
from ...robot.effects import Effect, parse_effect
from ..data.formats import write_modal, write_static
from ..data.formats.csv_points import write_points
from ..data.formats.uff import EXTENSIONS as UFF_EXTENSIONS
from ..data.formats.uff_geometry import PoseGeometry, stick_figure
from ..data.formats.uff_write import write_uff
from ..data.load_plan import LabPlan, parse_dirs, parse_loads
from ..data.measurements import ModalData, StaticData
from ..data.shape_data import Points, ShapeData
from ..dynamic.compare_shapes import shape_builds
from ..models import DEFAULT_OPTIONS, ValidationOptions, load, validation_models
from ..tolerances import tol
from .modal_lab import virtual_frfs, virtual_modal, virtual_shapes

__all__ = ["virtual_lab", "write_lab", "LabFiles",
           "LabResult", "run_lab", "lab_shapes", "lab_poses"]

log = logging.getLogger(__name__)

def virtual_lab(arm: ArmModel, plan: LabPlan, effects: list[Effect] = (), noise: float = 15e-6,
                seed: int = 0, flexible: ArmModel | None = None,
                ref_noise: float = 0.0) -> StaticData:
    """Measured-like static data of ``arm`` with hidden ``effects`` and tracker ``noise`` [m].

    ``ref_noise`` [m] adds an extra error to each series' reference reading only (the
    tracker re-locked on the reflector, or a reference averaged over a shorter window);
    it is shared by every row of the series, like the reference's ordinary noise.

    A ``links`` effect (link flexibility) needs ``flexible``, the robot's flexible model.

    Examples
    --------
    >>> from flexarm.assembly.emodel import emodel
    >>> from flexarm.robot.demo_arm import load_demo_robot
    >>> robot = load_demo_robot()
    >>> arm = emodel(robot, method="surface")
    >>> plan = LabPlan({"P1": robot.pose("P1")}, np.array([0.0, 100.0]), parse_dirs("z"))
    >>> virtual_lab(arm, plan, noise=0.0).disp.shape
    (2, 3)
    """
    series, steps, q, force = plan.rows()
    c, rest = split_links(effects)
    truth, laws = apply_effects(links_arm(arm, flexible, c), rest)
    u = relative_deflection(truth, q, force, None, series, laws)
    rng = np.random.default_rng(seed)
    e = noise * rng.standard_normal(u.shape)
    labels = np.array(series)
    ref = np.flatnonzero(np.r_[True, labels[1:] != labels[:-1]])
    start = ref[np.cumsum(np.r_[True, labels[1:] != labels[:-1]]) - 1]
    if any(x.kind in ADDED for x in rest):
        tau = joint_moments(arm, q, force)[:, :, 0]
        u = u + added_deflection(truth, rest, q, force - force[start], tau - tau[start])
    u = measured(rest, u)
    if ref_noise > 0:
        e[ref] += ref_noise * rng.standard_normal((len(ref), 3))
    disp = u + e - e[start]
    disp[ref] = 0.0
    sigma = np.full(len(u), noise)
    sigma[ref] = np.hypot(noise, ref_noise)  # the file states the reference's uncertainty
    log.info("virtual lab: %d readings in %d series, %d effects", len(u), len(ref), len(effects))
    return StaticData(series=series, steps=steps, q=q, force=force, disp=disp,
                      sigma=sigma if noise > 0 else None)


#: First comment line of every file the lab writes.
_COMMENT = "virtual lab data (flexarm lab)"


def write_lab(path, data: StaticData, truth: dict) -> tuple[Path, Path]:
    """Write the data file and ``<stem>.truth.json`` next to it, both or neither
    (:func:`~flexarm.fe.files.atomic_files`); returns both paths."""
    path = Path(path)
    tpath = path.with_suffix(".truth.json")
    with atomic_files(path, tpath) as (tmp, ttmp):
        _write_lab(tmp, ttmp, data, truth)
    return path, tpath


def _write_lab(path: Path, tpath: Path, data: StaticData, truth: dict) -> None:
    write_static(path, data, comments=(_COMMENT,))
    tpath.write_text(json.dumps(truth, indent=2, sort_keys=True))


#: Tracker noise and reference error [m] (``"15um"`` with a unit; a bare number is metres).
_NOISE = Quantity("length", "m", 0, 0.01)


@dataclass(frozen=True)
class LabFiles:
    """Paths :meth:`LabResult.write` wrote: static CSV, its truth JSON, modal CSV or
    universal file (or None) and, with a universal file, its points table."""

    static: Path
    truth: Path
    modal: Path | None = None
    points: Path | None = None


@dataclass(frozen=True, eq=False)
class LabResult:
    """A virtual lab run (:func:`run_lab`).

    Attributes
    ----------
    data : StaticData
        The static series (SI).
    truth : dict
        What ``diagnose`` should find, as written to ``<stem>.truth.json``: ``effects``
        (:meth:`~flexarm.robot.effects.Effect.to_dict`, SI), ``noise_m`` and
        ``ref_noise_m`` [m], ``seed``, ``robot`` (its file, or ``"demo"``), and when
        used ``flexible_mesh_m`` [m] and ``freq_noise`` (relative).
    modal : ModalData or None
        Natural frequencies, when asked for.
    shapes : ShapeData or None
        With ``modal``: frequencies, damping and mode shapes at ``points``.
    frfs : tuple of UffFrf
        With ``modal``: receptances at every point per TCP force, one per pose.
    points : Points or None
        The measurement points (:func:`~flexarm.validation.dynamic.shapes.default_points`).
    geometry : tuple of PoseGeometry
        With ``modal``: the test geometry, the points in the base frame at each pose
        [m] and the stick figure through them.
    """

    data: StaticData
    truth: dict
    modal: ModalData | None = None
    shapes: ShapeData | None = None
    frfs: tuple = ()
    points: Points | None = None
    geometry: tuple = ()

    def write(self, path: PathType, modal_path: PathType | None = None) -> LabFiles:
        """The static CSV ``path`` with ``<stem>.truth.json`` next to it and, given
        ``modal_path``, the modal CSV or universal file (with its points table): every
        file or none (:func:`~flexarm.fe.files.atomic_files`; Ctrl-C or a full disk
        leave the older files as they were)."""
        path = Path(path)
        files = LabFiles(path, path.with_suffix(".truth.json"))
        if modal_path is not None:
            if self.modal is None:
                raise ValueError("this lab run has no modal data: run it with modal=True")
            modal_path = Path(modal_path)
            is_uff = modal_path.suffix.lower() in UFF_EXTENSIONS
            if is_uff and self.shapes is None:
                raise ValueError("this lab run has no mode shapes: run it with modal=True")
            files = replace(files, modal=modal_path,
                            points=modal_path.with_suffix(".points.csv") if is_uff else None)
        with atomic_files(*[p for p in astuple(files) if p is not None]) as tmps:
            tmp = LabFiles(*tmps)  # the files asked for come first, in field order
            if tmp.points is not None:
                self._write_uff(tmp.modal, tmp.points, files.modal.name)
            elif tmp.modal is not None:
                write_modal(tmp.modal, self.modal, (_COMMENT,))
            _write_lab(tmp.static, tmp.truth, self.data, self.truth)
        return files

    def _write_uff(self, path: Path, points: Path, name: str) -> None:
        """Geometry per pose (2411, 82), mode shapes (55, mass-normalised: modal mass 1)
        and FRFs (58) as a universal file
        (:mod:`~flexarm.validation.data.formats.uff_write`), and the points table
        ``points`` of the file ``name``."""
        write_uff(path, self.shapes, self.frfs, self.geometry, modal_mass=1.0,
                  description=_COMMENT)
        write_points(points, self.points, (_COMMENT, f"measurement points of {name}"))

    def text(self, files: LabFiles) -> str:
        """What the ``lab`` command prints after writing ``files``."""
        lines = [] if files.modal is None else [
            f"wrote {files.modal} ({len(self.modal.freq_hz)} frequencies)"]
        if files.points is not None:
            lines = [f"wrote {files.modal} ({len(self.modal.freq_hz)} modes with shapes at "
                     f"{self.shapes.n_dofs} DOFs, {sum(len(f.H) for f in self.frfs)} FRFs) "
                     f"and {files.points}"]
        lines.append(f"wrote {files.static} ({len(self.data.series)} readings, "
                     f"{self.data.n_series} series) and {files.truth}")
        return "\n".join(lines)


def lab_poses(robot: Robot, poses: str | Sequence[str]) -> dict:
    """Pose label -> q [rad] of named poses (``"P1,P2"``) or of joint-angle sets in
    degrees separated by ``;`` (``"0,52,-19,12,-15,-11;0,0,66,0,-66,0"``, labelled
    ``Q1``, ``Q2``, ...), which an imported robot without named poses needs."""
    if isinstance(poses, str):
        if poses.strip()[:1] in set("0123456789+-."):  # names start with a letter
            sets = [t for t in poses.split(";") if t.strip()]
            return {f"Q{k + 1}": pose_from_string(robot, t) for k, t in enumerate(sets)}
        poses = [p.strip() for p in poses.split(",") if p.strip()]
    return {p: robot.pose(p) for p in poses}


def run_lab(robot: Robot | PathType | None = None, effects: Sequence[str | Effect] = (),
            options: ValidationOptions = DEFAULT_OPTIONS, *, noise: float | str = tol.tracker_sigma,
            poses: str | Sequence[str] = ("P1", "P2", "P3"), loads: str | ArrayLike = "0:800:100",
            dirs: str | list = "x,y,z", cycles: bool = False, seed: int = 0,
            ref_noise: float | str = 0.0, modal: bool = False, n_modes: int = 4,
            freq_noise_pct: float = 100 * tol.freq_noise,
            progress: Callable[[str], None] | None = None,
            frf_band: tuple | None = None) -> LabResult:
    """Virtual lab: static series (and natural frequencies) of ``robot``'s E-model with
    its own effects plus the hidden ``effects``, and tracker noise.

    Parameters
    ----------
    robot : Robot, path or None
        The robot or its file (None: the demo arm).
    effects : sequence of str or Effect
        Hidden effects, e.g. ``"backlash:j2=0.1mrad"``; a ``links`` effect builds the
        flexible model whatever ``options.flexible`` says.
    options : ValidationOptions
        Models of :func:`~flexarm.validation.models.validation_models`.
    noise, ref_noise : float or str
        Tracker noise and the extra error of each series' reference reading [m], or
        text like ``"15um"``.
    poses : str or sequence of str
        Named poses of the robot (``"P1,P2,P3"``), or joint-angle sets [deg] separated
        by ``;`` (see :func:`lab_poses`).
    loads : str or (k,) float
        Load levels [N], ``"0:800:100"`` (start:stop:step) or ``"0,200,400"``.
    dirs : str or list
        Load directions, ``"x,y,z,-z"`` (or the list of :func:`parse_dirs`).
    cycles : bool
        Load then unload each series.
    seed : int
        Noise seed (the modal noise uses the same).
    modal : bool
        Also give ``n_modes`` natural frequencies per pose with ``freq_noise_pct`` [%]
        relative noise.
    progress : callable (str) -> None, optional
        Gets a line per step of a flexible-model build.
    frf_band : (float, float) or None
        Band of the FRFs written with the shapes [Hz] (default: 0.25 Hz to 1.2 times the
        highest mode kept), 0.25 Hz lines.

    Examples
    --------
    >>> lab = run_lab(effects=["backlash:j2=0.1mrad"], poses="P1", loads="0:200:100",
    ...               dirs="z", noise="10um", seed=1)
    >>> lab.data.disp.shape, lab.truth["noise_m"], lab.truth["effects"][0]["kind"]
    ((3, 3), 1e-05, 'backlash')
    """
    noise = _NOISE.parse(noise, "noise")
    ref_noise = _NOISE.parse(ref_noise, "ref-noise")
    source = robot.name if isinstance(robot, Robot) else "demo" if robot is None else str(robot)
    robot = load(robot)
    effects = list(robot.effects) + [parse_effect(e, len(robot.joints)) if isinstance(e, str)
                                     else e for e in effects]
    if any(e.kind == "links" for e in effects):
        options = replace(options, flexible=True)
    models = validation_models(robot, options, progress)
    plan = LabPlan(lab_poses(robot, poses),
                   parse_loads(loads) if isinstance(loads, str) else np.asarray(loads, float),
                   parse_dirs(dirs) if isinstance(dirs, str) else list(dirs), cycles)
    data = virtual_lab(models.arm, plan, effects, noise, seed, models.flexible, ref_noise)
    truth = {"effects": [e.to_dict() for e in effects], "noise_m": noise, "seed": seed,
             "robot": source, "ref_noise_m": ref_noise}
    if models.flexible is not None:
        truth["flexible_mesh_m"] = models.flex_mesh
    if not modal:
        return LabResult(data, truth)
    truth["freq_noise"] = freq_noise_pct / 100
    modal_data = virtual_modal(models.arm, plan.poses, effects, n_modes, freq_noise_pct / 100,
                               seed, models.flexible)
    return LabResult(data, truth, modal_data,
                     **lab_shapes(models.arm, robot, plan.poses, effects, n_modes,
                                  freq_noise_pct / 100, seed, flexible=models.flexible,
                                  builds=shape_builds(models, options), band=frf_band))


def lab_shapes(arm: ArmModel, robot: Robot, poses: dict, effects, n_modes: int,
               freq_noise: float, seed: int, frf_noise: float = 0.02,
               flexible: ArmModel | None = None, builds=None,
               band: tuple | None = None) -> dict:
    """Mode shapes and FRFs of the virtual lab at the robot's default points: keyword
    arguments ``shapes``, ``frfs``, ``points``, ``geometry`` of :class:`LabResult`.

    The FRFs are receptances at every point (x, y, z) per force at the TCP along x, y
    and z, from 0.25 Hz in 0.25 Hz steps to 1.2 times the highest mode kept (or over
    ``band`` = (lo, hi) [Hz]), with ``frf_noise`` relative noise per line.  ``flexible``
    and its ``builds`` (for the recovery at the points) serve a link-flexibility effect.
    """
    from ..dynamic.point_geometry import point_coordinates
    from ..dynamic.shapes import default_points

    points = default_points(robot)
    shapes = virtual_shapes(arm, poses, points, effects, n_modes, freq_noise, 0.0, seed,
                            flexible, builds)
    lo, top = band if band is not None else (0.25, 1.2 * float(shapes.freq_hz.max()))
    if not 0 < lo < top:
        raise ValueError(f"FRF band {lo:g}:{top:g} Hz: expected 0 < LO < HI")
    freq = 0.25 * np.arange(max(int(np.ceil(lo / 0.25)), 1), int(np.ceil(top / 0.25)) + 1)
    tcp = int(points.nodes[-1])
    frfs = virtual_frfs(arm, poses, points, [(tcp, d) for d in "xyz"], freq, effects,
                        frf_noise, seed, flexible, builds)
    lines = stick_figure(points)
    geometry = tuple(PoseGeometry(label, points.nodes, point_coordinates(robot, q, points), lines)
                     for label, q in poses.items())
    return {"shapes": shapes, "frfs": tuple(frfs), "points": points, "geometry": geometry}
