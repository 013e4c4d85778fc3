"""The robot description (DESIGN §5) as frozen dataclasses, with validation.

Angles are radians and lengths metres inside; the TOML reader/writer
(:mod:`flexarm.robot.formats.toml`) converts degrees at the edge.  Validation
errors name the offending key and value.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from functools import cached_property
from pathlib import Path

import numpy as np

from ..fe.material import Material
from ..fe.typing import FloatArray
from .joints import JointModel
from .kinematics import Chain, rpy_matrix

__all__ = [
    "LumpedMass",
    "Region",
    "Link",
    "Joint",
    "BaseSupport",
    "Tool",
    "ModelOptions",
    "Robot",
    "pose_from_string",
    "check_limits",
]

@dataclass(frozen=True)
class LumpedMass:
    """A concentrated mass (motor, gearbox) rigidly fixed to a link.

    ``position`` [m] in the link frame; ``inertia`` (3, 3) [kg m^2] about its own centre.
    """

    name: str
    mass: float
    position: tuple
    inertia: tuple = ((0.0, 0.0, 0.0), (0.0, 0.0, 0.0), (0.0, 0.0, 0.0))


@dataclass(frozen=True)
class Region:
    """Cylindrical interface region (DESIGN §6) in the link frame.

    FE nodes with radial distance in ``[r_min, r_max]`` [m] from the axis through
    ``center`` and axial distance ``<= half_width`` [m] are selected; ``coupling``
    is ``"rbe2"`` or ``"rbe3"``.
    """

    center: tuple
    axis: tuple
    r_min: float
    r_max: float
    half_width: float
    coupling: str = "rbe2"

    def contains(self, points) -> np.ndarray:
        """(n,) bool: which ``points`` (n, 3) [m] lie in the region."""
        p = np.asarray(points, dtype=float) - np.asarray(self.center)
        a = np.asarray(self.axis, dtype=float)
        t = p @ a
        r = np.linalg.norm(p - t[:, None] * a, axis=1)
        return (np.abs(t) <= self.half_width) & (r >= self.r_min) & (r <= self.r_max)


@dataclass(frozen=True)
class Link:
    """One link: its CAD, material, lumped masses and interface regions.

    ``mesh`` is an absolute path (or None for a massless link); ``units`` the CAD
    length unit.  ``regions`` maps a joint name (or ``"tcp"``) to its seat region.
    ``volume_meshes`` maps a tet edge length [m] to a volume-mesh file whose tetrahedra
    are used at that size instead of meshing the CAD (a mesh made elsewhere, or pinned
    so that every run sees the same elements; :mod:`flexarm.robot.volume_meshes`).
    """

    name: str
    mesh: Path | None
    material: Material
    units: str = "m"
    lumped: tuple[LumpedMass, ...] = ()
    regions: dict = field(default_factory=dict, compare=False)
    volume_meshes: dict = field(default_factory=dict, compare=False)


@dataclass(frozen=True)
class Joint:
    """A revolute joint; ``origin`` [m] and ``rpy`` [rad] in the parent frame.

    ``model`` is the physical joint (gear torsion, bearing stiffness), used by the
    flexible and full-FE arms; ``emodel`` (optional) is the *equivalent* joint of the
    rigid-link E-model, the bearing in series with the bending of the links it carries
    (:func:`~flexarm.assembly.equivalent.equivalent_joint_models`).
    """

    name: str
    parent: str
    child: str
    origin: tuple
    axis: tuple
    lower: float
    upper: float
    model: JointModel
    rpy: tuple = (0.0, 0.0, 0.0)
    gear_ratio: float = 1.0
    emodel: JointModel | None = None


@dataclass(frozen=True)
class BaseSupport:
    """``"clamped"`` or ``"spring"`` with a (6, 6) foundation stiffness [N/m, N m/rad]."""

    kind: str = "clamped"
    stiffness: tuple | None = None
    damping_ratio: float = 0.02


@dataclass(frozen=True)
class Tool:
    """TCP frame on ``link`` (default: the last): offset ``xyz`` [m], ``rpy`` [rad]."""

    xyz: tuple = (0.0, 0.0, 0.0)
    rpy: tuple = (0.0, 0.0, 0.0)
    link: str | None = None

    def matrix(self) -> FloatArray:
        T = np.eye(4)
        T[:3, :3] = rpy_matrix(self.rpy)
        T[:3, 3] = self.xyz
        return T


@dataclass(frozen=True)
class ModelOptions:
    """Element order (1|2), mesh size [m], Craig–Bampton mode count per link, and the
    tetrahedraliser (``"tetwild"``; ``"gmsh"``: the same CAD gives the same mesh; ``"auto"``,
    the setting of imported robots: Gmsh where the CAD allows, fTetWild for dirty CAD)."""

    element_order: int = 1
    mesh_size: float = 0.03
    cb_modes: int = 10
    mesher: str = "tetwild"


@dataclass(frozen=True, eq=False)
class Robot:
    """A validated robot description.

    Links are listed base first; joint ``j`` (in order) has child ``links[j + 1]``
    and a parent listed earlier.  ``poses`` maps names to joint angles [rad].
    ``effects`` are the nonlinear joint laws (:class:`~flexarm.robot.effects.Effect` of
    kind backlash, hardening or hysteresis) and the fitted effects of kind
    :data:`~flexarm.robot.effects.STORED` (tool compliance, balancer, measurement frame)
    that every prediction compared with measurements adds; linear analyses ignore them.
    ``modal_damping`` maps a pose name to the modal damping ratios identified there,
    ``(freq_hz, zeta)`` tuples (``fit-damping --method modal``); the FRF at that pose
    uses them (:mod:`flexarm.validation.dynamic.pose_damping`).
    """

    name: str
    links: tuple[Link, ...]
    joints: tuple[Joint, ...]
    base: BaseSupport = BaseSupport()
    tool: Tool = Tool()
    poses: dict = field(default_factory=dict)
    options: ModelOptions = ModelOptions()
    wrist_coupling: tuple | None = None
    wrist_stiffness: tuple | None = None
    source: Path | None = None
    effects: tuple = ()
    modal_damping: dict = field(default_factory=dict, compare=False)

    def __post_init__(self) -> None:
        from .description_checks import validate

        validate(self)

    @cached_property
    def link_index(self) -> dict[str, int]:
        return {lk.name: i for i, lk in enumerate(self.links)}

    @property
    def joint_names(self) -> tuple[str, ...]:
        return tuple(j.name for j in self.joints)

    def __repr__(self) -> str:
        """One line: name, links, joints, pose names, mesh size [mm], element order, mesher.

        Examples
        --------
        >>> from flexarm.robot import load_robot
        >>> load_robot()  # doctest: +ELLIPSIS
        Robot('...', 7 links, 6 joints, poses P1, ..., mesh 30 mm Tet4 (...), 10 CB modes, \
base clamped)
        """
        from ..fe.notebook import names

        opts = self.options
        return (f"Robot({self.name!r}, {len(self.links)} links, {len(self.joints)} joints, "
                f"poses {names(self.poses) or 'none'}, mesh {opts.mesh_size * 1e3:.4g} mm "
                f"Tet{4 if opts.element_order == 1 else 10} ({opts.mesher}), "
                f"{opts.cb_modes} CB modes, base {self.base.kind})")

    def full_repr(self) -> str:
        """Every field as the dataclass repr writes it (the text cache keys hash; ``repr``
        is the short notebook line).

        Examples
        --------
        >>> from flexarm.robot import load_robot
        >>> text = load_robot().full_repr()
        >>> text.startswith("Robot(name="), "stiffness=" in text
        (True, True)
        """
        import dataclasses

        return (f"{type(self).__qualname__}(" + ", ".join(
            f"{f.name}={getattr(self, f.name)!r}" for f in dataclasses.fields(self) if f.repr)
            + ")")

    @property
    def lower(self) -> FloatArray:
        return np.array([j.lower for j in self.joints])

    @property
    def upper(self) -> FloatArray:
        return np.array([j.upper for j in self.joints])

    @cached_property
    def chain(self) -> Chain:
        """Kinematic :class:`Chain` (body ``i`` = ``links[i]``)."""
        idx = self.link_index
        tcp = idx[self.tool.link] if self.tool.link else len(self.links) - 1
        return Chain(
            origins=[j.origin for j in self.joints],
            axes=[j.axis for j in self.joints],
            parents=[idx[j.parent] for j in self.joints],
            origin_R=np.array([rpy_matrix(j.rpy) for j in self.joints]).reshape(-1, 3, 3),
            tool=self.tool.matrix(),
            tcp_body=tcp,
            gear_ratios=[j.gear_ratio for j in self.joints],
            wrist_coupling=None if self.wrist_coupling is None else np.array(self.wrist_coupling),
        )

    def pose(self, spec) -> FloatArray:
        """(n,) joint angles [rad] of a named pose or of a sequence of angles [rad]."""
        if isinstance(spec, str):
            if spec not in self.poses:
                raise ValueError(f"unknown pose '{spec}' (robot has {sorted(self.poses)})")
            return np.array(self.poses[spec], dtype=float)
        q = np.asarray(spec, dtype=float)
        if q.shape != (len(self.joints),):
            raise ValueError(f"pose must have {len(self.joints)} joint angles, got {q.shape}")
        return q


def pose_from_string(robot: Robot, text: str) -> FloatArray:
    """(n,) joint angles [rad] of a pose name (``"P1"``) or ``"q1,...,qn"`` in degrees."""
    text = text.strip()
    if text in robot.poses:
        return np.array(robot.poses[text], dtype=float)
    parts = [p for p in text.replace(";", ",").split(",") if p.strip()]
    try:
        q = np.radians([float(p) for p in parts])
    except ValueError:
        raise ValueError(f"pose must be one of {sorted(robot.poses)} or {len(robot.joints)} "
                         f"comma-separated angles in degrees, got '{text}'") from None
    if len(q) != len(robot.joints):
        raise ValueError(f"pose needs {len(robot.joints)} angles in degrees, got '{text}'")
    check_limits(robot, q, f"pose '{text}'")
    return q


def check_limits(robot: Robot, q, what: str = "pose") -> None:
    """Raise ``ValueError`` naming the joint, its angle and limits [deg] if a joint angle of
    ``q`` (n,) [rad] is not finite or lies outside the robot's limits.

    Examples
    --------
    >>> from flexarm.robot import load_robot
    >>> check_limits(load_robot(), np.radians([0, 260, 0, 0, 0, 0]))
    Traceback (most recent call last):
    ...
    ValueError: pose: joint_2 = 260 deg is outside its limits [-90, 150] deg
    """
    q = np.asarray(q, dtype=float)
    bad = np.flatnonzero(~np.isfinite(q) | (q < robot.lower) | (q > robot.upper))
    if bad.size:
        j = int(bad[0])
        raise ValueError(f"{what}: {robot.joints[j].name} = {math.degrees(q[j]):g} deg is "
                         f"outside its limits [{math.degrees(robot.lower[j]):g}, "
                         f"{math.degrees(robot.upper[j]):g}] deg")
