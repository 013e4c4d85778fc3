"""Static equilibrium with gravity preload and a TCP load, relative to a reference reading.

In a tree of bodies the load carried by each joint is statically determinate: the
moment about joint ``j``'s point is the moment of everything distal to it (gravity
of the distal bodies plus the external TCP wrench).  :func:`joint_moments` computes
it exactly from the kinematics and the bodies' mass properties, for rigid *and*
flexible bodies (small-deflection theory: loads act on the undeformed geometry).

The linear response is ``u = C(q) w`` with the TCP compliance of the arm model
(:func:`~flexarm.assembly.analyses.tcp_compliance`, which already includes the
foundation, bearings, coupled wrist and link flexibility).  A nonlinear joint law adds
an extra joint rotation ``delta_j(tau_j history)``; since the joint loads do not change
when a joint turns by a prescribed amount, the distal bodies follow it rigidly and the
TCP moves by ``J_j delta_j`` (the Jacobian column).  This is the exact solution of the
reduced equilibrium equations (what a Newton iteration would converge to), obtained
without iterating.  Gravity cancels in the linear part of a *relative* measurement but
sets the operating point of the nonlinear laws.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence

import numpy as np

from ..fe.typing import ArrayLike, FloatArray, IntArray
from ..robot.joints import joint_basis
from ..robot.kinematics import jacobian, link_frames, tcp_frame
from .analyses import GRAVITY, tcp_compliance
from .system import ArmModel

__all__ = ["body_masses", "joint_moments", "joint_screws", "relative_deflection",
           "series_starts", "distinct_poses"]


def body_masses(arm: ArmModel) -> tuple[FloatArray, FloatArray]:
    """Mass [kg] and centre of mass [m] (link frame) of every body.

    Uses the body's rigid-body modes (six-DOF nodes moving rigidly with node 0, modal
    coordinates zero), exact for rigid bodies and Craig-Bampton superelements.

    Returns
    -------
    mass : (n_bodies,) float
    com : (n_bodies, 3) float
    """
    masses, coms = [], []
    for b in arm.bodies:
        Phi = np.zeros((b.n_dofs, 6))
        r0 = b.node_positions[0]
        for k, r in enumerate(b.node_positions):
            d = r - r0
            Phi[6 * k : 6 * k + 3, :3] = np.eye(3)
            Phi[6 * k : 6 * k + 3, 3:] = -np.array([[0, -d[2], d[1]], [d[2], 0, -d[0]],
                                                    [-d[1], d[0], 0]])
            Phi[6 * k + 3 : 6 * k + 6, 3:] = np.eye(3)
        Mr = Phi.T @ b.M @ Phi
        m = float(Mr[0, 0])
        # M_r[:3, 3:] = -m S(c - r0)  ->  c - r0 from the skew block
        S = -Mr[:3, 3:] / max(m, np.finfo(float).tiny)
        masses.append(m)
        coms.append(r0 + np.array([S[2, 1], S[0, 2], S[1, 0]]))
    return np.array(masses), np.array(coms)


def _distal(arm: ArmModel) -> FloatArray:
    """(n_joints, n_bodies) 1 where the body is distal to (carried by) the joint."""
    n = arm.chain.n_joints
    D = np.zeros((n, n + 1))
    for i in range(1, n + 1):
        D[arm.chain.ancestors(i), i] = 1.0
    return D


def joint_screws(arm: ArmModel, q: ArrayLike) -> FloatArray:
    """TCP motion per unit rotation about each joint's three axes (*batched*).

    Returns
    -------
    (..., n_joints, 3, 6) float
        For joint ``j`` and axis ``a`` of its joint basis (axis, radial1, radial2):
        TCP (translation [m], rotation [rad]) in the base frame per radian.  Axis 0 is
        the Jacobian column.  Zero for joints that do not carry the TCP.
    """
    chain = arm.chain
    F = link_frames(chain, q)
    p_tcp = tcp_frame(chain, q, F)[..., :3, 3]
    S = np.zeros(F.shape[:-3] + (chain.n_joints, 3, 6))
    for j in chain.ancestors(chain.tcp_body):
        E = F[..., j + 1, :3, :3] @ joint_basis(chain.axes[j])  # (..., 3, 3) columns = axes
        r = p_tcp - F[..., j + 1, :3, 3]
        for a in range(3):
            e = E[..., :, a]
            S[..., j, a, :3] = np.cross(e, r)
            S[..., j, a, 3:] = e
    return S


def joint_moments(arm: ArmModel, q: ArrayLike, force: ArrayLike,
                  moment: ArrayLike | None = None, gravity: bool = True,
                  extra_masses: Sequence[tuple[int, float, ArrayLike]] = (),
                  pose_index: ArrayLike | None = None) -> FloatArray:
    """Moment carried by each joint, in its joint basis (*batched*, statically exact).

    Parameters
    ----------
    arm : ArmModel
    q : (..., n) float
        Joint angles [rad].
    force, moment : (..., 3) float
        External load on the TCP, base frame [N], [N m].
    gravity : bool
        Include the weight of the bodies (gravity along -z of the base frame).
    extra_masses : sequence of (body, mass [kg], position (3,) [m] in the link frame)
        Point masses added to bodies (e.g. a payload).
    pose_index : (m,) int, optional
        Load ``r`` (``force`` and ``moment`` (m, 3)) acts at pose ``q[pose_index[r]]``, ``q``
        (p, n) holding the distinct poses (:func:`distinct_poses`): the kinematics are
        computed once per pose, and the moments are bit for bit those of ``q`` repeated.

    Returns
    -------
    (..., n_joints, 3) float
        Moment about joint ``j``'s point of all loads distal to it [N m], projected on
        (axis, radial1, radial2): index 0 is the torque the gear carries.  Sign: the
        torque the distal part exerts, so that the joint rotates by ``+tau / k``.
    """
    chain = arm.chain
    q = np.asarray(q, dtype=float)
    F = link_frames(chain, q)
    p_tcp = tcp_frame(chain, q, F)[..., :3, 3]

    def at(a):  # per pose -> per load
        return a if pose_index is None else a[pose_index]

    shape = at(p_tcp).shape
    force = np.broadcast_to(np.asarray(force, dtype=float), shape)
    mom = np.zeros(shape) if moment is None else np.broadcast_to(moment, shape)
    m, c = body_masses(arm)
    pts = [(i, float(m[i]), c[i]) for i in range(len(m))] if gravity else []
    pts += [(int(b), float(mm), np.asarray(p, float)) for b, mm, p in extra_masses]
    D = _distal(arm)
    out = np.zeros(shape[:-1] + (chain.n_joints, 3))
    carriers = set(chain.ancestors(chain.tcp_body))
    for j in range(chain.n_joints):
        pj = F[..., j + 1, :3, 3]
        M = mom + np.cross(at(p_tcp - pj), force) if j in carriers else np.zeros(shape)
        for i, mi, ci in pts:
            if D[j, i]:
                ci_b = F[..., i, :3, :3] @ ci + F[..., i, :3, 3]
                M = M + at(np.cross(ci_b - pj, mi * GRAVITY))
        E = F[..., j + 1, :3, :3] @ joint_basis(chain.axes[j])
        out[..., j, :] = np.einsum("...ia,...i->...a", at(E), M)
    return out


def distinct_poses(q: ArrayLike) -> tuple[FloatArray, IntArray]:
    """The distinct rows of ``q`` (n, k) and the index of each row among them, as
    ``np.unique(q, axis=0, return_inverse=True)`` gives them, fast when equal rows come in
    runs (a static series holds one pose over its readings).

    Examples
    --------
    >>> uq, inv = distinct_poses([[0, 1.0], [0, 1.0], [0, 0.5], [0, 1.0]])
    >>> uq.tolist(), inv.tolist()
    ([[0.0, 0.5], [0.0, 1.0]], [1, 1, 0, 1])
    """
    q = np.asarray(q, dtype=float)
    new = np.ones(len(q), bool)
    new[1:] = np.any(q[1:] != q[:-1], axis=1)
    uq, inverse = np.unique(q[new], axis=0, return_inverse=True)
    return uq, np.repeat(inverse.ravel(), np.diff(np.r_[np.flatnonzero(new), len(q)]))


def series_starts(series: ArrayLike) -> np.ndarray:
    """(n,) int: index of the reference (first) row of each row's series."""
    s = np.asarray(series)
    new = np.r_[True, s[1:] != s[:-1]] if len(s) else np.zeros(0, bool)
    starts = np.flatnonzero(new)
    return starts[np.cumsum(new) - 1]


def relative_deflection(arm: ArmModel, q: ArrayLike, force: ArrayLike,
                        moment: ArrayLike | None, series: ArrayLike,
                        laws: Mapping[int, Sequence] | None = None) -> FloatArray:
    """TCP translation [m] of each reading relative to its series' first reading.

    Parameters
    ----------
    arm : ArmModel
        Any arm model (rigid or flexible links, foundation, coupled wrist).
    q : (n, n_joints) float
        Joint angles [rad] of each reading.
    force, moment : (n, 3) float or None
        TCP load per reading, base frame [N], [N m].
    series : (n,) labels
        Series of each reading; rows of a series are contiguous, in load order.
    laws : mapping joint index -> sequence of nonlinear laws, optional
        Extra joint deflections driven by the total joint torque history.

    Returns
    -------
    (n, 3) float
        ``u(q, w_k) - u(q, w_ref)`` in the base frame [m].

    Examples
    --------
    >>> from flexarm.assembly.examples import two_link_arm
    >>> arm = two_link_arm()
    >>> d = relative_deflection(arm, [[0, 0.3]] * 2, [[0, 0, 0], [0, 0, -100.0]], None, ["a", "a"])
    >>> d.shape, bool(d[0].any())
    ((2, 3), False)
    """
    q = np.asarray(q, dtype=float)
    force = np.asarray(force, dtype=float)
    n = len(q)
    w = np.zeros((n, 6))
    w[:, :3] = force
    if moment is not None:
        w[:, 3:] = moment
    ref = series_starts(series)
    dw = w - w[ref]
    # one compliance per distinct pose (the lab holds the pose within a series)
    uq, inv = np.unique(q, axis=0, return_inverse=True)
    C = tcp_compliance(arm, uq)
    u = np.einsum("nij,nj->ni", C[inv.ravel(), :3, :], dw)
    if laws:
        tau = joint_moments(arm, q, force, moment)[:, :, 0]
        J = jacobian(arm.chain, q)[:, :3, :]
        for j, js in laws.items():
            extra = np.zeros(n)
            for start in np.unique(ref):
                rows = np.flatnonzero(ref == start)
                for law in js:
                    extra[rows] += law.deflection(tau[rows, j])
            extra = extra - extra[ref]
            u += J[:, :, j] * extra[:, None]
    return u
