"""The 2-DOF machining-plane structure of :func:`.chatter.plane_model` at many poses at once.

Same definitions as :func:`~flexarm.studies.contact.chatter.plane_model` (condensed
static stiffness ``K = (P^T C P)^-1``; mass and damping from the two dominant modes),
but every step is batched over the poses: one batched assembly
(:func:`~flexarm.assembly.system.system_matrices`), one batched generalized
eigen-solve ``K phi = omega^2 M phi`` of the small assembled system (Cholesky of
``M``, then a symmetric ``eigh``), and the modal damping ratios (joint damping weighted
by each mode's strain-energy share, as in :func:`~flexarm.assembly.analyses.modes`)
for the two chosen modes only.  Used by :func:`.chatter_map.chatter_map`.
"""

from __future__ import annotations

import logging

import numpy as np

from ...assembly.analyses import tcp_compliance
from ...assembly.system import ArmModel, system_matrices
from ...fe.typing import ArrayLike, FloatArray
from ...robot.kinematics import tcp_frame
from ..tolerances import tol

__all__ = ["plane_axes_batched", "plane_matrices"]

log = logging.getLogger(__name__)


def plane_axes_batched(tool_axis: ArrayLike) -> FloatArray:
    """(..., 2, 3) axes of the planes normal to ``tool_axis`` (..., 3) (batched ``plane_axes``).

    ``e1`` is base y projected on the plane (base x where y is within ~6 deg of the
    tool axis), ``e2 = t x e1``.

    Examples
    --------
    >>> plane_axes_batched([[1.0, 0, 0], [0, 1.0, 0]]).round(3).tolist()[1][0]
    [1.0, 0.0, 0.0]
    """
    t = np.asarray(tool_axis, dtype=float)
    t = t / np.linalg.norm(t, axis=-1, keepdims=True)
    ey, ex = np.eye(3)[1], np.eye(3)[0]
    e1 = ey - t[..., 1:2] * t
    use_x = np.linalg.norm(e1, axis=-1, keepdims=True) <= 0.1
    e1 = np.where(use_x, ex - t[..., 0:1] * t, e1)
    e1 = e1 / np.linalg.norm(e1, axis=-1, keepdims=True)
    return np.stack([e1, np.cross(t, e1)], axis=-2)


def _modal_damping(arm: ArmModel, Phi: FloatArray, K: FloatArray,
                   omega: FloatArray) -> FloatArray:
    """(..., r) damping ratios of the mode shapes ``Phi`` (..., n_x, r) (strain-energy shares)."""
    lay = arm.layout
    Ks = arm.spring_stiffness()
    e = Phi * (Ks @ Phi)
    total = np.maximum(np.einsum("...ir,...ir->...r", Phi, K @ Phi), np.finfo(float).tiny)
    zeta = np.zeros_like(omega)
    shared = np.zeros_like(omega)
    for jm, idx in zip(arm.joints, lay["joint"], strict=True):
        share = e[..., idx, :].sum(axis=-2) / total
        zeta = zeta + share * jm.ratio(omega)
        shared = shared + share
    if arm.foundation is not None:
        share = e[..., lay["foundation"], :].sum(axis=-2) / total
        zeta = zeta + share * arm.foundation_damping
        shared = shared + share
    flexible = [b.damping_ratio for b in arm.bodies if not b.is_rigid]
    if flexible:
        zeta = zeta + np.clip(1 - shared, 0, None) * float(np.mean(flexible))
    return zeta


def plane_matrices(arm: ArmModel, q: ArrayLike, axes: ArrayLike | None = None,
                   chunk: int = 400) -> tuple[FloatArray, FloatArray, FloatArray, FloatArray]:
    """Effective ``M, C, K`` (..., 2, 2) and plane axes (..., 2, 3) at poses ``q`` (..., 6).

    Parameters
    ----------
    arm : ArmModel
    q : (..., 6) float
        Poses [rad].
    axes : (2, 3) float, optional
        A fixed machining plane; default: normal to the tool axis at each pose.
    chunk : int
        Poses per batched assembly (bounds the memory).

    Examples
    --------
    >>> from flexarm.robot.demo_arm import load_demo_robot
    >>> from flexarm.assembly import emodel
    >>> r = load_demo_robot()
    >>> M, C, K, P = plane_matrices(emodel(r, method="surface"), [r.pose("P1"), r.pose("P2")])
    >>> M.shape, bool(np.linalg.eigvalsh(K)[0, 0] < 2e5)
    ((2, 2, 2), True)
    """
    q = np.asarray(q, dtype=float)
    batch = q.shape[:-1]
    Q = q.reshape(-1, q.shape[-1])
    n = len(Q)
    log.info("plane matrices: %d poses", n)
    if axes is None:
        P = plane_axes_batched(tcp_frame(arm.chain, Q)[:, :3, 2])
    else:
        P = np.broadcast_to(np.asarray(axes, dtype=float).reshape(2, 3), (n, 2, 3))
        if np.abs(P[0] @ P[0].T - np.eye(2)).max() > tol.plane_orthonormal:
            raise ValueError("plane axes must be orthonormal (2, 3)")
    out = np.zeros((3, n, 2, 2))
    tiny = np.finfo(float).tiny
    for a in range(0, n, chunk):
        s = slice(a, min(a + chunk, n))
        Ps = P[s]
        C3 = tcp_compliance(arm, Q[s])[:, :3, :3]
        out[2, s] = np.linalg.inv(Ps @ C3 @ np.swapaxes(Ps, -1, -2))
        sm = system_matrices(arm, Q[s])
        Linv = np.linalg.inv(np.linalg.cholesky(sm.M))
        A = Linv @ sm.K @ np.swapaxes(Linv, -1, -2)
        lam, Y = np.linalg.eigh(0.5 * (A + np.swapaxes(A, -1, -2)))
        Phi = np.swapaxes(Linv, -1, -2) @ Y  # mass-normalised
        w = np.maximum(np.sqrt(np.clip(lam, 0.0, None)), tiny)
        psi = Ps @ (sm.G_tcp[:, :3, :] @ Phi)  # (m, 2, n_x) in-plane modal displacements
        r1 = np.argmax(np.sum(psi**2, axis=1) / w**2, axis=1)
        rows = np.arange(len(psi))
        p1 = psi[rows, :, r1]
        d1 = p1 / np.linalg.norm(p1, axis=1, keepdims=True)
        across = (psi[:, 0] * d1[:, 1:2] - psi[:, 1] * d1[:, 0:1]) ** 2 / w**2
        across[rows, r1] = -1.0
        r = np.stack([r1, np.argmax(across, axis=1)], axis=1)  # (m, 2)
        Psi = np.take_along_axis(psi, r[:, None, :], axis=2)
        Phi_r = np.take_along_axis(Phi, r[:, None, :], axis=2)
        w_r = np.take_along_axis(w, r, axis=1)
        zeta = _modal_damping(arm, Phi_r, sm.K, w_r)
        Pinv = np.linalg.inv(Psi)
        PinvT = np.swapaxes(Pinv, -1, -2)
        out[0, s] = PinvT @ Pinv
        out[1, s] = PinvT @ ((2 * zeta * w_r)[:, :, None] * Pinv)
    out = 0.5 * (out + np.swapaxes(out, -1, -2))
    log.info("plane matrices done")
    shape = batch + (2, 2)
    return (out[0].reshape(shape), out[1].reshape(shape), out[2].reshape(shape),
            P.reshape(batch + (2, 3)))
