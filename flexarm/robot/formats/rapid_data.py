"""RAPID data types: robtargets, joint targets, declarations, motions and modules.

The dataclasses :func:`~flexarm.robot.formats.rapid.read_rapid` returns, the
instruction signatures shared by the reader and the writer, and the configuration
helpers :func:`quadrant` and :func:`decode_cfx`.  Positions are in mm, quaternions
``[w, x, y, z]`` and joint values in degrees, as in RAPID.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, field
from types import MappingProxyType
from typing import Any

import numpy as np

from ...fe.typing import ArrayLike, FloatArray, IntArray

__all__ = [
    "RobTarget",
    "JointTarget",
    "Declaration",
    "Motion",
    "Procedure",
    "RapidModule",
    "Target",
    "SUPPORTED_INSTRUCTIONS",
    "EXTAX_UNUSED",
    "quadrant",
    "decode_cfx",
]

#: RAPID's value for an external axis that is not in use.
EXTAX_UNUSED = 9e9
#: Instructions this reader turns into :class:`Motion` objects.
SUPPORTED_INSTRUCTIONS = ("MoveL", "MoveJ", "MoveC", "MoveAbsJ")

#: Positional arguments and allowed optional arguments (with the positional argument
#: each optional one follows, -1 = before the first) of every supported instruction.
_SIGNATURES: dict[str, tuple[tuple[str, ...], dict[str, int]]] = {
    "MoveL": (("ToPoint", "Speed", "Zone", "Tool"),
              {"Conc": -1, "ID": 0, "V": 1, "T": 1, "Z": 2, "Inpos": 2, "WObj": 3, "Corr": 3,
               "TLoad": 3}),
    "MoveJ": (("ToPoint", "Speed", "Zone", "Tool"),
              {"Conc": -1, "ID": 0, "V": 1, "T": 1, "Z": 2, "Inpos": 2, "WObj": 3, "TLoad": 3}),
    "MoveC": (("CirPoint", "ToPoint", "Speed", "Zone", "Tool"),
              {"Conc": -1, "ID": 1, "V": 2, "T": 2, "Z": 3, "Inpos": 3, "WObj": 4, "Corr": 4,
               "TLoad": 4}),
    "MoveAbsJ": (("ToJointPos", "Speed", "Zone", "Tool"),
                 {"Conc": -1, "ID": 0, "NoEOffs": 0, "V": 1, "T": 1, "Z": 2, "Inpos": 2,
                  "WObj": 3, "TLoad": 3}),
}


def _frozen(a: ArrayLike, dtype) -> np.ndarray:
    arr = np.array(a, dtype=dtype)
    arr.setflags(write=False)
    return arr


@dataclass(frozen=True, eq=False)
class RobTarget:
    """A RAPID ``robtarget``: a TCP pose with configuration and external axes.

    Parameters
    ----------
    name : str
        Data name as written in the module (or the expression text for inline targets).
    pos_mm : (3,) float
        TCP position [mm] in the work-object frame.
    quat : (4,) float
        Tool orientation in the work-object frame, ``[w, x, y, z]`` (RAPID ``q1..q4``),
        exactly as written (not renormalised).
    conf : (4,) int
        Configuration ``[cf1, cf4, cf6, cfx]``: quadrants of axes 1, 4 and 6 and the
        arm-configuration number (see :mod:`flexarm.robot.paths` for its meaning).
    extax : (6,) float
        External axes a–f [mm or deg]; :data:`EXTAX_UNUSED` (9E9) when not used.

    Examples
    --------
    >>> p = RobTarget("p", [1000, 0, 500], [1, 0, 0, 0], [0, 0, 0, 1], [9e9] * 6)
    >>> p.pos_mm.tolist(), p.conf.tolist(), bool(p.is_extax_used.any())
    ([1000.0, 0.0, 500.0], [0, 0, 0, 1], False)
    """

    name: str
    pos_mm: FloatArray
    quat: FloatArray
    conf: IntArray
    extax: FloatArray

    def __post_init__(self) -> None:
        for attr, shape, dtype in (("pos_mm", (3,), np.float64), ("quat", (4,), np.float64),
                                   ("conf", (4,), np.int64), ("extax", (6,), np.float64)):
            arr = _frozen(getattr(self, attr), dtype)
            if arr.shape != shape:
                raise ValueError(f"RobTarget.{attr} must have shape {shape}, got {arr.shape}")
            object.__setattr__(self, attr, arr)

    @property
    def is_extax_used(self) -> np.ndarray:
        """(6,) bool: external axes with a value (not 9E9)."""
        return self.extax < EXTAX_UNUSED * (1 - 1e-6)

    def renamed(self, name: str) -> RobTarget:
        """The same target under another name."""
        return RobTarget(name, self.pos_mm, self.quat, self.conf, self.extax)


@dataclass(frozen=True, eq=False)
class JointTarget:
    """A RAPID ``jointtarget``: robot axes [deg] and external axes.

    Parameters
    ----------
    name : str
    joints_deg : (6,) float
        Robot axes 1–6 [deg].
    extax : (6,) float
        External axes a–f; 9E9 when not used.
    """

    name: str
    joints_deg: FloatArray
    extax: FloatArray

    def __post_init__(self) -> None:
        for attr in ("joints_deg", "extax"):
            arr = _frozen(getattr(self, attr), np.float64)
            if arr.shape != (6,):
                raise ValueError(f"JointTarget.{attr} must have shape (6,), got {arr.shape}")
            object.__setattr__(self, attr, arr)


@dataclass(frozen=True)
class Declaration:
    """Any other data declaration (``tooldata``, ``wobjdata``, ``speeddata``, ``num``, ...).

    ``value`` is the literal as nested tuples of float, bool and str (``None`` when the
    declaration has no initial value).
    """

    storage: str
    type: str
    name: str
    value: Any
    line: int


Target = RobTarget | JointTarget


@dataclass(frozen=True)
class Motion:
    """One Move instruction.

    Parameters
    ----------
    kind : {"MoveL", "MoveJ", "MoveC", "MoveAbsJ"}
    targets : tuple of RobTarget or JointTarget
        ``(ToPoint,)``, or ``(CirPoint, ToPoint)`` for ``MoveC``, or ``(ToJointPos,)``.
    speed, zone, tool : str
        The arguments as written (``"v10"``, ``"fine"``, ``"tool0"``).
    wobj : str or None
        ``\\WObj`` argument (``None``: ``wobj0``, the robot base frame).
    options : tuple of (str, str or None)
        The other optional arguments, e.g. ``(("Conc", None),)``.
    line : int
        Line of the instruction in the file (1-based).
    """

    kind: str
    targets: tuple[Target, ...]
    speed: str
    zone: str
    tool: str
    wobj: str | None
    options: tuple[tuple[str, str | None], ...]
    line: int

    @property
    def to_point(self) -> Target:
        """The destination (``ToPoint`` or ``ToJointPos``)."""
        return self.targets[-1]

    @property
    def cir_point(self) -> RobTarget | None:
        """The circle point of a ``MoveC`` (``None`` otherwise)."""
        return self.targets[0] if self.kind == "MoveC" else None

    @property
    def is_fine(self) -> bool:
        """True if the motion stops at its destination (zone ``fine``)."""
        return self.zone.lower() == "fine"


@dataclass(frozen=True)
class Procedure:
    """A ``PROC`` routine: its name, motions in program order and first line."""

    name: str
    motions: tuple[Motion, ...]
    line: int


@dataclass(frozen=True, eq=False)
class RapidModule:
    """A parsed RAPID module.

    Parameters
    ----------
    name : str
    targets : mapping of str to RobTarget
        Module-level robtargets in file order.
    procedures : mapping of str to Procedure
        In file order.
    joint_targets : mapping of str to JointTarget
    data : mapping of str to Declaration
        Every other module-level declaration.
    path : str
        File it was read from ("" if built in memory).
    """

    name: str
    targets: Mapping[str, RobTarget]
    procedures: Mapping[str, Procedure]
    joint_targets: Mapping[str, JointTarget] = field(default_factory=dict)
    data: Mapping[str, Declaration] = field(default_factory=dict)
    path: str = ""

    def __post_init__(self) -> None:
        for attr in ("targets", "procedures", "joint_targets", "data"):
            object.__setattr__(self, attr, MappingProxyType(dict(getattr(self, attr))))

    def procedure(self, name: str) -> Procedure:
        """Procedure by name (case-insensitive); ``KeyError`` lists the known ones."""
        for key, proc in self.procedures.items():
            if key.lower() == name.lower():
                return proc
        raise KeyError(f"no procedure '{name}' in module {self.name} "
                       f"(known: {', '.join(self.procedures)})")


def quadrant(angle_deg: ArrayLike) -> IntArray:
    """RAPID configuration quadrant of a rotating axis: ``floor(angle / 90 deg)``.

    ``0`` for [0, 90) deg, ``1`` for [90, 180), ``-1`` for [-90, 0), ``-2`` for
    [-180, -90), and so on beyond one turn.  ``cf1``, ``cf4`` and ``cf6`` are the quadrants
    of axes 1, 4 and 6.  (Exactly at a boundary the controller accepts either side.)

    Examples
    --------
    >>> quadrant([0.0, 45.0, 90.0, -10.0, -135.0, 200.0]).tolist()
    [0, 0, 1, -1, -2, 2]
    """
    return np.floor(np.asarray(angle_deg, dtype=np.float64) / 90.0).astype(np.int64)


def decode_cfx(cfx: int) -> dict[str, bool]:
    """Meaning of ``cfx`` (0..7) for ABB 6-axis serial arms such as the IRB 4600.

    Bit 2 set: wrist centre *behind* axis 1; bit 1 set: wrist centre *behind* the lower
    arm (the line through axes 2 and 3); bit 0 set: axis 5 angle *negative*.

    Returns
    -------
    dict
        ``wrist_in_front_of_axis1``, ``wrist_in_front_of_lower_arm``, ``axis5_positive``.

    Examples
    --------
    >>> decode_cfx(1)
    {'wrist_in_front_of_axis1': True, 'wrist_in_front_of_lower_arm': True, 'axis5_positive': False}
    """
    if int(cfx) != cfx or not 0 <= cfx <= 7:
        raise ValueError(f"cfx must be an integer in 0..7, got {cfx}")
    cfx = int(cfx)
    return {"wrist_in_front_of_axis1": not cfx & 4, "wrist_in_front_of_lower_arm": not cfx & 2,
            "axis5_positive": not cfx & 1}
