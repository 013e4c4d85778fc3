"""Assembly of bodies and joint springs into system matrices at a pose.

Exact constraint elimination: one transformation ``T`` maps the independent
coordinates ``x`` to the DOFs of every body (base frame), walking the tree from
the base.  ``x`` holds, in this order: the foundation's six DOFs (if the base sits
on a spring), each joint's free relative DOFs ``delta`` (torsion plus the finite
bearing directions), and each body's non-proximal DOFs.  A child's proximal node
is its parent's attachment point plus ``blockdiag(R_J, R_J) E_free delta``, so
rigid bearing directions never appear.  Then ``K = T^T diag(K_b) T + K_springs``
and ``M = T^T diag(M_b) T``; everything is batched over poses.  When every body has
one rotating node and no stiffness on its rigid DOFs (rigid links, floating-frame
superelements), ``K`` does not depend on the pose: :mod:`~flexarm.assembly.batched`
exploits that for many poses.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..fe.geometry import cross
from ..fe.typing import ArrayLike, FloatArray
from ..robot.joints import DOF_NAMES, JointModel, joint_basis
from ..robot.kinematics import Chain, link_frames
from .bodies import Body, rigid_transport

__all__ = [
    "ArmModel",
    "SystemMatrices",
    "system_matrices",
    "rotation_blocks",
    "is_rigid_arm",
    "rigid_tcp_map",
]


@dataclass(frozen=True, eq=False)
class ArmModel:
    """Bodies, joints and kinematics of an arm (the pose comes later).

    Parameters
    ----------
    chain : Chain
        Kinematics; body ``i`` is link frame ``i`` (0 = base).
    bodies : tuple of Body
        ``chain.n_joints + 1`` bodies in their link frames.
    joints : tuple of JointModel
        One per joint.
    joint_points : tuple of str
        Name of the point on the parent body where each joint attaches.
    tcp_point : str
        Name of the TCP point on body ``chain.tcp_body``.
    foundation : (6, 6) float or None
        Base spring [N/m, N m/rad] in the base frame at the base's proximal node;
        None = clamped.
    foundation_damping : float
        Damping ratio [-] of energy stored in the foundation spring.
    wrist_stiffness : (3, 3) float or None
        Coupled joint-space torsion stiffness of the last three joints [N m/rad];
        replaces their individual torsion springs.
    joint_names : tuple of str
        Labels for reports.
    joint_limits : (n_joints, 2) float or None
        Lower and upper joint angle [rad] (the robot's); analyses at a pose outside them
        are refused (:meth:`check_pose`).  None: no limits.
    """

    chain: Chain
    bodies: tuple[Body, ...]
    joints: tuple[JointModel, ...]
    joint_points: tuple[str, ...]
    tcp_point: str = "tcp"
    foundation: FloatArray | None = None
    foundation_damping: float = 0.02
    wrist_stiffness: FloatArray | None = None
    joint_names: tuple[str, ...] = ()
    joint_limits: FloatArray | None = None

    def __post_init__(self) -> None:
        n = self.chain.n_joints
        if len(self.bodies) != n + 1 or len(self.joints) != n or len(self.joint_points) != n:
            raise ValueError(f"{n} joints need {n + 1} bodies, {n} joint models and {n} "
                             f"attachment names; got {len(self.bodies)}, {len(self.joints)}, "
                             f"{len(self.joint_points)}")
        if not self.joint_names:
            object.__setattr__(self, "joint_names", tuple(f"joint_{j + 1}" for j in range(n)))
        if self.wrist_stiffness is not None:
            W = np.asarray(self.wrist_stiffness, dtype=float)
            if W.shape != (3, 3):
                raise ValueError(f"wrist_stiffness must be (3, 3), got {W.shape}")
            if any(not np.isfinite(self.joints[j].torsion) for j in range(n - 3, n)):
                raise ValueError("a coupled wrist needs finite torsion DOFs at the last 3 joints")
        if self.joint_limits is not None:
            limits = np.array(self.joint_limits, dtype=float)
            if limits.shape != (n, 2):
                raise ValueError(f"joint_limits must be ({n}, 2) [rad], got {limits.shape}")
            limits.setflags(write=False)
            object.__setattr__(self, "joint_limits", limits)

    def check_pose(self, q: ArrayLike, what: str = "pose") -> None:
        """Raise ``ValueError`` naming the joint, its angle and its limits [deg] when a
        joint angle of ``q`` (n_joints,) [rad] is not finite or lies outside
        :attr:`joint_limits`.

        Examples
        --------
        >>> from flexarm.assembly.examples import two_link_arm
        >>> import dataclasses
        >>> arm = dataclasses.replace(two_link_arm(), joint_limits=[[-3, 3], [-1, 1]])
        >>> arm.check_pose([0.0, 2.0])
        Traceback (most recent call last):
        ...
        ValueError: pose: joint_2 = 114.592 deg is outside its limits [-57.2958, 57.2958] deg
        """
        q = np.asarray(q, dtype=float).reshape(-1, self.chain.n_joints)  # one or many
        bad = ~np.isfinite(q)
        if self.joint_limits is not None:
            bad |= (q < self.joint_limits[:, 0]) | (q > self.joint_limits[:, 1])
        hit = np.argwhere(bad)
        if hit.size:
            i, j = (int(k) for k in hit[0])
            span = (" is not a finite angle" if self.joint_limits is None else
                    " is outside its limits [" + ", ".join(
                        f"{np.degrees(a):g}" for a in self.joint_limits[j]) + "] deg")
            raise ValueError(f"{what}: {self.joint_names[j]} = {np.degrees(q[i, j]):g} deg"
                             + span)

    # ----- layout of the independent coordinates x (pure bookkeeping, cached)
    @property
    def layout(self) -> dict:
        """Index arrays of ``x``: ``foundation``, ``joint`` (list), ``body`` (list), ``n``."""
        if "_layout" not in self.__dict__:
            k = 0
            lay: dict = {"foundation": np.arange(0)}
            if self.foundation is not None:
                lay["foundation"] = np.arange(6)
                k = 6
            lay["joint"] = []
            for jm in self.joints:
                n_free = len(jm.free_dofs)
                lay["joint"].append(np.arange(k, k + n_free))
                k += n_free
            lay["body"] = []
            for b in self.bodies:
                lay["body"].append(np.arange(k, k + b.n_dofs - 6))
                k += b.n_dofs - 6
            lay["n"] = k
            self.__dict__["_layout"] = lay
        return self.__dict__["_layout"]

    @property
    def coordinate_names(self) -> list[str]:
        """Label of each independent coordinate (``joint_2.torsion``, ``link_3.q7``...)."""
        names = [f"foundation.{d}" for d in ("ux", "uy", "uz", "rx", "ry", "rz")]
        names = names if self.foundation is not None else []
        for jn, jm in zip(self.joint_names, self.joints, strict=True):
            names += [f"{jn}.{DOF_NAMES[d]}" for d in jm.free_dofs]
        for b in self.bodies:
            names += [f"{b.name}.q{i}" for i in range(6, b.n_dofs)]
        return names

    def spring_stiffness(self) -> FloatArray:
        """(n_x, n_x) joint and foundation springs on the independent coordinates."""
        lay = self.layout
        K = np.zeros((lay["n"], lay["n"]))
        if self.foundation is not None:
            K[:6, :6] = np.asarray(self.foundation, dtype=float)
        for idx, jm in zip(lay["joint"], self.joints, strict=True):
            K[idx, idx] = jm.free_stiffness
        if self.wrist_stiffness is not None:
            n = self.chain.n_joints
            tors = [lay["joint"][j][list(self.joints[j].free_dofs).index(3)]
                    for j in range(n - 3, n)]
            K[np.ix_(tors, tors)] = np.asarray(self.wrist_stiffness, dtype=float)
        return K


def rotation_blocks(R: FloatArray, n_dofs: int, n_nodes: int) -> FloatArray:
    """(..., n_b, n_b) ``blockdiag(R, R)`` per node, identity on modal DOFs."""
    Q = np.zeros(R.shape[:-2] + (n_dofs, n_dofs))
    for k in range(2 * n_nodes):
        Q[..., 3 * k : 3 * k + 3, 3 * k : 3 * k + 3] = R
    idx = np.arange(6 * n_nodes, n_dofs)
    Q[..., idx, idx] = 1.0
    return Q


@dataclass(frozen=True, eq=False)
class SystemMatrices:
    """The assembled arm at one or many poses (leading batch axes ``...``).

    Attributes
    ----------
    K, M : (..., n_x, n_x) float
        Stiffness and mass on the independent coordinates.
    T : list of (..., n_b, n_x) float
        Body DOFs (base frame) of each body from ``x``.
    G_tcp : (..., 6, n_x) float
        TCP translation [m] and rotation [rad] (base frame) from ``x``.
    frames : (..., n + 1, 4, 4) float
        Link frames at the pose(s).
    """

    K: FloatArray
    M: FloatArray
    T: list
    G_tcp: FloatArray
    frames: FloatArray


def system_matrices(arm: ArmModel, q: ArrayLike) -> SystemMatrices:
    """Assemble ``K``, ``M``, ``T`` and the TCP map at joint angles ``q`` (..., n) [rad].

    Examples
    --------
    >>> from flexarm.assembly.examples import two_link_arm
    >>> sm = system_matrices(two_link_arm(), [0.0, 0.0])
    >>> sm.K.shape, sm.G_tcp.shape
    ((2, 2), (6, 2))
    """
    chain = arm.chain
    lay = arm.layout
    q = np.asarray(q, dtype=float)
    F = link_frames(chain, q)
    batch = q.shape[:-1]
    n_x = lay["n"]
    Q = [rotation_blocks(F[..., i, :3, :3], b.n_dofs, b.n_nodes) for i, b in enumerate(arm.bodies)]
    T: list = []
    for i, b in enumerate(arm.bodies):
        Ti = np.zeros(batch + (b.n_dofs, n_x))
        if i == 0:
            if arm.foundation is not None:
                Ti[..., :6, lay["foundation"]] = np.eye(6)
        else:
            j = i - 1
            p = int(chain.parents[j])
            bp = arm.bodies[p]
            # attachment point of the parent in base frame: blockdiag(R,R) G Q^T
            G = bp.G(arm.joint_points[j])
            R6 = rotation_blocks(F[..., p, :3, :3], 6, 1)
            Gb = R6 @ G @ np.swapaxes(Q[p], -1, -2)
            Ti[..., :6, :] = Gb @ T[p]
            jm = arm.joints[j]
            RJ = F[..., i, :3, :3] @ joint_basis(chain.axes[j])
            E = rotation_blocks(RJ, 6, 1)[..., :, jm.free_dofs]
            Ti[..., :6, lay["joint"][j]] += E
        Ti[..., 6:, lay["body"][i]] = np.eye(b.n_dofs - 6)
        T.append(Ti)
    K = np.broadcast_to(arm.spring_stiffness(), batch + (n_x, n_x)).copy()
    M = np.zeros(batch + (n_x, n_x))
    for i, b in enumerate(arm.bodies):
        Tt = np.swapaxes(T[i], -1, -2)
        Mb = Q[i] @ b.M @ np.swapaxes(Q[i], -1, -2)
        M += Tt @ Mb @ T[i]
        if np.any(b.K):
            K += Tt @ (Q[i] @ b.K @ np.swapaxes(Q[i], -1, -2)) @ T[i]
    c = chain.tcp_body
    R6 = rotation_blocks(F[..., c, :3, :3], 6, 1)
    Gt = R6 @ arm.bodies[c].G(arm.tcp_point) @ np.swapaxes(Q[c], -1, -2)
    return SystemMatrices(K=K, M=M, T=T, G_tcp=Gt @ T[c], frames=F)


def is_rigid_arm(arm: ArmModel) -> bool:
    """All bodies rigid (one node, no K): then ``K`` does not depend on the pose."""
    return all(b.is_rigid for b in arm.bodies)


def rigid_tcp_map(arm: ArmModel, q: ArrayLike) -> FloatArray:
    """(..., 6, n_x) TCP motion from ``x`` for an all-rigid arm (*batched*, fast path).

    Equal to ``system_matrices(arm, q).G_tcp`` but without building ``T``: a free
    rotation ``w`` of a joint whose child node sits at ``p`` moves the TCP by
    ``[w x (p_tcp - p); w]``, a free translation ``v`` by ``[v; 0]``.
    """
    if not is_rigid_arm(arm):
        raise ValueError("rigid_tcp_map needs an arm of rigid bodies")
    chain = arm.chain
    lay = arm.layout
    F = link_frames(chain, q)
    c = chain.tcp_body
    G_local = arm.bodies[c].G(arm.tcp_point)
    # TCP point in the tcp body's frame: G = [[I, -S(r)], [0, I]] -> r from the skew block
    r_loc = np.array([G_local[1, 5], G_local[2, 3], G_local[0, 4]])
    r_loc = r_loc + arm.bodies[c].node_positions[0]
    p_tcp = F[..., c, :3, :3] @ r_loc + F[..., c, :3, 3]
    G = np.zeros(F.shape[:-3] + (6, lay["n"]))
    if arm.foundation is not None:
        p0 = arm.bodies[0].node_positions[0]
        G[..., :, lay["foundation"]] = rigid_transport(p_tcp - p0)
    _joint_tcp_columns(G, arm, c, F[..., :3, :3], F[..., :3, 3], p_tcp, lay["joint"])
    return G


def _joint_tcp_columns(G: FloatArray, arm: ArmModel, c: int, R: FloatArray, t: FloatArray,
                       p_tcp: FloatArray, joint_cols) -> None:
    """Fill the TCP motion of the joints on the path to body ``c`` into ``G`` (in place).

    ``R`` (..., n_bodies, 3, 3) and ``t`` (..., n_bodies, 3) are the body frames,
    ``p_tcp`` (..., 3) the TCP [m] and ``joint_cols[j]`` the columns of joint ``j``'s
    free DOFs.  A free translation ``v`` moves the TCP by ``[v; 0]``, a free rotation
    ``w`` of a joint whose child node sits at ``p`` by ``[w x (p_tcp - p); w]``.
    """
    chain = arm.chain
    for j in chain.ancestors(c):
        i = j + 1
        RJ = R[..., i, :, :] @ joint_basis(chain.axes[j])
        arm_tcp = p_tcp - (R[..., i, :, :] @ arm.bodies[i].node_positions[0] + t[..., i, :])
        for col, d in zip(joint_cols[j], arm.joints[j].free_dofs, strict=True):
            e = RJ[..., :, d % 3]
            if d < 3:
                G[..., :3, col] = e
            else:
                G[..., :3, col] = cross(e, arm_tcp)
                G[..., 3:, col] = e
