"""The loaded arm: where the programmed tool really is under gravity and a process wrench.

:class:`LoadedArm` is an arm model (:func:`~flexarm.assembly.arm.build_arm`, E-model or
flexible links) with the robot file's effects: linear ones in its springs
(:func:`~flexarm.assembly.effects.apply_effects`), the nonlinear joint laws (backlash,
hardening, hysteresis) and the effects that add a motion of their own (a tool
compliance, a gravity balancer).  The measurement-setup effects a diagnosis may find
(tracker frame, load cell, reflector offset) belong to the lab, not to the arm, and are
left out.

:func:`deflection` gives the small motion of the programmed tool frame, base frame, at
many poses at once:

* the linear response ``C(q) w`` (:func:`~flexarm.assembly.analyses.tcp_compliance`)
  to the wrench carried from the tool point to the arm's TCP, plus the gravity sag
  (:func:`~flexarm.assembly.analyses.gravity_sag`) unless only the process load is
  compensated;
* every joint's extra rotation (a nonlinear law, a balancer in parallel with the gear),
  seen through the Jacobian: the joint loads are statically exact, so the distal bodies
  follow a joint's extra turn rigidly (:mod:`flexarm.assembly.statics`);
* the tool's own compliance, ``R C R^T f`` in the robot's tool frame.

A law with memory sees the path's torque history: :func:`law_rotations` evaluates it
along a sampled path in execution order (:mod:`flexarm.assembly.nonlinear`).
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from ....assembly.analyses import tcp_compliance
from ....assembly.arm import ArmSpec, build_arm
from ....assembly.effects import apply_effects
from ....assembly.statics import joint_moments
from ....assembly.system import ArmModel
from ....assembly.tolerances import tol as assembly_tol
from ....fe.geometry import rigid_transport
from ....fe.typing import ArrayLike, FloatArray
from ....robot.effects import TOOL_INDEX, TOOL_PARAMS
from ....robot.kinematics import jacobian, link_frames, tcp_frame
from .sag import gravity_sag

__all__ = ["LoadedArm", "loaded_arm", "deflection", "law_rotations", "joint_torques",
           "gravity_sag", "SETUP_EFFECTS"]

#: Effects of the measurement setup, not of the arm: a compensation ignores them.
SETUP_EFFECTS = ("frame", "loadcell", "reflector")


@dataclass(frozen=True, eq=False)
class LoadedArm:
    """An arm model with its joint laws, balancers and tool compliance.

    Attributes
    ----------
    arm : ArmModel
        Linear effects built into the springs.
    laws : dict
        Joint index -> tuple of laws (``deflection(tau history) -> rad``).
    tool_compliance : (3, 3) float
        Compliance of the tool in the robot's tool frame [m/N] (zeros: a rigid tool).
    balancers : tuple of (int, float, float)
        ``(joint, kc, ks)``: a stiffness ``kc cos q + ks sin q`` [N m/rad] in parallel
        with the joint's gear.
    gravity : bool
        The deflection includes the gravity sag (absolute accuracy); otherwise only the
        change the process wrench makes (the unloaded run as the reference, as the circle
        test measures).  The laws always see gravity's preload.
    label : str
        The model, for reports (``"E-model of identified.toml"``).
    """

    arm: ArmModel
    laws: dict = field(default_factory=dict)
    tool_compliance: FloatArray = field(default_factory=lambda: np.zeros((3, 3)))
    balancers: tuple = ()
    gravity: bool = True
    label: str = ""

    @property
    def law_joints(self) -> tuple[int, ...]:
        """Joints (0-based) with a nonlinear law."""
        return tuple(sorted(self.laws))


def loaded_arm(robot, effects=(), spec: ArmSpec = ArmSpec(),  # noqa: B008 (frozen)
               gravity: bool = True, arm: ArmModel | None = None, label: str = "",
               progress=None) -> LoadedArm:
    """The :class:`LoadedArm` of ``robot`` with its own effects and ``effects`` on top.

    Parameters
    ----------
    robot : Robot
    effects : sequence of Effect
        Extra effects (e.g. a lab's hidden ones) after ``robot.effects``.
    spec : ArmSpec
        Which arm model (E-model by default); ignored when ``arm`` is given.
    gravity : bool
        See :attr:`LoadedArm.gravity`.
    arm : ArmModel, optional
        A model already built for ``robot``.

    Examples
    --------
    >>> from flexarm.robot.demo_arm import load_demo_robot
    >>> from flexarm.robot.effects import parse_effect
    >>> la = loaded_arm(load_demo_robot(), [parse_effect("backlash:j2=0.1mrad")])
    >>> la.law_joints, la.label
    ((1,), 'E-model of flexarm demo arm (IRB 4600-60/2.05 class)')
    """
    if arm is None:
        arm = build_arm(robot, spec, progress=progress).model
    every = [*robot.effects, *effects]
    links = [e for e in every if e.kind == "links"]
    if links:
        raise ValueError("a 'links' effect needs the flexible model: give the robot file "
                         "diagnose --apply writes (its links carry the fitted flexibility)")
    model, laws = apply_effects(arm, [e for e in every if e.kind not in SETUP_EFFECTS])
    C = np.zeros((3, 3))
    balancers = []
    for e in every:
        if e.kind == "tool":
            for name, (a, b) in zip(TOOL_PARAMS, TOOL_INDEX, strict=True):
                C[a, b] += e.get(name, 0.0)
                C[b, a] = C[a, b]
        elif e.kind == "balancer":
            balancers.append((int(e.joint), e.get("kc"), e.get("ks")))
    name = label or f"{spec.label} of {robot.name}"
    return LoadedArm(model, {j: tuple(v) for j, v in laws.items()}, C, tuple(balancers),
                     gravity, name)


def _tool_transport(la: LoadedArm, q: FloatArray, tool: FloatArray):
    """(frames, A (n, 6, 6), robot TCP frames): ``A`` carries the arm's TCP motion to the
    programmed tool point (:func:`~flexarm.fe.geometry.rigid_transport`)."""
    chain = la.arm.chain
    F = link_frames(chain, q)
    T_tcp = tcp_frame(chain, q, F)
    p_tool = F[..., chain.tcp_body, :3, :3] @ tool[:3, 3] + F[..., chain.tcp_body, :3, 3]
    return F, rigid_transport(p_tool - T_tcp[..., :3, 3]), T_tcp


def joint_torques(la: LoadedArm, q: ArrayLike, wrench: ArrayLike, tool: ArrayLike,
                  gravity: bool = True) -> FloatArray:
    """(n, n_joints) torque about every joint axis [N m] under the tool wrench (*batched*).

    ``wrench`` (n, 6) is the force [N] and moment [N m] on the programmed tool point
    ``tool`` (4, 4) [m, last body], base frame; ``gravity`` adds the bodies' weight.

    Examples
    --------
    >>> from flexarm.robot.demo_arm import load_demo_robot
    >>> robot = load_demo_robot()
    >>> la = loaded_arm(robot)
    >>> tau = joint_torques(la, robot.pose("P1")[None], np.zeros((1, 6)), np.eye(4))
    >>> bool(abs(tau[0, 0]) < 1e-9 and abs(tau[0, 1]) > 1e3)  # weight: joint 2, not 1
    True
    """
    q = np.asarray(q, dtype=float)
    _F, A, _T = _tool_transport(la, q, np.asarray(tool, float))
    W = np.einsum("nji,nj->ni", A, np.asarray(wrench, dtype=float))  # A^T w: at the TCP
    return joint_moments(la.arm, q, W[:, :3], W[:, 3:], gravity=gravity)[..., 0]


def law_rotations(la: LoadedArm, q: ArrayLike, wrench: ArrayLike, tool: ArrayLike
                  ) -> FloatArray:
    """(n, n_joints) extra rotation of every joint with a law [rad] along a path.

    The rows are one history in execution order (a hysteresis loop is traversed along
    it); the torques include gravity.  Without :attr:`LoadedArm.gravity` the rotation
    under gravity alone is subtracted, so only the process load's share remains.

    Examples
    --------
    >>> from flexarm.robot.demo_arm import load_demo_robot
    >>> from flexarm.robot.effects import parse_effect
    >>> la = loaded_arm(load_demo_robot(), [parse_effect("backlash:j2=0.1mrad")])
    >>> q = np.tile(load_demo_robot().pose("P1"), (2, 1))
    >>> law_rotations(la, q, np.zeros((2, 6)), np.eye(4))[:, 1].tolist()  # gravity's flank
    [5e-05, 5e-05]
    """
    q = np.asarray(q, dtype=float)
    out = np.zeros(q.shape)
    if not la.laws:
        return out
    tau = joint_torques(la, q, wrench, tool)
    tau0 = None if la.gravity else joint_torques(la, q, np.zeros_like(wrench), tool)
    for j, laws in la.laws.items():
        for law in laws:
            out[:, j] += law.deflection(tau[:, j])
            if tau0 is not None:
                out[:, j] -= law.deflection(tau0[:, j])
    return out


def _balancer_rotations(la: LoadedArm, q: FloatArray, tau: FloatArray) -> FloatArray:
    """(n, n_joints) extra rotation [rad] of the balanced joints under torques ``tau``."""
    out = np.zeros(q.shape)
    for j, kc, ks in la.balancers:
        k = la.arm.joints[j].torsion
        kb = kc * np.cos(q[:, j]) + ks * np.sin(q[:, j])
        k_total = np.maximum(k + kb, assembly_tol.min_compliance_scale * k)
        out[:, j] += tau[:, j] * (1.0 / k_total - 1.0 / k)
    return out


def deflection(la: LoadedArm, q: ArrayLike, wrench: ArrayLike, tool: ArrayLike,
               rotations: ArrayLike | None = None, sag: ArrayLike | None = None) -> FloatArray:
    """(n, 6) small motion of the programmed tool frame [m, rad] under ``wrench`` (*batched*).

    Parameters
    ----------
    la : LoadedArm
    q : (n, 6) float
        Joint angles [rad].
    wrench : (n, 6) float
        Force [N] and moment [N m] on the tool point, base frame.
    tool : (4, 4) float
        Programmed tool on the last body [m].
    rotations : (n, n_joints) float, optional
        Extra joint rotations of the laws [rad] (:func:`law_rotations` along the path);
        computed at these poses as one history when not given.

    Returns
    -------
    (n, 6) float
        Translation [m] and rotation [rad] of the tool frame, base frame; the loaded
        pose is :func:`~.ik_batch.displaced` by it.

    Examples
    --------
    >>> from flexarm.robot.demo_arm import load_demo_robot
    >>> robot = load_demo_robot()
    >>> la = loaded_arm(robot, gravity=False)
    >>> w = np.array([[0.0, 800.0, 0.0, 0.0, 0.0, 0.0]])
    >>> d = deflection(la, robot.pose("P1")[None], w, np.eye(4))
    >>> bool(d[0, 1] > 1e-3)  # millimetres along y at 800 N, the weak direction
    True
    """
    q = np.asarray(q, dtype=float)
    tool = np.asarray(tool, dtype=float)
    wrench = np.asarray(wrench, dtype=float)
    F, A, T_tcp = _tool_transport(la, q, tool)
    W = np.einsum("nji,nj->ni", A, wrench)
    u = np.einsum("nij,nj->ni", tcp_compliance(la.arm, q), W)
    if la.gravity:
        u = u + (gravity_sag(la.arm, q) if sag is None else np.asarray(sag, dtype=float))
    rot = law_rotations(la, q, wrench, tool) if rotations is None else np.array(rotations)
    if la.balancers:
        tau = joint_moments(la.arm, q, W[:, :3], W[:, 3:], gravity=la.gravity)[..., 0]
        rot = rot + _balancer_rotations(la, q, tau)
    if np.any(rot):
        u = u + np.einsum("nij,nj->ni", jacobian(la.arm.chain, q, F), rot)
    d = np.einsum("nij,nj->ni", A, u)
    if np.any(la.tool_compliance):
        R = T_tcp[..., :3, :3]
        d[:, :3] += np.einsum("nij,jk,nlk,nl->ni", R, la.tool_compliance, R, wrench[:, :3])
    return d
