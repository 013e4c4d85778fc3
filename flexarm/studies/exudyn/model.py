"""The arm at a pose as an Exudyn flexible-multibody system (``pip install flexarm[mbs]``).

flexarm does not integrate the flexible multibody equations: it hands the arm to
Exudyn.  :func:`exudyn_arm` builds the ``mbs``: every flexible link is an
``ObjectFFRFreducedOrder`` made from its Craig-Bampton (or Guyan) superelement
(:mod:`~flexarm.studies.exudyn.bodies`: the same mode basis, stiffness and mass,
lumped masses included), every rigid link an ``ObjectRigidBody``; each joint is a
``GenericJoint`` locking the bearing's rigid directions in the joint frame plus a
``RigidBodySpringDamper`` with the joint's finite torsion, tilt, radial and axial
springs; the base is clamped (or on its foundation spring); gravity is a mass-proportional
load.  Links attach at their named points through rigid markers (``MarkerSuperElementRigid``
on a massless star of points that moves rigidly with the seat).

Damping: Exudyn takes viscous joint dampers and stiffness-proportional link damping, not
our modal ratios; :func:`~flexarm.studies.exudyn.damping.fit_damping` chooses them so
that the lowest modes keep our ratios (higher modes come out over-damped).
"""

from __future__ import annotations

import logging
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from ...assembly.analyses import natural_frequencies
from ...assembly.arm import Arm
from ...assembly.bodies import point_mass_properties
from ...assembly.build import link_material, link_mesh
from ...fe.assembly import assemble
from ...fe.errors import ConvergenceError, MissingDependencyError
from ...fe.typing import ArrayLike, FloatArray
from ...robot.joints import joint_basis
from ...robot.kinematics import link_frames
from .bodies import FFRFLink, ffrf_link
from .damping import ProportionalDamping, fit_damping

__all__ = ["require_exudyn", "ExudynArm", "ExudynCheck", "exudyn_arm", "exudyn_check", "ffrf_links",
           "exportable", "ffrf_interface", "exudyn_frequencies", "exudyn_static_tcp",
           "exudyn_gravity_sag"]

log = logging.getLogger(__name__)

#: Standard gravity [m/s^2], along -z of the base frame.
GRAVITY = (0.0, 0.0, -9.80665)


def require_exudyn():
    """The ``exudyn`` module; ``MissingDependencyError`` naming the package when absent."""
    return _exudyn()


def _exudyn():
    try:
        import exudyn
    except ImportError:  # optional: pip install flexarm[mbs]
        raise MissingDependencyError("exudyn", "the flexible-multibody model") from None
    return exudyn


def simulation_settings():
    """Exudyn's ``SimulationSettings`` without its solution file: by default every solve
    writes ``solution/coordinatesSolution.txt`` into the working folder, which is not
    where flexarm's outputs go."""
    sims = _exudyn().SimulationSettings()
    sims.solution.file.write = False
    return sims


@dataclass(frozen=True, eq=False)
class ExudynArm:
    """An assembled Exudyn system of the arm at pose ``q``.

    Attributes
    ----------
    SC, mbs
        Exudyn's ``SystemContainer`` and ``MainSystem``.
    bodies : list of dict
        Per link: ``object`` (index) and ``node`` (reference node), for FFRF links also
        ``modal`` (the modal-coordinate node).
    tcp : tuple (int, int or None)
        Object of the TCP and its mesh node (None: the TCP link is rigid).
    tcp_marker : int
        A position marker at the TCP (for loads).
    tcp_position : (3,) float
        TCP in the base frame at the reference configuration [m].
    q : (n,) float
        The pose [rad].
    gravity_on : bool
        Whether gravity loads the bodies.
    joint_springs : tuple of int
        The spring-damper object of each joint (its ``offset`` drives the joint).
    tcp_rigid_marker : int
        A rigid marker at the TCP, axes of the TCP body (for loads with a lever).
    """

    SC: object
    mbs: object
    bodies: list
    tcp: tuple
    tcp_marker: int
    tcp_position: FloatArray
    q: FloatArray
    gravity_on: bool = True
    joint_springs: tuple = ()
    tcp_rigid_marker: int = -1


def ffrf_links(arm: Arm, progress: Callable[[str], None] | None = None) -> list:
    """:class:`~flexarm.studies.exudyn.bodies.FFRFLink` of every flexible link of ``arm``
    (None for rigid links): the link meshes come from the cache, their FE mass matrices
    are assembled again (seconds)."""
    robot, model = arm.robot, arm.model
    if arm.builds is None:
        return [None] * len(model.bodies)
    opts = arm.spec.build_options().resolved(robot)
    out = []
    for lb, lk, body in zip(arm.builds, robot.links, model.bodies, strict=True):
        if lb.superelement is None:
            out.append(None)
            continue
        if progress:
            progress(f"{lk.name}: floating-frame body")
        mesh = link_mesh(lk, opts.mesh_size, opts.order, mesher=robot.options.mesher)
        _, M = assemble(mesh, link_material(lk, opts.stiffness_scale))
        lumped = [point_mass_properties(m.mass, m.position, m.inertia) for m in lk.lumped]
        out.append(ffrf_link(body, lb.superelement, M, mesh.points, lumped))
    return out


def ffrf_interface(link: FFRFLink):
    """Exudyn's ``ObjectFFRFreducedOrderInterface`` of ``link``: the floating-frame
    inertia terms integrated over its points, the mode basis, and our reduced stiffness
    (``cms.SaveToFile`` writes it for a model without flexarm)."""
    _exudyn()
    from exudyn.FEM import FEMinterface, ObjectFFRFreducedOrderInterface

    fem = FEMinterface()
    fem.nodes = {"Position": link.positions}
    fem.massMatrix = link.M
    fem.stiffnessMatrix = link.M * 0.0  # ours is given reduced (below)
    fem.modeBasis = {"matrix": link.Psi, "type": "HCBmodes"}
    cms = ObjectFFRFreducedOrderInterface(fem)
    cms.stiffnessMatrixReduced = link.K.copy()
    return cms


def _add_ffrf(exu, mbs, link: FFRFLink, frame: FloatArray, gravity, beta: float) -> dict:
    ids = ffrf_interface(link).AddObjectFFRFreducedOrder(
        mbs, positionRef=frame[:3, 3], rotationMatrixRef=frame[:3, :3],
        stiffnessProportionalDamping=beta, gravity=list(gravity), name=link.name)
    return {"object": ids["oFFRFreducedOrder"], "node": ids["nRigidBody"],
            "modal": ids["nGenericODE2"], "link": link}


def _add_rigid(exu, mbs, body, frame: FloatArray, gravity) -> dict:
    from exudyn.utilities import RigidBodyInertia

    Mb = np.asarray(body.M, dtype=float)
    m = Mb[0, 0]
    B = Mb[:3, 3:6] / m  # = -skew(c)
    c = np.array([B[1, 2], B[2, 0], B[0, 1]])
    ids = mbs.CreateRigidBody(inertia=RigidBodyInertia(m, Mb[3:6, 3:6], c),  # about origin
                              referencePosition=frame[:3, 3],
                              referenceRotationMatrix=frame[:3, :3],
                              gravity=list(gravity), returnDict=True)
    return {"object": ids["bodyNumber"], "node": ids["nodeNumber"], "body": body}


def _point_marker(exu, mbs, b: dict, name: str, rotation: FloatArray | None = None) -> int:
    """A rigid marker at named point ``name`` of body ``b`` whose frame is ``rotation``
    (3, 3) in the body frame; a position marker when ``rotation`` is None."""
    import exudyn.itemInterface as eii

    if "link" not in b:  # rigid body: the point from its transport matrix
        G = b["body"].points[name]
        p = [G[1, 5], G[2, 3], G[0, 4]]
        R = np.eye(3) if rotation is None else rotation
        return mbs.AddMarker(eii.MarkerBodyRigid(bodyNumber=b["object"],
                                                 localHT=exu.HT(rotation=R, translation=p)))
    nodes = [int(k) for k in b["link"].points[name]]
    if rotation is None:
        return mbs.AddMarker(eii.MarkerSuperElementPosition(
            bodyNumber=b["object"], meshNodeNumbers=[nodes[0]], weightingFactors=[1.0]))
    return mbs.AddMarker(eii.MarkerSuperElementRigid(
        bodyNumber=b["object"], meshNodeNumbers=nodes, weightingFactors=[1 / 7] * 7,
        localHT=exu.HT(rotation=rotation, translation=[0.0, 0.0, 0.0])))


def _joint_stiffness(jm) -> tuple[FloatArray, list[int]]:
    k = jm.stiffness
    free = np.isfinite(k)
    return np.where(free, k, 0.0), [0 if f else 1 for f in free]



def exportable(arm):
    """``arm.model`` if Exudyn can take it: reduced links (superelements) and no coupled
    wrist stiffness; else ``ValueError`` saying what to export instead."""
    model = arm.model
    if not hasattr(model, "layout"):
        raise ValueError("the full-FE arm has no superelements: export a reduced model "
                         "(guyan, cb, or the E-model)")
    if model.wrist_stiffness is not None:
        raise ValueError("a coupled wrist stiffness is not in the Exudyn model yet")
    return model

def exudyn_arm(arm: Arm, q: ArrayLike, gravity: ArrayLike | None = GRAVITY,
               links: list | None = None, damping: ProportionalDamping | None = None,
               progress: Callable[[str], None] | None = None) -> ExudynArm:
    """Build and assemble the Exudyn system of ``arm`` at pose ``q`` (n,) [rad].

    ``gravity`` [m/s^2] (base frame; None or zeros: off).  ``links`` reuses
    :func:`ffrf_links` (they do not depend on the pose); ``damping`` the dampers (default:
    :func:`~flexarm.studies.exudyn.damping.fit_damping` at ``q``).
    """
    exu = _exudyn()
    import exudyn.itemInterface as eii

    model = exportable(arm)
    q = np.asarray(q, dtype=float)
    g = [0.0, 0.0, 0.0] if gravity is None else [float(v) for v in gravity]
    links = ffrf_links(arm, progress) if links is None else links
    F = link_frames(model.chain, q)
    pd = fit_damping(model, q) if damping is None else damping
    SC = exu.SystemContainer()
    mbs = SC.AddSystem()
    bodies = []
    for body, link, frame, beta in zip(model.bodies, links, F, pd.link_beta, strict=True):
        if link is None:
            bodies.append(_add_rigid(exu, mbs, body, frame, g))
        else:
            bodies.append(_add_ffrf(exu, mbs, link, frame, g, float(beta)))
    ground = mbs.AddObject(eii.ObjectGround())
    m_ground = mbs.AddMarker(eii.MarkerBodyRigid(bodyNumber=ground, localPosition=[0, 0, 0]))
    m_base = mbs.AddMarker(eii.MarkerNodeRigid(nodeNumber=bodies[0]["node"]))
    if model.foundation is None:
        mbs.AddObject(eii.ObjectJointGeneric(markerNumbers=[m_ground, m_base],
                                             constrainedAxes=[1] * 6))
    else:
        Kf = np.asarray(model.foundation, dtype=float)
        mbs.AddObject(eii.ObjectConnectorRigidBodySpringDamper(
            markerNumbers=[m_ground, m_base], stiffness=Kf, damping=pd.foundation_tau * Kf))
    chain = model.chain
    springs = []
    for j, jm in enumerate(model.joints):
        i, p = j + 1, int(chain.parents[j])
        Jb = joint_basis(chain.axes[j])
        # both markers carry the joint frame (axis, radial1, radial2) at the joint point
        m0 = _point_marker(exu, mbs, bodies[p], model.joint_points[j],
                           F[p, :3, :3].T @ F[i, :3, :3] @ Jb)
        m1 = mbs.AddMarker(eii.MarkerNodeRigid(
            nodeNumber=bodies[i]["node"], localHT=exu.HT(rotation=Jb, translation=[0, 0, 0])))
        k, locked = _joint_stiffness(jm)
        tau = np.zeros(6)
        tau[jm.free_dofs] = pd.joint_tau[j]
        mbs.AddObject(eii.ObjectJointGeneric(markerNumbers=[m0, m1], constrainedAxes=locked))
        springs.append(mbs.AddObject(eii.ObjectConnectorRigidBodySpringDamper(
            markerNumbers=[m0, m1], stiffness=np.diag(k), damping=np.diag(tau * k))))
    c = chain.tcp_body
    tcp_marker = _point_marker(exu, mbs, bodies[c], model.tcp_point)
    tcp_rigid = _point_marker(exu, mbs, bodies[c], model.tcp_point, np.eye(3))
    tcp_node = None
    G = model.bodies[c].points[model.tcp_point]
    p_tcp = F[c, :3, :3] @ np.array([G[1, 5], G[2, 3], G[0, 4]]) + F[c, :3, 3]
    if "link" in bodies[c]:
        tcp_node = int(bodies[c]["link"].points[model.tcp_point][0])
    mbs.Assemble()
    log.info("Exudyn arm: %d ODE2 coordinates", mbs.systemData.ODE2Size())
    return ExudynArm(SC, mbs, bodies, (bodies[c]["object"], tcp_node), tcp_marker, p_tcp, q,
                     any(g), tuple(springs), tcp_rigid)


def exudyn_frequencies(ea: ExudynArm, n: int = 10) -> FloatArray:
    """(n,) lowest natural frequencies [Hz] by Exudyn's own eigen-solver on the assembled
    system linearised at its reference configuration (constraints by null-space
    projection)."""
    exu = _exudyn()
    sims = simulation_settings()
    freq, _ = exu.solver.ComputeODE2Eigenvalues(ea.mbs, sims, convert2Frequencies=True,
                                               useAbsoluteValues=True)
    freq = np.sort(np.asarray(freq, dtype=float))
    return freq[:n]


def exudyn_static_tcp(ea: ExudynArm, force: ArrayLike) -> FloatArray:
    """(3,) TCP displacement [m] (base frame) from Exudyn's (nonlinear) static solver under
    a TCP ``force`` (3,) [N] (base frame), relative to the same solve without it when
    gravity is on (so the sag cancels), else to the reference configuration."""
    exu = _exudyn()
    ref = exu.ConfigurationType.Reference
    p0 = _static_tcp(ea, np.zeros(3)) if ea.gravity_on else _tcp_position(exu, ea, ref)
    return _static_tcp(ea, force) - p0


def exudyn_gravity_sag(ea: ExudynArm) -> FloatArray:
    """(3,) TCP displacement [m] (base frame) under the arm's weight alone: Exudyn's
    static solve from the reference configuration (needs gravity on)."""
    if not ea.gravity_on:
        raise ValueError("the Exudyn model was built without gravity")
    exu = _exudyn()
    return _static_tcp(ea, np.zeros(3)) - _tcp_position(exu, ea, exu.ConfigurationType.Reference)


def _static_tcp(ea: ExudynArm, force: ArrayLike) -> FloatArray:
    """TCP position [m] after a static solve with ``force`` [N] at the TCP (removed after)."""
    exu = _exudyn()
    import exudyn.itemInterface as eii

    mbs = ea.mbs
    if "static_load" not in ea.bodies[0]:  # one load, reused by every solve
        ea.bodies[0]["static_load"] = mbs.AddLoad(eii.LoadForceVector(
            markerNumber=ea.tcp_marker, loadVector=[0.0, 0.0, 0.0]))
        mbs.Assemble()
    load = ea.bodies[0]["static_load"]
    sims = simulation_settings()
    sims.linearSolver.solverType = exu.LinearSolverType.EXUdense
    sims.staticSolver.verboseMode = 0
    try:
        mbs.SetLoadParameter(load, "loadVector", [float(v) for v in force])
        _solve_static(exu, mbs, sims)
        return _tcp_position(exu, ea, exu.ConfigurationType.Current)
    finally:
        mbs.SetLoadParameter(load, "loadVector", [0.0, 0.0, 0.0])


def _solve_static(exu, mbs, sims) -> None:
    try:
        ok = exu.SolveStatic(mbs, sims)
    except exu.SolverError as exc:
        raise ConvergenceError(f"Exudyn's static solver failed ({exc})") from None
    if not ok:
        raise ConvergenceError("Exudyn's static solver did not converge")


def _tcp_position(exu, ea: ExudynArm, configuration) -> FloatArray:
    return np.asarray(ea.mbs.GetMarkerOutput(ea.tcp_marker, exu.OutputVariableType.Position,
                                             configuration), dtype=float)


@dataclass(frozen=True)
class ExudynCheck:
    """Exudyn's linearised frequencies and static TCP deflection next to ours.

    Attributes
    ----------
    freq_exudyn, freq_ours : (n,) float
        Lowest natural frequencies [Hz] (gravity off).
    force : (3,) float
        TCP load [N], base frame.
    u_exudyn, u_ours : (3,) float
        TCP displacement [m] under ``force``: Exudyn's nonlinear static solve and our
        compliance.
    """

    freq_exudyn: FloatArray
    freq_ours: FloatArray
    force: FloatArray
    u_exudyn: FloatArray
    u_ours: FloatArray

    @property
    def freq_error(self) -> FloatArray:
        """(n,) relative frequency differences [-]."""
        return self.freq_exudyn / self.freq_ours - 1

    @property
    def static_error(self) -> float:
        """Relative difference of the displacement along the load [-]."""
        e = self.force / np.linalg.norm(self.force)
        return float((self.u_exudyn @ e) / (self.u_ours @ e) - 1)

    def text(self) -> str:
        """The comparison as a table (Hz, mm, %)."""
        lines = [f"{'mode':>4s} {'exudyn_Hz':>10s} {'flexarm_Hz':>10s} {'diff_%':>9s}"]
        lines += [f"{r + 1:4d} {a:10.4f} {b:10.4f} {100 * (a / b - 1):9.5f}"
                  for r, (a, b) in enumerate(zip(self.freq_exudyn, self.freq_ours,
                                                 strict=True))]
        f = ", ".join(f"{v:g}" for v in self.force)
        lines.append(f"TCP displacement under ({f}) N [mm]: Exudyn "
                     f"{np.round(self.u_exudyn * 1e3, 5).tolist()}, flexarm "
                     f"{np.round(self.u_ours * 1e3, 5).tolist()}; along the load "
                     f"{100 * self.static_error:+.4f} %")
        return "\n".join(lines)


def exudyn_check(arm: Arm, q: ArrayLike, n: int = 10, force: ArrayLike = (0.0, 800.0, 0.0),
                 links: list | None = None,
                 progress: Callable[[str], None] | None = None) -> ExudynCheck:
    """Build the Exudyn model of ``arm`` at ``q`` with gravity off and compare its first
    ``n`` eigenfrequencies and its static TCP deflection under ``force`` [N] with ours."""
    from ...assembly.analyses import tcp_compliance

    ea = exudyn_arm(arm, q, gravity=None, links=links, progress=progress)
    f = np.asarray(force, dtype=float)
    ours = natural_frequencies(arm.model, np.asarray(q, dtype=float))[:n]
    return ExudynCheck(exudyn_frequencies(ea, n), ours, f, exudyn_static_tcp(ea, f),
                       tcp_compliance(arm.model, q)[:3, :3] @ f)
