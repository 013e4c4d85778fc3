"""One way from a robot description to an arm model: the E-model or the flexible arm.

:class:`ArmSpec` names the model and its few knobs, :func:`build_arm` builds it.  Every
command and job that needs "the arm of this robot" goes through here, so the defaults
are the same everywhere: E-model link masses from the CAD surfaces (exact for closed
CAD, no meshing), the robot's mesh size and Craig-Bampton mode count for flexible
links, RBE2 seats.
"""

from __future__ import annotations

import logging
import warnings
from collections.abc import Callable
from dataclasses import dataclass

from ..robot.description import Robot
from .build import BuildOptions, LinkBuild, build_robot
from .emodel import emodel
from .flexible import flexible_arm
from .full_arm import FullFEArm, full_arm
from .system import ArmModel

__all__ = ["MODELS", "MASS_METHODS", "check_mass_method", "ArmSpec", "Arm", "build_arm"]

log = logging.getLogger(__name__)

#: Arm models: rigid links (E-model), links reduced by Guyan or Craig-Bampton, or the
#: unreduced links (the full-FE reference, solved pose by pose).
MODELS = ("emodel", "guyan", "cb", "full")
#: Where E-model link mass properties come from: CAD surface integrals or tet meshes.
MASS_METHODS = ("surface", "tets")


def check_mass_method(mass: str) -> None:
    """Raise ``ValueError`` unless ``mass`` is one of :data:`MASS_METHODS`.

    Examples
    --------
    >>> check_mass_method("tets")
    >>> check_mass_method("cad")
    Traceback (most recent call last):
    ...
    ValueError: mass must be one of surface, tets, got 'cad'
    """
    if mass not in MASS_METHODS:
        raise ValueError(f"mass must be one of {', '.join(MASS_METHODS)}, got '{mass}'")


@dataclass(frozen=True)
class ArmSpec:
    """Which arm model of a robot.

    Parameters
    ----------
    model : {"emodel", "guyan", "cb", "full"}
        Rigid links with joint springs, links reduced by Guyan or Craig-Bampton, or the
        unreduced links (:class:`~flexarm.assembly.full_arm.FullFEArm`).
    mass : {"surface", "tets"}
        E-model link mass properties: closed-surface integrals of the CAD, or volume
        integrals over the link's tetrahedral mesh (the same solid as the flexible arm).
    mesh_size : float or None
        Tet edge length [m] of flexible links and of ``mass="tets"`` (None: the robot's).
    n_modes : int or None
        Craig-Bampton modes per link (None: the robot's); for ``"full"``, the arm modes
        computed per pose (None: 12).
    coupling : {"rbe2", "rbe3"}
        Seat coupling of flexible links.
    """

    model: str = "emodel"
    mass: str = "surface"
    mesh_size: float | None = None
    n_modes: int | None = None
    coupling: str = "rbe2"

    def __post_init__(self) -> None:
        if self.model not in MODELS:
            raise ValueError(f"model must be one of {', '.join(MODELS)}, got '{self.model}'")
        check_mass_method(self.mass)

    @property
    def label(self) -> str:
        """Name for titles and tables: ``E-model``, ``Guyan``, ``CB``."""
        return {"emodel": "E-model", "guyan": "Guyan", "cb": "CB", "full": "Full FE"}[self.model]

    def build_options(self) -> BuildOptions:
        """The :class:`BuildOptions` of a flexible model (Guyan seats for ``"full"``)."""
        if self.model == "full":
            return BuildOptions("guyan", 0, self.coupling, self.mesh_size)
        return BuildOptions(self.model, self.n_modes, self.coupling, self.mesh_size)


@dataclass(frozen=True, eq=False)
class Arm:
    """An arm model of ``robot``: ``model`` (an :class:`ArmModel`, or a
    :class:`~flexarm.assembly.full_arm.FullFEArm` for ``"full"``; every analysis of
    :mod:`~flexarm.assembly.analyses` takes either), the ``spec`` it was built from and
    the link ``builds`` (None for the E-model and the full-FE arm)."""

    robot: Robot
    model: ArmModel | FullFEArm
    spec: ArmSpec
    builds: tuple[LinkBuild, ...] | None = None


def build_arm(robot: Robot, spec: ArmSpec = ArmSpec(),
              progress: Callable[[str], None] | None = None) -> Arm:
    """The arm model ``spec`` of ``robot`` (flexible links are meshed and reduced once,
    then read from the cache).  A robot with placeholder joint stiffness (a URDF import)
    gets one warning naming those joints.

    Examples
    --------
    >>> from flexarm.robot.demo_arm import load_demo_robot
    >>> arm = build_arm(load_demo_robot())
    >>> arm.spec.label, arm.model.chain.n_joints
    ('E-model', 6)
    """
    log.info("arm of %s: %s", robot.name, spec)
    placeholders = [j.name for j in robot.joints if j.model.is_placeholder]
    if placeholders:  # the arm's answers are only as good as these unmeasured defaults
        which = (f"joints {', '.join(placeholders)} have" if len(placeholders) > 1
                 else f"joint {placeholders[0]} has")
        warnings.warn(f"robot '{robot.name}': {which} placeholder stiffness (not measured); "
                      "identify it with `flexarm diagnose DATA.csv --robot ROBOT.toml --apply "
                      "-o NEW.toml`", stacklevel=2)
    if spec.model == "emodel":
        size = robot.options.mesh_size if spec.mesh_size is None else float(spec.mesh_size)
        return Arm(robot, emodel(robot, method=spec.mass, mesh_size=size), spec)
    opts = spec.build_options().resolved(robot)
    if spec.model == "full":
        return Arm(robot, full_arm(robot, opts, spec.n_modes or 12, progress), spec)
    builds = build_robot(robot, opts, progress=progress)
    return Arm(robot, flexible_arm(robot, opts, builds), spec, builds)
