"""Fast many-pose paths for arms whose assembled stiffness does not depend on the pose.

What depends on the pose ``q`` in :func:`~flexarm.assembly.system.system_matrices`?
Each body's DOFs are the motion of its proximal node (six, rotated into the base
frame by ``blockdiag(R_i, R_i)``) followed by link-frame quantities that do not
rotate (the floating-frame elastic coordinates of
:func:`~flexarm.assembly.flexible.body_coordinates`).  A body's ``K`` is exactly zero
on its six rigid coordinates (rigid bodies: ``K = 0``), so the rotation never meets a
non-zero entry of ``K``, and the rows of ``T`` that depend on ``q`` (the proximal
motion) multiply zero rows of ``K``.  The joint springs act on the joint coordinates
(joint frame), the foundation on base-frame coordinates.  Hence

    ``K(q) = K_springs + blockdiag(K_i[6:, 6:])``        (exactly, every pose)

and only the TCP map ``G_tcp(q)`` and the mass matrix ``M(q)`` change with ``q``.
The TCP compliance is then ``C(q) = G(q) K^-1 G(q)^T`` with ``K^-1`` restricted once
to the few coordinates the TCP map can touch (foundation, joint coordinates on the
path to the TCP body, and the elastic coordinates of the interface nodes that carry
the next joint on that path): a small dense product per pose instead of an
assembly and a solve.  :func:`has_constant_stiffness` tells when this holds.
"""

from __future__ import annotations

import numpy as np
import scipy.linalg as sla

from ..fe.threads import one_blas_thread
from ..fe.typing import ArrayLike, FloatArray
from ..robot.joints import joint_basis
from ..robot.kinematics import link_frames
from .bodies import rigid_transport
from .system import ArmModel, _joint_tcp_columns, rotation_blocks

#: Poses per block of :func:`fast_tcp_compliance` (the block's TCP maps fit in cache).
POSE_CHUNK = 512

__all__ = [
    "has_constant_stiffness",
    "constant_stiffness",
    "tcp_support",
    "tcp_map",
    "fast_tcp_compliance",
    "mass_matrix",
]


def _cached(arm: ArmModel, key: str, make):
    """Per-arm cache (``ArmModel`` is frozen; its layout is cached the same way)."""
    if key not in arm.__dict__:
        arm.__dict__[key] = make()
    return arm.__dict__[key]


def has_constant_stiffness(arm: ArmModel) -> bool:
    """True when every body has one rotating node and ``K`` zero on its six rigid DOFs."""
    return _cached(arm, "_constant_stiffness", lambda: all(
        b.n_nodes == 1 and not np.any(b.K[:6]) and not np.any(b.K[:, :6]) for b in arm.bodies))


def constant_stiffness(arm: ArmModel) -> FloatArray:
    """(n_x, n_x) the pose-independent ``K`` [N/m, N m/rad] (see the module notes).

    Examples
    --------
    >>> from flexarm.assembly.examples import two_link_arm
    >>> from flexarm.assembly.system import system_matrices
    >>> arm = two_link_arm()
    >>> bool(np.array_equal(constant_stiffness(arm), system_matrices(arm, [0.3, 1.0]).K))
    True
    """
    if not has_constant_stiffness(arm):
        raise ValueError("the stiffness of this arm depends on the pose (multi-node bodies)")

    def make():
        K = arm.spring_stiffness()
        for idx, b in zip(arm.layout["body"], arm.bodies, strict=True):
            K[np.ix_(idx, idx)] += b.K[6:, 6:]
        K.setflags(write=False)
        return K

    return _cached(arm, "_constant_K", make)


def _exit_points(arm: ArmModel) -> list[tuple[int, str]]:
    """(body, point name) along the path base -> TCP body: where each passes on the load."""
    chain = arm.chain
    path = chain.ancestors(chain.tcp_body)
    out = [(int(chain.parents[j]), arm.joint_points[j]) for j in path]
    return out + [(chain.tcp_body, arm.tcp_point)]


def _point_offset(G: FloatArray, node: FloatArray) -> FloatArray:
    """(3,) position [m] of a point whose ``G[:, :6]`` is ``rigid_transport(p - node)``."""
    return node + np.array([G[1, 5], G[2, 3], G[0, 4]])


def tcp_support(arm: ArmModel) -> np.ndarray:
    """(n_s,) int: the coordinates ``x`` that can move the TCP, in ascending order."""

    def make():
        lay = arm.layout
        cols = [lay["foundation"]]
        for j in arm.chain.ancestors(arm.chain.tcp_body):
            cols.append(lay["joint"][j])
        for i, name in _exit_points(arm):
            Ge = arm.bodies[i].G(name)[:, 6:]
            cols.append(lay["body"][i][np.any(Ge != 0, axis=0)])
        s = np.unique(np.concatenate(cols)).astype(np.int64)
        s.setflags(write=False)
        return s

    return _cached(arm, "_tcp_support", make)


def tcp_map(arm: ArmModel, q: ArrayLike, compact: bool = False) -> FloatArray:
    """(..., 6, n) TCP motion [m, rad] (base frame) from ``x`` (*batched*).

    Equal to ``system_matrices(arm, q).G_tcp`` without building ``T``: the TCP is
    carried rigidly from (a) the base node by the foundation DOFs, (b) each joint's
    child node by the joint's free DOFs, (c) each body's exit point (the next joint on
    the path, or the TCP) by that body's elastic coordinates, rotated to the base frame.
    With ``compact`` only the columns :func:`tcp_support` are returned.
    """
    if not has_constant_stiffness(arm):
        raise ValueError("tcp_map needs bodies with one rotating node each")
    chain, lay = arm.chain, arm.layout
    F = link_frames(chain, q)
    R, t = F[..., :3, :3], F[..., :3, 3]
    support = tcp_support(arm)
    n = len(support) if compact else lay["n"]
    where = np.full(lay["n"], -1)
    where[support if compact else np.arange(n)] = np.arange(n)
    exits = _exit_points(arm)
    c, tcp = exits[-1]
    r_tcp = _point_offset(arm.bodies[c].G(tcp), arm.bodies[c].node_positions[0])
    p_tcp = R[..., c, :, :] @ r_tcp + t[..., c, :]
    G = np.zeros(F.shape[:-3] + (6, n))
    if arm.foundation is not None:
        p0 = R[..., 0, :, :] @ arm.bodies[0].node_positions[0] + t[..., 0, :]
        G[..., :, where[lay["foundation"]]] = rigid_transport(p_tcp - p0)
    _joint_tcp_columns(G, arm, c, R, t, p_tcp, [where[cols] for cols in lay["joint"]])
    for i, name in exits:
        Gi = arm.bodies[i].G(name)
        used = np.any(Gi[:, 6:] != 0, axis=0)
        if not np.any(used):
            continue
        r = _point_offset(Gi, arm.bodies[i].node_positions[0])
        Ri = R[..., i, :, :]
        d = p_tcp - (_rotate(Ri, r[:, None])[..., 0] + t[..., i, :])
        # [[I, -S(d)], [0, I]] blockdiag(R, R) [A; B] = [R A + (R B) x d; R B], column-wise:
        # one GEMM over all poses for [A | B] instead of two (6, 6) products per pose
        m = int(used.sum())
        RAB = _rotate(Ri, np.hstack([Gi[:3, 6:][:, used], Gi[3:, 6:][:, used]]))
        RA, RB = RAB[..., :m], RAB[..., m:]
        cols = _as_slice(where[lay["body"][i][used]])
        dx, dy, dz = (d[..., k, None] for k in range(3))
        G[..., 0, cols] = RA[..., 0, :] + RB[..., 1, :] * dz - RB[..., 2, :] * dy
        G[..., 1, cols] = RA[..., 1, :] + RB[..., 2, :] * dx - RB[..., 0, :] * dz
        G[..., 2, cols] = RA[..., 2, :] + RB[..., 0, :] * dy - RB[..., 1, :] * dx
        G[..., 3:, cols] = RB
    return G


def _rotate(R: FloatArray, A: FloatArray) -> FloatArray:
    """(..., 3, m) ``R @ A`` for a stack of rotations (..., 3, 3) and one (3, m): a single
    GEMM over the stack (numpy's stacked matmul of small matrices does not reach BLAS)."""
    return (R.reshape(-1, 3) @ A).reshape(R.shape[:-1] + A.shape[1:])


def _as_slice(cols: np.ndarray):
    """``cols`` as a slice when they are consecutive (a view instead of a gather)."""
    if len(cols) and np.array_equal(cols, np.arange(cols[0], cols[0] + len(cols))):
        return slice(int(cols[0]), int(cols[0]) + len(cols))
    return cols


def fast_tcp_compliance(arm: ArmModel, q: ArrayLike) -> FloatArray:
    """(..., 6, 6) TCP compliance ``G K^-1 G^T`` with the constant ``K`` (*batched*).

    ``K^-1`` on :func:`tcp_support` is computed once per arm (Cholesky); each pose
    then costs one (6, n_s) map and two small products.
    """

    def make():
        K = constant_stiffness(arm)
        s = tcp_support(arm)
        E = np.zeros((K.shape[0], len(s)))
        E[s, np.arange(len(s))] = 1.0
        Ks = sla.cho_solve(sla.cho_factor(K), E)[s]
        return 0.5 * (Ks + Ks.T)

    L = _cached(arm, "_tcp_flexibility_factor", lambda: _psd_factor(_cached(
        arm, "_tcp_flexibility", make)))
    q = np.asarray(q, dtype=float)
    flat = q.reshape(-1, q.shape[-1])
    C = np.empty((len(flat), 6, 6))
    with one_blas_thread():  # many small products: threads only add overhead
        for start in range(0, len(flat), POSE_CHUNK):  # the (6, n_s) maps stay in cache
            G = tcp_map(arm, flat[start:start + POSE_CHUNK], compact=True)
            # C = (G L)(G L)^T: one GEMM for the chunk, symmetric by construction
            H = (G.reshape(-1, G.shape[-1]) @ L).reshape(G.shape[:-1] + (L.shape[1],))
            C[start:start + POSE_CHUNK] = H @ np.swapaxes(H, -1, -2)
    return C.reshape(q.shape[:-1] + (6, 6))


def _psd_factor(A: FloatArray) -> FloatArray:
    """``L`` with ``A = L L^T`` for a symmetric positive semi-definite ``A`` (Cholesky, or
    the eigen-decomposition's ``V sqrt(w)`` when ``A`` is singular to round-off)."""
    try:
        return np.linalg.cholesky(A)
    except np.linalg.LinAlgError:
        w, V = np.linalg.eigh(A)
        return V * np.sqrt(np.clip(w, 0.0, None))


def mass_matrix(arm: ArmModel, q: ArrayLike) -> FloatArray:
    """(..., n_x, n_x) ``M(q)`` [kg, kg m, kg m^2] by rank-6 updates (*batched*).

    Equal to ``system_matrices(arm, q).M`` for arms with :func:`has_constant_stiffness`
    bodies: body ``i`` adds ``T_r^T Q M_rr Q^T T_r`` (``T_r`` (6, n_x): base-frame motion
    of its proximal node), the coupling ``Q M_re`` to its own elastic coordinates and
    the constant ``M_ee``; the rank-6 terms of all bodies go into one product per pose.
    """
    if not has_constant_stiffness(arm):
        raise ValueError("mass_matrix needs bodies with one rotating node each")
    chain, lay = arm.chain, arm.layout
    F = link_frames(chain, q)
    batch = F.shape[:-3]
    n_x = lay["n"]
    R6 = [rotation_blocks(F[..., i, :3, :3], 6, 1) for i in range(len(arm.bodies))]
    M = np.zeros(batch + (n_x, n_x))
    Tr: list = []
    Y: list = []
    for i, b in enumerate(arm.bodies):
        T = np.zeros(batch + (6, n_x))
        if i == 0:
            if arm.foundation is not None:
                T[..., :, lay["foundation"]] = np.eye(6)
        else:
            j = i - 1
            p = int(chain.parents[j])
            Gp = arm.bodies[p].G(arm.joint_points[j])
            T += R6[p] @ Gp[:, :6] @ np.swapaxes(R6[p], -1, -2) @ Tr[p]
            T[..., :, lay["body"][p]] += R6[p] @ Gp[:, 6:]
            RJ = F[..., i, :3, :3] @ joint_basis(chain.axes[j])
            T[..., :, lay["joint"][j]] += rotation_blocks(RJ, 6, 1)[..., :, arm.joints[j].free_dofs]
        Tr.append(T)
        # Y_i = [Q M_rr Q^T, Q M_re] [T_r; S_e]: then M = sum_i T_r^T Y_i + the S_e^T rows
        Yi = R6[i] @ b.M[:6, :6] @ np.swapaxes(R6[i], -1, -2) @ T
        e = lay["body"][i]
        if len(e):
            Yi[..., :, e] += R6[i] @ b.M[:6, 6:]
            M[..., e, :] += b.M[6:, :6] @ np.swapaxes(R6[i], -1, -2) @ T
            M[..., e[:, None], e[None, :]] += b.M[6:, 6:]
        Y.append(Yi)
    M += np.swapaxes(np.concatenate(Tr, axis=-2), -1, -2) @ np.concatenate(Y, axis=-2)
    return M
