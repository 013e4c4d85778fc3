"""How named effects (:mod:`flexarm.robot.effects`) change an arm model.

:func:`apply_effects` turns an :class:`~flexarm.assembly.system.ArmModel` plus effects
into a new arm (the linear effects: torsion scale, bearing tilt, foundation, coupled
wrist) and a map joint -> nonlinear laws (:mod:`flexarm.assembly.nonlinear`).  The
``links`` effect changes the bodies and needs the flexible model
(:func:`~flexarm.assembly.linkflex.links_arm`); it is left to the caller.
"""

from __future__ import annotations

from dataclasses import dataclass, replace

import numpy as np

from ..robot.effects import Effect
from .nonlinear import Backlash, Hardening, Hysteresis
from .system import ArmModel
from .tolerances import tol

__all__ = ["apply_effects", "resolve", "wrist_compliance", "SignedLaw"]


def resolve(effect: Effect, arm: ArmModel) -> Effect:
    """Convert relative command-line parameters (ratios, stiffnesses) to the SI model form."""
    e = effect
    if e.kind == "hardening" and "ratio" in dict(e.params):
        k2 = arm.joints[e.joint].torsion
        return Effect(e.kind, e.joint, (("extra", 1 / (e.get("ratio") * k2) - 1 / k2),
                                        ("threshold", e.get("threshold"))))
    if e.kind in ("tilt", "base") and "stiffness" in dict(e.params):
        return Effect(e.kind, e.joint, (("compliance", 1 / e.get("stiffness")),))
    if e.kind == "wrist":
        return _wrist_couplings(e, wrist_compliance(arm))
    return e


def _wrist_couplings(e: Effect, Cw: np.ndarray) -> Effect:
    """A wrist effect given by correlations ``rho`` as couplings ``c = rho sqrt(c_i c_j)``
    of the wrist compliances ``Cw`` (3, 3) [rad/(N m)] it is applied to."""
    if not any(k.startswith("rho") for k, _ in e.params):
        return e
    c = np.diag(Cw)
    idx = {"45": (0, 1), "46": (0, 2), "56": (1, 2)}
    return Effect(e.kind, None, tuple(
        (f"c{k[3:]}", v * float(np.sqrt(c[idx[k[3:]][0]] * c[idx[k[3:]][1]])))
        for k, v in e.params))


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
    bodies = list(arm.bodies)
    foundation = None if arm.foundation is None else np.array(arm.foundation, float)
    Cw = wrist_compliance(arm)
    wrist_changed = arm.wrist_stiffness is not None
    laws: dict[int, list] = {}
    n = arm.chain.n_joints
    for e in effects:
        # a correlation is one of the compliances as they stand, after any scale before it
        e = _wrist_couplings(e, Cw) if e.kind == "wrist" else resolve(e, arm)
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
        elif e.kind == "foundation":
            c = np.array([e.get("cx", 0.0), e.get("cy", 0.0)])
            if not np.any(c > 0):
                continue
            k = np.where(c > 0, 1.0 / np.where(c > 0, c, 1.0), tol.rigid_foundation)
            Kf = np.diag([tol.rigid_foundation] * 3 + [k[0], k[1], tol.rigid_foundation])
            foundation = Kf if foundation is None else np.linalg.inv(
                np.linalg.inv(foundation) + np.linalg.inv(Kf))
        elif e.kind == "mass":
            bodies[j + 1] = with_added_mass(bodies[j + 1], e.get("mass"))
        elif e.kind == "wrist":
            for key, (a, b) in (("c45", (0, 1)), ("c46", (0, 2)), ("c56", (1, 2))):
                v = e.get(key, 0.0)
                Cw[a, b] += v
                Cw[b, a] += v
            wrist_changed = True
        # "links" changes the bodies: linkflex.links_arm, applied by the caller
    wrist = np.linalg.inv(Cw) if wrist_changed else None
    new = replace(arm, joints=tuple(joints), bodies=tuple(bodies), foundation=foundation,
                  wrist_stiffness=wrist)
    new.__dict__.pop("_layout", None)
    return new, laws


def at_pose(arm: ArmModel, effects, q) -> ArmModel:
    """``arm`` at joint angles ``q`` [rad] with the pose-dependent springs of ``effects``:
    a gravity balancer adds ``kc cos q_j + ks sin q_j`` [N m/rad] to its joint's gear
    stiffness (floored as in :func:`added_deflection`), which the arm's modes at that pose
    feel as its static deflections do.  ``arm`` itself when there are none."""
    bal = [e for e in effects if e.kind == "balancer"]
    if not bal:
        return arm
    q = np.asarray(q, dtype=float)
    joints = list(arm.joints)
    for e in bal:
        j = e.joint
        k = joints[j].torsion
        kb = e.get("kc") * np.cos(q[j]) + e.get("ks") * np.sin(q[j])
        joints[j] = replace(joints[j], torsion=float(max(k + kb, tol.min_compliance_scale * k)))
    new = replace(arm, joints=tuple(joints))
    new.__dict__.pop("_layout", None)
    return new


def body_centre_of_mass(body) -> np.ndarray:
    """Centre of mass [m] of ``body`` in its link frame, from its rigid-motion mass block at
    the proximal node (``M_rt = m skew(c - x0)``)."""
    M = np.asarray(body.M, float)[:6, :6]
    m = M[0, 0]
    S = M[3:6, 0:3] / m if m > 0 else np.zeros((3, 3))
    r = 0.5 * np.array([S[2, 1] - S[1, 2], S[0, 2] - S[2, 0], S[1, 0] - S[0, 1]])
    return np.asarray(body.node_positions, float)[0] + r


def with_added_mass(body, mass: float):
    """``body`` with a point ``mass`` [kg] at its centre of mass, moving with its proximal
    node (the rigid motion of a flexible body)."""
    if mass == 0 or body.M[0, 0] <= 0:
        return body
    x0 = np.asarray(body.node_positions, float)[0]
    r = body_centre_of_mass(body) - x0
    T = np.zeros((3, body.M.shape[0]))
    T[:, :3] = np.eye(3)
    T[:, 3:6] = -np.array([[0, -r[2], r[1]], [r[2], 0, -r[0]], [-r[1], r[0], 0]])
    return replace(body, M=np.asarray(body.M, float) + mass * T.T @ T)


#: Effects that add a TCP motion on top of the arm's compliance (not a change of the arm).
ADDED = ("tool", "balancer", "reflector")


def added_deflection(arm: ArmModel, effects, q, dforce, dtau) -> np.ndarray:
    """(n, 3) TCP translation [m] the ``tool`` and ``balancer`` effects add, base frame.

    ``q`` (n, n_joints) joint angles [rad], ``dforce`` (n, 3) TCP force change [N] (base
    frame) and ``dtau`` (n, n_joints) joint torque change [N m] since each series'
    reference reading; ``arm`` carries the gear stiffnesses the balancer works against.
    A tool compliance ``C`` (3, 3) [m/N] in the tool frame moves the TCP by
    ``R C R^T dF`` (``R`` the tool frame's orientation); a balancer of stiffness
    ``kb(q_j) = kc cos q_j + ks sin q_j`` in parallel with the gear ``k`` turns joint
    ``j`` by ``dtau (1 / (k + kb) - 1 / k)`` more, seen at the TCP through the Jacobian; a
    reflector at offset ``o`` [m] from the TCP (tool frame) moves by ``w x R o`` more, ``w``
    the TCP rotation the load change gives.

    Examples
    --------
    >>> from flexarm.assembly.examples import two_link_arm
    >>> arm = two_link_arm()
    >>> e = [Effect("tool", None, (("cxx", 1e-7), ("cyy", 1e-7), ("czz", 1e-7)))]
    >>> added_deflection(arm, e, [[0.0, 0.3]], [[0, 0, -100.0]], [[0.0, 0.0]]).round(9)
    array([[ 0.e+00,  0.e+00, -1.e-05]])
    """
    from ..robot.effects import TOOL_INDEX, TOOL_PARAMS
    from ..robot.kinematics import jacobian, tcp_frame

    q = np.atleast_2d(np.asarray(q, dtype=float))
    dforce = np.atleast_2d(np.asarray(dforce, dtype=float))
    dtau = np.atleast_2d(np.asarray(dtau, dtype=float))
    u = np.zeros((len(q), 3))
    tools = [e for e in effects if e.kind == "tool"]
    if tools:
        C = np.zeros((3, 3))
        for e in tools:
            for name, (a, b) in zip(TOOL_PARAMS, TOOL_INDEX, strict=True):
                C[a, b] += e.get(name, 0.0)
                C[b, a] = C[a, b]
        R = tcp_frame(arm.chain, q)[:, :3, :3]
        u += np.einsum("nij,jk,nlk,nl->ni", R, C, R, dforce)
    offsets = [e for e in effects if e.kind == "reflector"]
    if offsets:
        from .analyses import tcp_compliance

        o = sum(np.array([e.get("ox", 0.0), e.get("oy", 0.0), e.get("oz", 0.0)])
                for e in offsets)
        T = tcp_frame(arm.chain, q)
        uq, inv = np.unique(q, axis=0, return_inverse=True)
        Crot = tcp_compliance(arm, uq)[inv.ravel(), 3:6, :3]
        w = np.einsum("nij,nj->ni", Crot, dforce)  # TCP rotation the load change gives
        u += np.cross(w, np.einsum("nij,j->ni", T[:, :3, :3], o))
    bal = [e for e in effects if e.kind == "balancer"]
    if bal:
        J = jacobian(arm.chain, q)[:, :3, :]
        for e in bal:
            j = e.joint
            k = arm.joints[j].torsion
            kb = e.get("kc") * np.cos(q[:, j]) + e.get("ks") * np.sin(q[:, j])
            dc = 1.0 / np.maximum(k + kb, tol.min_compliance_scale * k) - 1.0 / k
            u += J[:, :, j] * (dtau[:, j] * dc)[:, None]
    return u


def measured(effects, u) -> np.ndarray:
    """(n, 3) TCP motions ``u`` [m] as a tracker whose frame is off by the ``frame``
    effects sees them: ``(1 + scale) (u + r x u)`` for a small rotation vector ``r`` [rad];
    a ``loadcell`` that reads ``1 + scale`` times the true force divides them by it (the
    file's forces, which the model is given, are that much too large).

    Examples
    --------
    >>> e = [Effect("frame", None, (("rz", 0.01), ("scale", 0.0)))]
    >>> measured(e, [[1.0, 0.0, 0.0]]).round(6)
    array([[1.  , 0.01, 0.  ]])
    """
    u = np.asarray(u, dtype=float)
    for e in effects:
        if e.kind == "loadcell":  # the stated force is 1 + scale times the true one
            u = u / (1.0 + e.get("scale"))
        if e.kind == "frame":
            r = np.array([e.get("rx", 0.0), e.get("ry", 0.0), e.get("rz", 0.0)])
            u = (1.0 + e.get("scale", 0.0)) * (u + np.cross(r, u))
    return u


__all__ += ["ADDED", "added_deflection", "measured", "at_pose", "body_centre_of_mass",
            "with_added_mass"]
