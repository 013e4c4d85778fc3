"""Whether a refitted candidate's values are physical: the last of the acceptance checks.

A fit keeps compliances and masses above zero by construction
(:func:`~flexarm.robot.effects.lower_bound`); these rules add what a bound cannot say:

* joint laws: a backlash or lost motion above zero and below ``tol.max_backlash``;
* tool/adapter compliance: a positive semi-definite 3x3 matrix (a negative direction
  would be a spring that pushes back);
* coupled wrist: the wrist's compliance with the couplings stays positive definite;
* gravity balancer: its stiffness ``kc cos q + ks sin q`` at every measured angle at most
  ``tol.max_balancer_share`` of the joint's gear stiffness (a spring balancer carries the
  arm's weight; it does not double the gear);
* measurement frame: rotations below ``tol.max_frame_error``; load cell: a scale within
  ``tol.max_force_scale``; reflector: within ``tol.max_reflector_offset`` of the TCP;
* added mass: at most ``tol.max_added_mass_share`` of the arm's moving mass;
* link flexibility: a factor between 0 and ``tol.max_link_compliance``.
"""

from __future__ import annotations

import numpy as np

from ...assembly.effects import wrist_compliance
from ...robot.effects import TOOL_INDEX, TOOL_PARAMS, Effect
from ..static.fit import Problem
from ..tolerances import tol

__all__ = ["plausible"]


def plausible(problem: Problem, effect: Effect, amplitudes) -> bool:
    """Whether the fitted ``effect`` (its free ``amplitudes`` named) is physical."""
    kind = effect.kind
    v = np.array([effect.get(a) for a in amplitudes], float)
    if kind == "links":
        return bool(np.all(v > 0) and np.all(v < tol.max_link_compliance))
    if kind in ("backlash", "hysteresis"):
        return bool(np.all(v > 0) and np.all(v < tol.max_backlash))
    if kind == "tool":
        C = np.zeros((3, 3))
        for name, (a, b) in zip(TOOL_PARAMS, TOOL_INDEX, strict=True):
            C[a, b] = C[b, a] = effect.get(name, 0.0)
        ev = np.linalg.eigvalsh(C)
        return bool(ev.max() > 0 and ev.min() >= -1e-3 * ev.max())
    if kind == "wrist":
        Cw = wrist_compliance(problem.arm)
        for key, (a, b) in (("c45", (0, 1)), ("c46", (0, 2)), ("c56", (1, 2))):
            Cw[a, b] += effect.get(key, 0.0)
            Cw[b, a] += effect.get(key, 0.0)
        return bool(np.linalg.eigvalsh(Cw).min() > 0)
    if kind == "balancer":
        q = problem.data.q[:, effect.joint]
        kb = effect.get("kc") * np.cos(q) + effect.get("ks") * np.sin(q)
        k = problem.arm.joints[effect.joint].torsion
        return bool(np.abs(kb).max() <= tol.max_balancer_share * k)
    if kind == "frame":
        return bool(np.all(np.abs(v) < tol.max_frame_error))
    if kind == "loadcell":
        return bool(np.all(np.abs(v) <= tol.max_force_scale))
    if kind == "reflector":
        return bool(np.linalg.norm(v) <= tol.max_reflector_offset)
    if kind == "mass":
        moving = sum(float(b.M[0, 0]) for b in problem.arm.bodies[1:])
        return bool(np.all(v > 0) and v.sum() <= tol.max_added_mass_share * moving)
    if kind == "foundation":
        return bool(np.all(v >= 0) and np.any(v > 0))
    return bool(np.all(v > 0))
