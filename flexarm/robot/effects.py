"""Named physical effects of a robot's joints, base and links, as data.

An :class:`Effect` is a kind, an optional joint and named parameters in SI units:

==============  =============================================  ================================
kind            parameters                                     model
==============  =============================================  ================================
``stiffness``   ``scale`` [-]                                  torsion compliance x scale
``backlash``    ``width`` [rad]                                dead band
``hardening``   ``extra`` [rad/(N m)], ``threshold`` [N m]     softer below the threshold
``hysteresis``  ``lost`` [rad], ``radius`` [N m]               lost motion, rounded
``tilt``        ``compliance`` [rad/(N m)]                     bearing tilt in series
``base``        ``compliance`` [rad/(N m)]                     foundation tilt about x, y
``wrist``       ``c45``, ``c46``, ``c56`` [rad/(N m)]          coupled wrist compliance
``links``       ``compliance`` [-]                             link flexibility
``tool``        ``cxx`` ... ``cyz`` [m/N]                      tool/adapter compliance, 3x3
                                                               in the tool frame
``balancer``    ``kc``, ``ks`` [N m/rad]                       gravity balancer: stiffness
                                                               ``kc cos q + ks sin q`` in
                                                               parallel with the gear
``frame``       ``rx``, ``ry``, ``rz`` [rad], ``scale`` [-]    tracker frame misaligned:
                                                               small rotation and scale
``foundation``  ``cx``, ``cy`` [rad/(N m)]                     foundation tilt about base x
                                                               and y, each its own
``mass``        ``mass`` [kg]                                  added at the centre of mass
                                                               of the joint's child link
``loadcell``    ``scale`` [-]                                  the static file's forces read
                                                               ``1 + scale`` times the true
``reflector``   ``ox``, ``oy``, ``oz`` [m]                     the measured point sits off
                                                               the TCP (tool frame)
==============  =============================================  ================================

:func:`parse_effect` reads the command-line form ``backlash:j2=0.1mrad``,
``hardening:j1=0.5,t=400Nm`` (``K1/K2 = 0.5`` below 400 N m), ``hysteresis:j2=0.1mrad,r=300Nm``,
``tilt:j2=1e7`` (added tilt stiffness [N m/rad]), ``base:k=2e7`` (foundation tilt stiffness
[N m/rad]), ``wrist:c45=0.5,c56=0.3`` (correlations of the wrist compliances),
``stiffness:j3=1.3`` (torsion *stiffness* x 1.3), ``links:c=1`` (the flexible model's
links), ``tool:cxx=2e-7,cyz=5e-8`` (tool-frame compliance [m/N]), ``balancer:j2=3e5,s=1e5``
(balancer stiffness ``kc`` and ``ks`` [N m/rad]), ``frame:rz=1.5deg,scale=0.002``,
``foundation:kx=2e7`` (tilt stiffness about base x only [N m/rad]; ``ky=`` about y),
``mass:l3=20kg`` (added to link 3), ``loadcell:s=0.03`` (forces read 3 % high) and
``reflector:ox=30mm,oz=-10mm`` (the reflector's offset from the TCP, tool frame).
How an effect changes an arm model is :mod:`flexarm.assembly.effects`.
"""

from __future__ import annotations

import re
from dataclasses import dataclass, replace

import numpy as np

from ..fe.quantities import Quantity

__all__ = ["Effect", "parse_effect", "KINDS", "NONLINEAR", "STORED", "TOOL_PARAMS",
           "TOOL_INDEX", "TYPED",
           "LOWER_BOUNDS", "lower_bound"]

#: Effects that make a joint law nonlinear (the robot file's ``[nonlinear]`` table).
NONLINEAR = ("backlash", "hardening", "hysteresis")
KINDS = ("stiffness", "backlash", "hardening", "hysteresis", "tilt", "base", "wrist", "links",
         "tool", "balancer", "frame", "foundation", "mass", "loadcell", "reflector")
#: Fitted effects a robot file keeps besides its springs, masses and joint laws (its
#: ``[[effects]]`` array): what the arm adds to every static prediction (tool, balancer)
#: and the measurement setup (tracker frame, load cell, reflector offset).
STORED = ("tool", "balancer", "frame", "loadcell", "reflector")
#: Parameters of the tool-frame compliance, in the order of :data:`TOOL_INDEX`.
TOOL_PARAMS = ("cxx", "cyy", "czz", "cxy", "cxz", "cyz")
TOOL_INDEX = ((0, 0), (1, 1), (2, 2), (0, 1), (0, 2), (1, 2))
#: The smallest physical value of a parameter, where it has one: compliances, a scale of a
#: compliance, a tool's direct compliances.  A fit keeps its parameters above these
#: (Gauss-Newton steps are cut short of the bound), so no model it evaluates has a negative
#: spring.  Signed amplitudes (a backlash width the score test may probe below zero, a
#: balancer, a frame rotation) have none.
LOWER_BOUNDS = {("stiffness", "scale"): 0.0, ("hardening", "extra"): 0.0,
                ("hardening", "threshold"): 0.0, ("hysteresis", "radius"): 0.0,
                ("tilt", "compliance"): 0.0, ("base", "compliance"): 0.0,
                ("links", "compliance"): 0.0, ("tool", "cxx"): 0.0, ("tool", "cyy"): 0.0,
                ("tool", "czz"): 0.0, ("frame", "scale"): -1.0, ("foundation", "cx"): 0.0,
                ("foundation", "cy"): 0.0, ("mass", "mass"): 0.0, ("loadcell", "scale"): -0.5}


def lower_bound(kind: str, name: str) -> float:
    """The lower bound of parameter ``name`` of an effect of ``kind`` (``-inf`` if none).

    Examples
    --------
    >>> lower_bound("tilt", "compliance"), lower_bound("balancer", "kc")
    (0.0, -inf)
    """
    return LOWER_BOUNDS.get((kind, name), -np.inf)


def _q(kind: str, unit: str, low: float, high: float, **kw) -> Quantity:
    return Quantity(kind, unit, low, high, **kw)


_ANGLE = {"bare": False, "result": "rad"}  # an angle's unit is never guessed
_STIFF = ("torsional stiffness", "Nm/rad")
#: (kind, key) -> (what the value is, how it is read) of every typed value of an effect;
#: key ``j`` is the value given with the joint (``backlash:j2=0.1mrad``).  The ranges hold
#: every effect a robot can plausibly show and keep the signs that make physical sense.
TYPED = {
    ("stiffness", "j"): ("torsion stiffness factor", _q("ratio", "", 0, 1e3, open_low=True)),
    ("backlash", "j"): ("backlash width", _q("angle", "mrad", 0, 100, open_low=True, **_ANGLE)),
    ("hardening", "j"): ("hardening ratio K1/K2", _q("ratio", "", 0, 1, open_low=True)),
    ("hardening", "t"): ("hardening threshold", _q("moment", "Nm", 0, 1e6, open_low=True)),
    ("hysteresis", "j"): ("hysteresis lost motion",
                          _q("angle", "mrad", 0, 100, open_low=True, **_ANGLE)),
    ("hysteresis", "r"): ("hysteresis radius", _q("moment", "Nm", 0, 1e6, open_low=True)),
    ("tilt", "j"): ("tilt stiffness", _q(*_STIFF, 0, 1e13, open_low=True)),
    ("base", "k"): ("foundation tilt stiffness", _q(*_STIFF, 0, 1e13, open_low=True)),
    ("links", "c"): ("link compliance factor", _q("ratio", "", 0, 100)),
    **{("wrist", k): (f"wrist correlation {k}", _q("ratio", "", -1, 1, open_low=True,
                                                      open_high=True))
       for k in ("c45", "c46", "c56")},
    **{("tool", k): (f"tool compliance {k}",
                     _q("compliance", "m/N", 0 if k[1] == k[2] else -1e-3, 1e-3))
       for k in TOOL_PARAMS},
    ("balancer", "j"): ("balancer stiffness kc", _q(*_STIFF, -1e10, 1e10)),
    ("balancer", "s"): ("balancer stiffness ks", _q(*_STIFF, -1e10, 1e10)),
    **{("frame", k): (f"frame rotation {k}", _q("angle", "deg", -45, 45, **_ANGLE))
       for k in ("rx", "ry", "rz")},
    ("frame", "scale"): ("frame scale", _q("ratio", "", -0.5, 0.5)),
    **{("foundation", f"k{a}"): (f"foundation stiffness k{a}", _q(*_STIFF, 0, 1e13))
       for a in "xy"},
    ("mass", "j"): ("added mass", _q("mass", "kg", 0, 1e4, open_low=True)),
    ("loadcell", "s"): ("load cell scale", _q("ratio", "", -0.5, 0.5)),
    **{("reflector", k): (f"reflector offset {k}",
                          _q("length", "mm", -2000, 2000, bare=False, result="m"))
       for k in ("ox", "oy", "oz")},
}


@dataclass(frozen=True)
class Effect:
    """One physical effect: ``kind``, 0-based ``joint`` (or None), SI ``params``.

    Examples
    --------
    >>> e = Effect("backlash", 1, (("width", 1e-4),))
    >>> e.label, e.get("width")
    ('joint 2 backlash', 0.0001)
    """

    kind: str
    joint: int | None = None
    params: tuple[tuple[str, float], ...] = ()

    def __post_init__(self) -> None:
        if self.kind not in KINDS:
            raise ValueError(f"unknown effect kind '{self.kind}' (known: {', '.join(KINDS)})")

    def get(self, name: str, default: float | None = None) -> float:
        for k, v in self.params:
            if k == name:
                return float(v)
        if default is None:
            raise KeyError(f"effect {self.kind} has no parameter '{name}'")
        return default

    def with_params(self, **values: float) -> Effect:
        d = dict(self.params)
        d.update({k: float(v) for k, v in values.items()})
        return replace(self, params=tuple(d.items()))

    @property
    def label(self) -> str:
        """Short human label, e.g. ``joint 2 backlash``, ``link 3 added mass``."""
        if self.kind == "mass":
            return f"link {self.joint + 1} added mass"
        return self.kind if self.joint is None else f"joint {self.joint + 1} {self.kind}"

    def to_dict(self) -> dict:
        """JSON-ready record; joints are numbered from 1 (``joint_number``), as the
        command line and every label count them."""
        return {"kind": self.kind,
                "joint_number": None if self.joint is None else self.joint + 1,
                "params": dict(self.params)}

    @classmethod
    def from_dict(cls, d: dict) -> Effect:
        """The record of :meth:`to_dict`; older files' 0-based ``joint`` is read too."""
        if "joint_number" in d:
            joint = None if d["joint_number"] is None else int(d["joint_number"]) - 1
        else:
            joint = d.get("joint")
        return cls(d["kind"], joint, tuple((k, float(v))
                                           for k, v in d.get("params", {}).items()))


def _compliance(k: float) -> float:
    """A compliance [rad/(N m)] from a stiffness [N m/rad]; 0 (rigid) for 0."""
    return 0.0 if k == 0 else 1.0 / k


def parse_effect(spec: str, n_joints: int = 6) -> Effect:
    """Effect from its command-line form (see the module docstring).

    Every value is read by :mod:`flexarm.fe.quantities` with the quantity and range of
    :data:`TYPED`: angles and lengths need a unit (``0.1mrad``, ``30mm``), other values
    are read in the SI unit of the table above when bare (``t=400`` is 400 N m), and a
    value of the wrong sign or outside its plausible range is refused.  Every message
    starts ``effect '<spec>':``.

    Examples
    --------
    >>> parse_effect("backlash:j2=0.1mrad")
    Effect(kind='backlash', joint=1, params=(('width', 0.0001),))
    """
    if ":" not in spec:
        raise ValueError(f"effect '{spec}': expected KIND:KEY=VALUE[,KEY=VALUE]")
    kind, rest = spec.split(":", 1)
    kind = kind.strip().lower()
    if kind not in KINDS:
        raise ValueError(f"effect '{spec}': unknown kind '{kind}' (known: {', '.join(KINDS)})")
    items = {}
    for part in rest.split(","):
        if "=" not in part:
            raise ValueError(f"effect '{spec}': '{part}' is not KEY=VALUE")
        k, v = part.split("=", 1)
        items[k.strip().lower()] = v.strip()
    joint = None
    for k in list(items):
        if re.fullmatch(r"[jl]\d+", k):
            joint = int(k[1:]) - 1
            if not 0 <= joint < n_joints:
                raise ValueError(f"effect '{spec}': joint {joint + 1} outside 1..{n_joints}")
            items["j"] = items.pop(k)
    needs_joint = kind in ("stiffness", "backlash", "hardening", "hysteresis", "tilt",
                           "balancer", "mass")
    if needs_joint and joint is None:
        raise ValueError(f"effect '{spec}': name the joint, e.g. {kind}:j2=...")

    def value(key: str, default: float = 0.0) -> float:
        """The typed value of ``key`` (``default`` [SI] when not given), checked."""
        if key not in items:
            return default
        name, quantity = TYPED[(kind, key)]
        try:
            return quantity.parse(items[key], name)
        except ValueError as exc:
            raise ValueError(f"effect '{spec}': {exc}") from None

    if kind == "stiffness":
        return Effect(kind, joint, (("scale", 1.0 / value("j")),))
    if kind == "backlash":
        return Effect(kind, joint, (("width", value("j")),))
    if kind == "hysteresis":
        return Effect(kind, joint, (("lost", value("j")), ("radius", value("r", 300.0))))
    if kind == "hardening":
        return Effect(kind, joint, (("ratio", value("j")), ("threshold", value("t", 400.0))))
    if kind == "tilt":
        return Effect(kind, joint, (("stiffness", value("j")),))
    if kind == "base":
        return Effect(kind, None, (("stiffness", value("k", 2e7)),))
    if kind == "links":
        return Effect(kind, None, (("compliance", value("c", 1.0)),))
    if kind == "wrist":
        return Effect(kind, None, tuple((f"rho{k[1:]}", value(k)) for k in items
                                        if k in ("c45", "c46", "c56")))
    if kind == "tool":
        return Effect(kind, None, tuple((k, value(k)) for k in TOOL_PARAMS))
    if kind == "balancer":
        return Effect(kind, joint, (("kc", value("j")), ("ks", value("s"))))
    if kind == "frame":
        return Effect(kind, None, tuple((k, value(k)) for k in ("rx", "ry", "rz", "scale")))
    if kind == "foundation":
        return Effect(kind, None, tuple((f"c{a}", _compliance(value(f"k{a}"))) for a in "xy"))
    if kind == "mass":
        return Effect(kind, joint, (("mass", value("j")),))
    if kind == "loadcell":
        return Effect(kind, None, (("scale", value("s")),))
    return Effect(kind, None, tuple((k, value(k)) for k in ("ox", "oy", "oz")))  # reflector
