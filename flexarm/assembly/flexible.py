"""The flexible arm: superelements as :class:`~flexarm.assembly.bodies.Body` s.

A superelement's DOFs are 6 per interface node (seat centres ``c_k``, link frame) then
the modal coordinates.  The body uses *floating-frame* coordinates (see
:func:`body_coordinates`): the motion of the proximal joint point ``o`` (the joint
springs act at the joint origin, on the bearing axis but not necessarily at the seat
centre; the offset is an exact rigid link), then each other seat's elastic motion
relative to the rigid motion carried from ``o``, then the modal coordinates.  Only
the first six rotate with the link; the rest are link-frame quantities that
:func:`~flexarm.assembly.system.system_matrices` keeps as they are (an orthogonal
change of coordinates per body, which changes no frequency or compliance).  The
rigid motions are then exactly the first six coordinates, so ``K`` is zeroed there
explicitly: the round-off ``eps |K|`` of a very stiff link can no longer act as a
spring in series with the joints (it did at ``E x 1e6``).  Distal joints and the TCP
attach at their points by rigid transport from their own seat node (the TCP from
node 0 when carried rigidly by the flange).

Lumped masses (motors, gearboxes) are rigid point masses attached *exactly* to the
nearest interface node by rigid transport (``L^T M_rb L`` on that node's 6 DOFs):
they add inertia but no stiffness, and their total mass properties are unchanged, so
the rigid limit is exactly the E-model.  Spreading them over a seat would need the FE
nodes; the nearest seat is where a motor flange sits in these arms.
"""

from __future__ import annotations

import logging
from collections.abc import Callable, Mapping

import numpy as np

from ..fe.mass_properties import MassProperties, rigid_body_mass_matrix
from ..fe.typing import ArrayLike, FloatArray
from ..reduction import Superelement
from ..robot.description import Robot
from .bodies import Body, point_mass_properties, rigid_body, rigid_transport
from .build import BuildOptions, LinkBuild, Mesher, build_robot
from .emodel import link_mass_properties
from .system import ArmModel

__all__ = ["superelement_body", "body_coordinates", "flexible_bodies", "flexible_arm",
           "coupled_wrist_stiffness"]

log = logging.getLogger(__name__)


def superelement_body(
    se: Superelement,
    name: str,
    origin: ArrayLike,
    attachments: Mapping[str, tuple[int, ArrayLike]] | None = None,
    lumped: list[MassProperties] | None = None,
    damping_ratio: float = 0.01,
) -> Body:
    """A :class:`Body` from a 6-DOF-node superelement (link frame).

    Parameters
    ----------
    se : Superelement
        RBE2/RBE3 superelement; interface node 0 is the proximal seat.
    name : str
    origin : (3,) float
        Proximal joint point [m] (link frame); becomes node 0.
    attachments : mapping str -> (int, (3,) float)
        Named points: (interface node index, position [m]) -- a rigid transport from
        that node (node 0 after its move to ``origin``).
    lumped : list of MassProperties
        Rigid masses, each attached to the nearest interface node.
    damping_ratio : float
        Modal damping ratio [-] of the link's strain energy.

    Examples
    --------
    >>> from flexarm.fe.material import MATERIALS
    >>> from flexarm.fe.mesh import TetMesh
    >>> from flexarm.reduction import CylinderRegion, reduce_part
    >>> mesh = TetMesh.box((1.0, 0.1, 0.1), (8, 1, 1), origin=(0, -0.05, -0.05))
    >>> ends = [CylinderRegion(n, (x, 0, 0), (1, 0, 0), 0, 1, 1e-3) for n, x in (("a", 0.0),
    ...         ("b", 1.0))]
    >>> se = reduce_part(mesh, MATERIALS["steel"], ends, "rbe2", "cb", 4)
    >>> b = superelement_body(se, "bar", [0, 0, 0], {"tip": (1, [1.0, 0, 0])})
    >>> b.n_nodes, b.n_dofs, round(b.M[0, 0], 6)
    (1, 16, 78.5)
    """
    if se.dofs_per_node != 6:
        raise ValueError(f"{name}: a body needs 6-DOF interface nodes (rbe2|rbe3), got "
                         f"{se.dofs_per_node}-DOF nodes ('{se.coupling}')")
    S = body_coordinates(se.node_positions, origin, se.n_dofs)
    K = S.T @ np.asarray(se.K, dtype=float) @ S
    K[:6, :] = 0.0  # rigid motions of the free link are exactly the first six coordinates
    K[:, :6] = 0.0
    M = S.T @ np.asarray(se.M, dtype=float) @ S
    nodes = np.asarray(se.node_positions, dtype=float)
    for mp in lumped or []:
        k = int(np.argmin(np.linalg.norm(nodes - mp.center_of_mass, axis=1)))
        L = S[6 * k : 6 * k + 6]
        M += L.T @ rigid_body_mass_matrix(mp, nodes[k]) @ L
    points = {}
    for key, (k, p) in (attachments or {}).items():
        if not 0 <= int(k) < len(nodes):
            raise ValueError(f"{name}: point '{key}' on node {k}, body has {len(nodes)} nodes")
        k = int(k)
        points[key] = rigid_transport(np.asarray(p, float) - nodes[k]) @ S[6 * k : 6 * k + 6]
    return Body(name, 0.5 * (M + M.T), 0.5 * (K + K.T), np.asarray(origin, float)[None, :],
                points, damping_ratio)


def body_coordinates(node_positions: ArrayLike, origin: ArrayLike, n_dofs: int) -> FloatArray:
    """(n, n) ``S``: superelement DOFs from body coordinates ``y`` (link frame).

    ``y = [u_o; w_1; ...; w_m-1; q]``: the motion ``u_o`` of the joint point ``origin``
    [m], the elastic motion ``w_k`` of interface node ``k`` relative to the rigid motion
    carried from ``origin``, and the modal coordinates ``q``.  Node ``k`` moves by
    ``A(c_k - o) u_o + w_k`` (``w_0 = 0``).
    """
    c = np.asarray(node_positions, dtype=float).reshape(-1, 3)
    A = rigid_transport(c - np.asarray(origin, dtype=float))
    S = np.eye(n_dofs)
    S[: 6 * len(c), :6] = A.reshape(-1, 6)
    return S


def _body_of(robot: Robot, i: int, lb: LinkBuild, damping_ratio: float, mass_method: str,
             mesh_size: float) -> Body:
    chain = robot.chain
    lk = robot.links[i]
    children = {jt.name: np.asarray(jt.origin, float) for j, jt in enumerate(robot.joints)
                if int(chain.parents[j]) == i}
    tcp = chain.tool[:3, 3] if i == chain.tcp_body else None
    if lb.superelement is None:  # rigid base: the E-model's body
        pts = dict(children)
        if tcp is not None:
            pts["tcp"] = tcp
        return rigid_body(lk.name, link_mass_properties(lk, mass_method, mesh_size,
                                                        robot.options.mesher),
                          np.zeros(3), pts)
    att = {name: (lb.regions.index(name), p) for name, p in children.items()}
    if tcp is not None:
        att["tcp"] = (lb.regions.index("tcp") if "tcp" in lb.regions else 0, tcp)
    lumped = [point_mass_properties(m.mass, m.position, m.inertia) for m in lk.lumped]
    return superelement_body(lb.superelement, lk.name, np.zeros(3), att, lumped, damping_ratio)


def flexible_bodies(robot: Robot, builds: tuple[LinkBuild, ...], damping_ratio: float = 0.01,
                    mesh_size: float | None = None) -> tuple[Body, ...]:
    """One :class:`Body` per link from its build (rigid E-model body where none)."""
    ms = robot.options.mesh_size if mesh_size is None else mesh_size
    return tuple(_body_of(robot, i, lb, damping_ratio, "tets", ms)
                 for i, lb in enumerate(builds))


def coupled_wrist_stiffness(robot: Robot) -> FloatArray:
    """(3, 3) joint-space torsion stiffness of the wrist [N m/rad].

    ``robot.wrist_stiffness`` when given; otherwise ``C^T diag(k) C`` with ``C`` the
    wrist coupling (joint to motor angles of joints 4-6, identity if none) and ``k``
    the joints' torsion stiffness read as motor-side values referred to the joints.
    """
    if robot.wrist_stiffness is not None:
        return np.asarray(robot.wrist_stiffness, dtype=float)
    C = np.eye(3) if robot.wrist_coupling is None else np.asarray(robot.wrist_coupling, float)
    k = np.array([jt.model.torsion for jt in robot.joints[-3:]], dtype=float)
    return C.T @ np.diag(k) @ C


def flexible_arm(
    robot: Robot,
    options: BuildOptions = BuildOptions(),  # noqa: B008 (frozen dataclass)
    builds: tuple[LinkBuild, ...] | None = None,
    coupled_wrist: bool = False,
    damping_ratio: float = 0.01,
    cache: bool = True,
    mesher: Mesher | None = None,
    progress: Callable[[str], None] | None = None,
) -> ArmModel:
    """The flexible :class:`ArmModel` of ``robot`` (links = superelements).

    Same kinematics, joint models, base support and tool as
    :func:`~flexarm.assembly.emodel.emodel`; only the bodies differ.  ``builds``
    reuses :func:`~flexarm.assembly.build.build_robot` results; ``coupled_wrist``
    uses :func:`coupled_wrist_stiffness` for joints 4-6.
    """
    opts = options.resolved(robot)
    if builds is None:
        builds = build_robot(robot, opts, cache, mesher, progress)
    bodies = flexible_bodies(robot, builds, damping_ratio, opts.mesh_size)
    foundation = None
    if robot.base.kind == "spring":
        foundation = np.asarray(robot.base.stiffness, dtype=float)
    wrist = None if robot.wrist_stiffness is None else np.asarray(robot.wrist_stiffness)
    if coupled_wrist:
        wrist = coupled_wrist_stiffness(robot)
    return ArmModel(robot.chain, bodies, tuple(j.model for j in robot.joints), robot.joint_names,
                    "tcp", foundation, robot.base.damping_ratio, wrist, robot.joint_names,
                    np.column_stack([robot.lower, robot.upper]))
