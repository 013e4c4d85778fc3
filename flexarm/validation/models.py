"""The models a validation run works with: the E-model that is compared or diagnosed and,
for the link-flexibility candidate, a coarse flexible model of the same robot.

The flexible model is only a candidate's reference (links ``c`` times as compliant as
the CAD), so a coarse mesh is enough and it is built once, then read from the
superelement cache.  With it, the E-model takes its link masses from the same tet
meshes: the flexible model's rigid-link limit is then exactly that E-model, and the
candidate's signature is link bending alone, not a mass-property difference.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

from ..assembly.arm import ArmSpec, build_arm, check_mass_method
from ..assembly.system import ArmModel
from ..fe.typing import PathType
from ..robot.description import Robot
from ..robot.effects import Effect
from ..robot.loader import load_robot

__all__ = ["ValidationOptions", "DEFAULT_OPTIONS", "ValidationModels", "validation_models", "load"]

#: Models a validation run compares or diagnoses.
_MODELS = ("emodel", "guyan", "cb")


@dataclass(frozen=True)
class ValidationOptions:
    """Which models a validation run uses.

    Parameters
    ----------
    mass : {"surface", "tets"}
        E-model link mass properties without a flexible model (see
        :class:`~flexarm.assembly.arm.ArmSpec`).
    model : {"emodel", "guyan", "cb"}
        The model compared with or diagnosed on the measurements: rigid links, or links
        reduced by Guyan or Craig-Bampton (``mesh_size``, ``n_modes``, ``coupling`` as
        in :class:`~flexarm.assembly.arm.ArmSpec`).  The full-FE model is not offered:
        a diagnosis evaluates its model thousands of times.
    flexible : bool
        Also build the coarse flexible model (the link-flexibility candidate); the
        E-model then takes its masses from the same tet meshes.
    flex_mesh : float
        Tet edge of that flexible model [m].
    flex_modes : int
        Its Craig-Bampton modes per link.
    """

    mass: str = "surface"
    flexible: bool = False
    flex_mesh: float = 0.06
    flex_modes: int = 4
    model: str = "emodel"
    mesh_size: float | None = None
    n_modes: int | None = None
    coupling: str = "rbe2"

    def __post_init__(self) -> None:
        check_mass_method(self.mass)
        if self.model not in _MODELS:
            raise ValueError(f"a validation run works on the {', '.join(_MODELS)} model, got "
                             f"'{self.model}' (the full-FE model would be solved thousands of "
                             "times; compare-models gives its difference from cb)")
        if self.flexible and self.model != "emodel":
            raise ValueError("the link-flexibility candidate turns rigid links flexible: it "
                             f"needs the E-model, and the {self.model} model has flexible links")


#: The options of the commands' defaults: E-model from the CAD surfaces, no flexible model.
DEFAULT_OPTIONS = ValidationOptions()


@dataclass(frozen=True, eq=False)
class ValidationModels:
    """The models of one robot a validation run works with.

    Attributes
    ----------
    robot : Robot
        The robot description; its ``effects`` (the robot file's ``[nonlinear]`` table)
        belong to the model.
    arm : ArmModel
        The model compared with or diagnosed on the measurements (the E-model unless
        the options name a flexible one).
    flexible : ArmModel or None
        The coarse flexible model of the link-flexibility candidate (None: not built).
    flex_mesh : float or None
        Its tet edge [m].
    """

    robot: Robot
    arm: ArmModel
    flexible: ArmModel | None = None
    flex_mesh: float | None = None

    def effects_with_links(self) -> list[Effect]:
        """The effects of the model compared with measurements: the robot's own, plus
        link flexibility at the CAD's compliance (``links:c=1``) when the flexible model
        was built and the robot names none (asking for it means flexible links)."""
        effects = list(self.robot.effects)
        if self.flexible is None or any(e.kind == "links" for e in effects):
            return effects
        return effects + [Effect("links", None, (("compliance", 1.0),))]


def load(robot: Robot | PathType | None) -> Robot:
    """``robot`` itself, or the robot of a ``.toml``/``.urdf`` file (None: the demo arm)."""
    return robot if isinstance(robot, Robot) else load_robot(robot)


def validation_models(robot: Robot | PathType | None = None,
                      options: ValidationOptions = DEFAULT_OPTIONS,
                      progress: Callable[[str], None] | None = None) -> ValidationModels:
    """The E-model of ``robot`` and, with ``options.flexible``, its coarse flexible model
    (meshed and reduced on the first run, then from the cache; ``progress`` gets a line
    per step).

    Examples
    --------
    >>> models = validation_models()
    >>> models.arm.chain.n_joints, models.flexible is None, models.effects_with_links()
    (6, True, [])
    """
    robot = load(robot)
    if not options.flexible:
        spec = ArmSpec(options.model, options.mass, options.mesh_size, options.n_modes,
                       options.coupling)
        return ValidationModels(robot, build_arm(robot, spec, progress).model)
    if progress is not None:
        progress(f"flexible model (mesh {options.flex_mesh} m, cached after the first run)")
    flexible = build_arm(robot, ArmSpec("cb", mesh_size=options.flex_mesh,
                                        n_modes=options.flex_modes), progress)
    arm = build_arm(robot, ArmSpec("emodel", "tets", options.flex_mesh))
    return ValidationModels(robot, arm.model, flexible.model, float(options.flex_mesh))
