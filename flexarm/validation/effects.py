"""Named physical effects that modify an arm model (for the virtual lab and the diagnosis).

An :class:`Effect` is a kind, an optional joint and named parameters in SI units:

================  ==========================================  ============================
kind              parameters                                  model
================  ==========================================  ============================
``stiffness``     ``scale`` [-]                               torsion compliance x scale
``backlash``      ``width`` [rad]                             :class:`Backlash`
``hardening``     ``extra`` [rad/(N m)], ``threshold`` [N m]  :class:`Hardening`
``hysteresis``    ``lost`` [rad], ``radius`` [N m]            :class:`Hysteresis`
``tilt``          ``compliance`` [rad/(N m)]                  bearing tilt in series
``base``          ``compliance`` [rad/(N m)]                  foundation tilt about x, y
``wrist``         ``c45``, ``c46``, ``c56`` [rad/(N m)]       coupled wrist compliance
``links``         ``compliance`` [-]                          link flexibility (``linkflex``)
================  ==========================================  ============================

:func:`apply_effects` turns an :class:`~flexarm.assembly.system.ArmModel` plus effects
into a new arm (linear effects) and a map joint -> nonlinear laws.  :func:`parse_effect`
reads the command-line form ``backlash:j2=0.1mrad``, ``hardening:j1=0.5,t=400Nm``
(``K1/K2 = 0.5`` below 400 N m), ``hysteresis:j2=0.1mrad,r=300Nm``, ``tilt:j2=1e7``
(added tilt stiffness [N m/rad]), ``base:k=2e7`` (foundation tilt stiffness [N m/rad]),
``wrist:c45=0.5,c56=0.3`` (correlations of the wrist compliances), ``stiffness:j3=1.3``
(torsion *stiffness* x 1.3), ``links:c=1`` (the flexible model's links; needs the flexible
model, see :mod:`~flexarm.validation.linkflex`; :func:`apply_effects` leaves it to the caller).
"""

from __future__ import annotations

import re
from dataclasses import dataclass, replace

import numpy as np

from ..assembly.nonlinear import Backlash, Hardening, Hysteresis
from ..assembly.system import ArmModel
from ..fe.tolerances import tol

__all__ = ["Effect", "apply_effects", "parse_effect", "wrist_compliance", "KINDS"]

KINDS = ("stiffness", "backlash", "hardening", "hysteresis", "tilt", "base", "wrist", "links")
_UNITS = {"": 1.0, "rad": 1.0, "mrad": 1e-3, "urad": 1e-6, "nm": 1.0, "knm": 1e3,
          "nm/rad": 1.0, "deg": np.pi / 180}


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
        """Short human label, e.g. ``joint 2 backlash``."""
        return self.kind if self.joint is None else f"joint {self.joint + 1} {self.kind}"

    def to_dict(self) -> dict:
        return {"kind": self.kind, "joint": self.joint, "params": dict(self.params)}

    @classmethod
    def from_dict(cls, d: dict) -> Effect:
        return cls(d["kind"], d.get("joint"), tuple((k, float(v))
                                                    for k, v in d.get("params", {}).items()))


def _value(text: str) -> float:
    m = re.fullmatch(r"\s*([-+0-9.eE]+)\s*([A-Za-z/]*)\s*", text)
    if not m or m.group(2).lower() not in _UNITS:
        raise ValueError(f"cannot read value '{text}' (number with unit among "
                         f"{sorted(u for u in _UNITS if u)})")
    return float(m.group(1)) * _UNITS[m.group(2).lower()]


def parse_effect(spec: str, n_joints: int = 6) -> Effect:
    """Effect from its command-line form (see the module docstring).

    Examples
    --------
    >>> parse_effect("backlash:j2=0.1mrad")
    Effect(kind='backlash', joint=1, params=(('width', 0.0001),))
    """
    if ":" not in spec:
        raise ValueError(f"effect '{spec}': expected KIND:KEY=VALUE[,KEY=VALUE]")
    kind, rest = spec.split(":", 1)
    kind = kind.strip().lower()
    items = {}
    for part in rest.split(","):
        if "=" not in part:
            raise ValueError(f"effect '{spec}': '{part}' is not KEY=VALUE")
        k, v = part.split("=", 1)
        items[k.strip().lower()] = v.strip()
    joint, amount = None, None
    for k in list(items):
        if re.fullmatch(r"j\d+", k):
            joint = int(k[1:]) - 1
            if not 0 <= joint < n_joints:
                raise ValueError(f"effect '{spec}': joint {joint + 1} outside 1..{n_joints}")
            amount = _value(items.pop(k))
    needs_joint = kind in ("stiffness", "backlash", "hardening", "hysteresis", "tilt")
    if needs_joint and joint is None:
        raise ValueError(f"effect '{spec}': name the joint, e.g. {kind}:j2=...")
    if kind == "stiffness":
        return Effect(kind, joint, (("scale", 1.0 / amount),))
    if kind == "backlash":
        return Effect(kind, joint, (("width", amount),))
    if kind == "hysteresis":
        return Effect(kind, joint, (("lost", amount), ("radius", _value(items.get("r", "300")))))
    if kind in ("hardening", "tilt"):
        return Effect(kind, joint, (("ratio" if kind == "hardening" else "stiffness", amount),)
                      + ((("threshold", _value(items.get("t", "400"))),)
                         if kind == "hardening" else ()))
    if kind == "base":
        return Effect(kind, None, (("stiffness", _value(items.get("k", "2e7"))),))
    if kind == "links":
        return Effect(kind, None, (("compliance", _value(items.get("c", "1"))),))
    if kind == "wrist":
        return Effect(kind, None, tuple((f"rho{k[1:]}", _value(v)) for k, v in items.items()
                                        if k in ("c45", "c46", "c56")))
    raise ValueError(f"unknown effect kind '{kind}' (known: {', '.join(KINDS)})")


def resolve(effect: Effect, arm: ArmModel) -> Effect:
    """Convert relative command-line parameters (ratios, stiffnesses) to the SI model form."""
    e = effect
    if e.kind == "hardening" and "ratio" in dict(e.params):
        k2 = arm.joints[e.joint].torsion
        return Effect(e.kind, e.joint, (("extra", 1 / (e.get("ratio") * k2) - 1 / k2),
                                        ("threshold", e.get("threshold"))))
    if e.kind in ("tilt", "base") and "stiffness" in dict(e.params):
        return Effect(e.kind, e.joint, (("compliance", 1 / e.get("stiffness")),))
    if e.kind == "wrist" and any(k.startswith("rho") for k, _ in e.params):
        c = np.diag(wrist_compliance(arm))
        idx = {"45": (0, 1), "46": (0, 2), "56": (1, 2)}
        return Effect(e.kind, None, tuple(
            (f"c{k[3:]}", v * float(np.sqrt(c[idx[k[3:]][0]] * c[idx[k[3:]][1]])))
            for k, v in e.params))
    return e


def wrist_compliance(arm: ArmModel) -> np.ndarray:
    """(3, 3) joint-space torsion compliance of the last three joints [rad/(N m)]."""
    n = arm.chain.n_joints
    if arm.wrist_stiffness is not None:
        return np.linalg.inv(np.asarray(arm.wrist_stiffness, dtype=float))
    return np.diag([1.0 / arm.joints[j].torsion for j in range(n - 3, n)])


@dataclass(frozen=True)
class SignedLaw:
    """A law with a signed amplitude (fits may pass through negative values)."""

    law: object
    amplitude: float

    def deflection(self, tau):
        return self.amplitude * self.law.shape(tau)


def _signed(cls, amplitude: float, *args):
    return cls(amplitude, *args) if amplitude >= 0 else SignedLaw(cls(0.0, *args), amplitude)


def apply_effects(arm: ArmModel, effects) -> tuple[ArmModel, dict[int, list]]:
    """New arm with the linear effects, and the nonlinear laws per joint index."""
    joints = list(arm.joints)
    foundation = None if arm.foundation is None else np.array(arm.foundation, float)
    Cw = wrist_compliance(arm)
    wrist_changed = arm.wrist_stiffness is not None
    laws: dict[int, list] = {}
    n = arm.chain.n_joints
    for e in (resolve(e, arm) for e in effects):
        j = e.joint
        if e.kind == "stiffness":
            s = max(e.get("scale"), tol.min_compliance_scale)  # a fit may probe s <= 0
            joints[j] = replace(joints[j], torsion=joints[j].torsion / s)
            if j >= n - 3:
                k = j - (n - 3)
                Cw[k, :] *= np.sqrt(s)
                Cw[:, k] *= np.sqrt(s)
        elif e.kind == "backlash":
            laws.setdefault(j, []).append(_signed(Backlash, e.get("width")))
        elif e.kind == "hardening":
            laws.setdefault(j, []).append(Hardening(e.get("threshold"), e.get("extra")))
        elif e.kind == "hysteresis":
            laws.setdefault(j, []).append(_signed(Hysteresis, e.get("lost"), e.get("radius")))
        elif e.kind == "tilt":
            jt = joints[j]
            c1, c2 = (1.0 / jt.tilt + e.get("compliance"), 1.0 / jt.tilt_2 + e.get("compliance"))
            ok = c1 > 0 and c2 > 0  # a negative total compliance (during a fit) -> rigid
            joints[j] = replace(jt, tilt=1.0 / c1 if ok else np.inf,
                                tilt2=None if jt.tilt2 is None else (1.0 / c2 if ok else np.inf))
        elif e.kind == "base":
            c = e.get("compliance")
            if c <= 0:  # no foundation spring of negative compliance (a fit may probe one)
                continue
            Kf = np.diag([tol.rigid_foundation] * 3 + [1 / c, 1 / c, tol.rigid_foundation])
            foundation = Kf if foundation is None else np.linalg.inv(
                np.linalg.inv(foundation) + np.linalg.inv(Kf))
        elif e.kind == "wrist":
            for key, (a, b) in (("c45", (0, 1)), ("c46", (0, 2)), ("c56", (1, 2))):
                v = e.get(key, 0.0)
                Cw[a, b] += v
                Cw[b, a] += v
            wrist_changed = True
        # "links" changes the bodies: linkflex.links_arm, applied by the caller
    wrist = np.linalg.inv(Cw) if wrist_changed else None
    new = replace(arm, joints=tuple(joints), foundation=foundation, wrist_stiffness=wrist)
    new.__dict__.pop("_layout", None)
    return new, laws
