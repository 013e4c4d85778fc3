"""Consistency checks of a robot description (:class:`~flexarm.robot.description.Robot`
runs them when it is made): every error is a ``ValueError`` naming the key and value."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np

from ..fe.typing import FloatArray
from ..fe.units import LENGTH_UNITS
from .link_checks import check_link_density
from .tolerances import tol

__all__ = ["validate"]

_UNIT_TOL = 1e-6  # |axis| must be 1 to this (a description error, not round-off)


def _vec(value, n: int, key: str) -> FloatArray:
    a = np.asarray(value, dtype=float)
    if a.shape != (n,):
        raise ValueError(f"{key} must have {n} numbers, got {value!r}")
    if not np.all(np.isfinite(a)):
        raise ValueError(f"{key} must be finite, got {value!r}")
    return a



def validate(robot) -> None:
    """Raise ``ValueError`` naming key and value for anything inconsistent."""
    from ..meshes import MESHER_SETTINGS

    if robot.options.mesher not in MESHER_SETTINGS:
        raise ValueError(f"model.mesher must be one of {', '.join(MESHER_SETTINGS)}, "
                         f"got '{robot.options.mesher}'")
    _validate_options(robot.options)
    names = [lk.name for lk in robot.links]
    _validate_unique(names, "links")
    _validate_unique([j.name for j in robot.joints], "joints")
    if len(robot.joints) != len(robot.links) - 1:
        raise ValueError(f"{len(robot.links)} links need {len(robot.links) - 1} joints, "
                         f"got {len(robot.joints)}")
    for lk in robot.links:
        _validate_link(lk)
    _validate_joints(robot.joints, names)
    _vec(robot.tool.xyz, 3, "tool.xyz")
    _vec([math.degrees(float(v)) for v in robot.tool.rpy], 3, "tool.rpy_deg")
    if robot.tool.link is not None and robot.tool.link not in names:
        raise ValueError(f"tool.link: unknown link '{robot.tool.link}'")
    _validate_base_and_wrist(robot)
    _validate_poses(robot)
    _validate_effects(robot)
    _validate_modal_damping(robot)


def _validate_unique(names: list[str], what: str) -> None:
    seen = set()
    for name in names:
        if name in seen:
            raise ValueError(f"{what}: duplicate name '{name}' (names must be unique)")
        seen.add(name)


def _validate_options(opts) -> None:
    if opts.element_order not in (1, 2):
        raise ValueError(f"model.element_order must be 1 (Tet4) or 2 (Tet10), "
                         f"got {opts.element_order}")
    if not (math.isfinite(opts.mesh_size) and opts.mesh_size > 0):
        raise ValueError(f"model.mesh_size must be a positive edge length [m], "
                         f"got {opts.mesh_size}")
    if opts.cb_modes < 0:
        raise ValueError(f"model.cb_modes must be >= 0, got {opts.cb_modes}")


def _validate_link(lk) -> None:
    if lk.units not in LENGTH_UNITS:
        raise ValueError(f"links.{lk.name}.units: unknown unit '{lk.units}' "
                         f"(use {'|'.join(LENGTH_UNITS)})")
    if lk.mesh is not None and not Path(lk.mesh).is_file():
        raise ValueError(f"links.{lk.name}.mesh: file not found: '{lk.mesh}'")
    check_link_density(lk)
    for m in lk.lumped:
        if not m.mass >= 0:
            raise ValueError(f"links.{lk.name}.lumped.{m.name}.mass must be >= 0 kg, "
                             f"got {m.mass}")
        if not m.mass <= tol.lumped_mass_max:
            raise ValueError(f"links.{lk.name}.lumped.{m.name}.mass: {m.mass:g} kg is not a "
                             f"plausible lumped mass (at most {tol.lumped_mass_max:g} kg)")
    for rname, reg in lk.regions.items():
        key = f"links.{lk.name}.regions.{rname}"
        if abs(np.linalg.norm(reg.axis) - 1) > _UNIT_TOL:
            raise ValueError(f"{key}.axis must be a unit vector, got {list(reg.axis)}")
        if not 0 <= reg.r_min <= reg.r_max or not reg.half_width > 0:
            raise ValueError(f"{key}: need 0 <= r_min <= r_max and half_width > 0, got "
                             f"r_min={reg.r_min}, r_max={reg.r_max}, "
                             f"half_width={reg.half_width}")
        if reg.coupling not in ("rbe2", "rbe3"):
            raise ValueError(f"{key}.coupling must be rbe2|rbe3, got '{reg.coupling}'")


def _validate_joints(joints, names: list[str]) -> None:
    seen = {names[0]}
    for j, jt in enumerate(joints):
        key = f"joints.{jt.name}"
        if jt.parent not in names:
            raise ValueError(f"{key}.parent: unknown link '{jt.parent}'")
        if jt.child not in names:
            raise ValueError(f"{key}.child: unknown link '{jt.child}'")
        if jt.child != names[j + 1]:
            raise ValueError(f"{key}.child must be '{names[j + 1]}' (links in joint order), "
                             f"got '{jt.child}'")
        if jt.parent not in seen:
            raise ValueError(f"{key}.parent '{jt.parent}' must come before its child")
        seen.add(jt.child)
        _vec(jt.origin, 3, f"{key}.origin")
        _vec([math.degrees(float(v)) for v in jt.rpy], 3, f"{key}.rpy_deg")
        if abs(np.linalg.norm(_vec(jt.axis, 3, f"{key}.axis")) - 1) > _UNIT_TOL:
            raise ValueError(f"{key}.axis must be a unit vector, got {list(jt.axis)}")
        if not (math.isfinite(jt.lower) and math.isfinite(jt.upper)):
            raise ValueError(f"{key}.limits must be finite, got [{math.degrees(jt.lower):g}, "
                             f"{math.degrees(jt.upper):g}] deg")
        if not jt.lower < jt.upper:
            raise ValueError(f"{key}.limits reversed: lower {math.degrees(jt.lower):g} deg >= "
                             f"upper {math.degrees(jt.upper):g} deg")
        if not jt.gear_ratio != 0:
            raise ValueError(f"{key}.gear_ratio must be nonzero, got {jt.gear_ratio}")


def _validate_base_and_wrist(robot) -> None:
    if robot.base.kind not in ("clamped", "spring"):
        raise ValueError(f"base.support must be clamped|spring, got '{robot.base.kind}'")
    if not 0 <= robot.base.damping_ratio < 1:
        raise ValueError(f"base.damping_ratio must be in [0, 1), got {robot.base.damping_ratio}")
    if robot.base.kind == "spring":
        K = np.asarray(robot.base.stiffness, dtype=float)
        if K.shape != (6, 6) or not np.allclose(K, K.T) or np.linalg.eigvalsh(K).min() <= 0:
            raise ValueError("base.stiffness must be a symmetric positive definite 6x6 matrix")
    if robot.wrist_stiffness is not None:
        W = np.asarray(robot.wrist_stiffness, dtype=float)
        if W.shape != (3, 3) or not np.allclose(W, W.T) or np.linalg.eigvalsh(W).min() <= 0:
            raise ValueError("wrist.stiffness must be a symmetric positive definite 3x3 matrix")
    if robot.wrist_coupling is not None:
        Cw = np.asarray(robot.wrist_coupling, dtype=float)
        if Cw.shape != (3, 3):
            raise ValueError("wrist.coupling must be a 3x3 matrix")
        if not np.all(np.isfinite(Cw)) or abs(np.linalg.det(Cw)) < 1e-9:
            # motor_to_joint inverts it; C^T diag(k) C would not be positive definite
            raise ValueError("wrist.coupling must be an invertible 3x3 matrix")


def _validate_poses(robot) -> None:
    lo, hi = robot.lower, robot.upper
    for pname, q in robot.poses.items():
        q = np.asarray(q, dtype=float)
        if q.shape != lo.shape:
            raise ValueError(f"poses.{pname} must have {len(lo)} angles, got {len(q)}")
        bad = np.flatnonzero((q < lo) | (q > hi))
        if bad.size:
            j = int(bad[0])
            raise ValueError(f"poses.{pname}: {robot.joints[j].name} = {math.degrees(q[j]):g} "
                             f"deg outside limits [{math.degrees(lo[j]):g}, "
                             f"{math.degrees(hi[j]):g}] deg")


def _validate_modal_damping(robot) -> None:
    """``modal_damping``: pose name -> (frequencies [Hz], damping ratios [-]) identified
    at that named pose, equally long, f > 0 and 0 <= zeta < 1."""
    for pname, (freq, zeta) in robot.modal_damping.items():
        where = f"modal_damping.{pname}"
        if pname not in robot.poses:
            raise ValueError(f"{where}: no pose '{pname}' in [poses]")
        if len(freq) != len(zeta):
            raise ValueError(f"{where}: {len(freq)} freq_hz but {len(zeta)} zeta")
        if not all(f > 0 for f in freq):
            raise ValueError(f"{where}.freq_hz must be > 0, got {list(freq)}")
        if not all(0 <= z < 1 for z in zeta):
            raise ValueError(f"{where}.zeta must lie in [0, 1), got {list(zeta)}")


def _validate_effects(robot) -> None:
    from .effects import NONLINEAR, STORED

    for e in robot.effects:
        if e.kind in STORED:
            if e.joint is not None and not 0 <= e.joint < len(robot.joints):
                raise ValueError(f"effects: {e.label} names no joint of the robot")
            if not all(math.isfinite(v) for _, v in e.params):
                raise ValueError(f"effects: {e.label} has a non-finite parameter")
            continue
        if e.kind not in NONLINEAR or e.joint is None or not 0 <= e.joint < len(robot.joints):
            raise ValueError(f"nonlinear: a robot carries joint laws of kind "
                             f"{'|'.join(NONLINEAR)} on one of its joints, got {e.label}")
        for name, value in e.params:
            # a negative dead band or radius has no physical meaning; the radius divides
            if not (math.isfinite(value) and value >= 0) or (name == "radius" and value == 0):
                raise ValueError(f"nonlinear.{robot.joints[e.joint].name}: {e.kind} {name} "
                                 f"must be {'> 0' if name == 'radius' else '>= 0'}, "
                                 f"got {value:g}")
