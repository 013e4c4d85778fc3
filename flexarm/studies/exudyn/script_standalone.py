"""The text of the standalone Exudyn script (``flexarm export-exudyn``, default): it
builds the arm from the files written beside it with ``exudyn`` and ``numpy`` only.

The files are described in :mod:`~flexarm.studies.exudyn.standalone`.  The script's own
eigen-solve is NumPy's (Exudyn's ``ComputeODE2Eigenvalues`` needs SciPy): Exudyn's mass
matrix and Jacobian at the reference configuration, projected on the null space of the
constraint Jacobian, then a Cholesky-reduced symmetric eigenproblem.
"""

from __future__ import annotations

__all__ = ["standalone_script"]

_TEMPLATE = '''"""Exudyn model of the arm @ROBOT@ at pose @POSE@ (@LABEL@).

Written by `flexarm export-exudyn` (@VERSIONS@).  Needs only `pip install exudyn numpy`:
no flexarm.  Files beside this script, SI units:

- @DATA@: the assembly (body frames at the pose in the base frame, rigid-body
  inertia, joint frames, springs and dampers, the TCP, gravity, flexarm's frequencies);
- one Exudyn CMS file per flexible link (named in @DATA@'s `link_files`), written by
  `ObjectFFRFreducedOrderInterface.SaveToFile`: its mode basis, reduced mass and
  stiffness and floating-frame inertia terms.

Every flexible link is an ObjectFFRFreducedOrder, every rigid link a rigid body, every
joint a GenericJoint locking its rigid directions plus a RigidBodySpringDamper with the
joint springs and dampers (joint frame: axis, radial 1, radial 2).  `build()` returns
the system and its item numbers (`tcp_marker` for loads at the TCP).

    python @SCRIPT@                 # eigenfrequencies next to flexarm's (gravity off)
    python @SCRIPT@ --simulate 0.2  # let the arm settle under gravity for 0.2 s
"""

import argparse
from pathlib import Path

import exudyn as exu
import exudyn.itemInterface as eii
import numpy as np
from exudyn.FEM import ObjectFFRFreducedOrderInterface
from exudyn.utilities import RigidBodyInertia

HERE = Path(__file__).resolve().parent
DATA = HERE / "@DATA@"
GRAVITY = @GRAVITY@  # [m/s^2], base frame; None: off


def load(path=DATA):
    """The assembly arrays, by name."""
    with np.load(path) as f:
        return {k: f[k] for k in f.files}


def settings():
    """Simulation settings that write no solution file into the working folder."""
    sims = exu.SimulationSettings()
    sims.solution.file.write = False
    sims.staticSolver.verboseMode = 0
    return sims


def _marker(mbs, body, nodes, point, rotation):
    """A rigid marker at a point of a body, axes `rotation` (body frame): on a flexible
    body the mean of the point's star of 7 mesh nodes, on a rigid one at `point` [m]."""
    if nodes[0] < 0:
        return mbs.AddMarker(eii.MarkerBodyRigid(
            bodyNumber=body, localHT=exu.HT(rotation=rotation, translation=point)))
    return mbs.AddMarker(eii.MarkerSuperElementRigid(
        bodyNumber=body, meshNodeNumbers=[int(n) for n in nodes], weightingFactors=[1 / 7] * 7,
        localHT=exu.HT(rotation=rotation, translation=[0.0, 0.0, 0.0])))


def build(gravity=GRAVITY, data=None):
    """Assemble the arm; returns (SC, mbs, items): the item numbers `objects` and `nodes`
    (per body), `joint_springs` (per joint), `tcp_marker` (position) and
    `tcp_rigid_marker` (TCP body axes)."""
    d = load() if data is None else data
    g = [0.0, 0.0, 0.0] if gravity is None else [float(v) for v in gravity]
    SC = exu.SystemContainer()
    mbs = SC.AddSystem()
    objects, nodes = [], []
    for i, name in enumerate(d["body_names"]):
        F, file = d["frames"][i], str(d["link_files"][i])
        if file:
            cms = ObjectFFRFreducedOrderInterface()
            cms.LoadFromFile(str(HERE / file))
            ids = cms.AddObjectFFRFreducedOrder(
                mbs, positionRef=F[:3, 3], rotationMatrixRef=F[:3, :3],
                stiffnessProportionalDamping=float(d["beta"][i]), gravity=g, name=str(name))
            objects.append(ids["oFFRFreducedOrder"])
            nodes.append(ids["nRigidBody"])
        else:
            ids = mbs.CreateRigidBody(
                inertia=RigidBodyInertia(float(d["mass"][i]), d["inertia"][i], d["com"][i]),
                referencePosition=F[:3, 3], referenceRotationMatrix=F[:3, :3], gravity=g,
                returnDict=True)
            objects.append(ids["bodyNumber"])
            nodes.append(ids["nodeNumber"])
    ground = mbs.AddObject(eii.ObjectGround())
    m_ground = mbs.AddMarker(eii.MarkerBodyRigid(bodyNumber=ground, localPosition=[0, 0, 0]))
    m_base = mbs.AddMarker(eii.MarkerNodeRigid(nodeNumber=nodes[0]))
    Kf = d["foundation"]
    if not Kf.any():  # clamped base
        mbs.AddObject(eii.ObjectJointGeneric(markerNumbers=[m_ground, m_base],
                                             constrainedAxes=[1] * 6))
    else:
        mbs.AddObject(eii.ObjectConnectorRigidBodySpringDamper(
            markerNumbers=[m_ground, m_base], stiffness=Kf,
            damping=float(d["foundation_tau"]) * Kf))
    springs = []
    for j in range(len(d["joint_names"])):
        p = int(d["joint_parent"][j])
        m0 = _marker(mbs, objects[p], d["joint_nodes"][j], d["joint_point"][j],
                     d["joint_rotation_parent"][j])
        m1 = mbs.AddMarker(eii.MarkerNodeRigid(
            nodeNumber=nodes[j + 1],
            localHT=exu.HT(rotation=d["joint_rotation_child"][j], translation=[0, 0, 0])))
        mbs.AddObject(eii.ObjectJointGeneric(
            markerNumbers=[m0, m1], constrainedAxes=[int(v) for v in d["joint_locked"][j]]))
        springs.append(mbs.AddObject(eii.ObjectConnectorRigidBodySpringDamper(
            markerNumbers=[m0, m1], stiffness=np.diag(d["joint_stiffness"][j]),
            damping=np.diag(d["joint_damping"][j]))))
    c, star, point = int(d["tcp_body"]), d["tcp_nodes"], d["tcp_point"]
    if star[0] < 0:
        tcp = mbs.AddMarker(eii.MarkerBodyRigid(
            bodyNumber=objects[c], localHT=exu.HT(rotation=np.eye(3), translation=point)))
    else:
        tcp = mbs.AddMarker(eii.MarkerSuperElementPosition(
            bodyNumber=objects[c], meshNodeNumbers=[int(star[0])], weightingFactors=[1.0]))
    tcp_rigid = _marker(mbs, objects[c], star, point, np.eye(3))
    mbs.Assemble()
    return SC, mbs, {"objects": objects, "nodes": nodes, "joint_springs": springs,
                     "tcp_marker": tcp, "tcp_rigid_marker": tcp_rigid}


def frequencies(mbs, n=10, tolerance=1e-12):
    """The n lowest natural frequencies [Hz] of the undamped system linearised at its
    reference configuration, constraints by null-space projection (what
    exudyn.solver.ComputeODE2Eigenvalues does, with NumPy instead of SciPy)."""
    sims = settings()
    solver = exu.MainSolverStatic()
    solver.InitializeSolver(mbs, sims)
    n2, n1 = solver.GetODE2size(), solver.GetODE1size()
    solver.ComputeMassMatrix(mbs)
    M = solver.GetSystemMassMatrix()
    solver.ComputeJacobianODE2RHS(mbs, scalarFactor_ODE2=-1, scalarFactor_ODE2_t=0,
                                  scalarFactor_ODE1=0)
    solver.ComputeJacobianAE(mbs, scalarFactor_ODE2=1.0, scalarFactor_ODE2_t=0.0,
                             scalarFactor_ODE1=0.0, velocityLevel=False)
    J = solver.GetSystemJacobian()
    solver.FinalizeSolver(mbs, sims)
    K, C = J[:n2, :n2], J[:n2, n2 + n1:]
    N = np.eye(n2)
    if C.shape[1]:
        U, s, _ = np.linalg.svd(C)
        N = U[:, int((np.abs(s) > tolerance).sum()):]
    # the lower triangles, as LAPACK's symmetric solvers read them
    Kn, Mn = (np.tril(A) + np.tril(A, -1).T for A in (N.T @ K @ N, N.T @ M @ N))
    Li = np.linalg.inv(np.linalg.cholesky(Mn))
    lam = np.linalg.eigvalsh(Li @ Kn @ Li.T)
    return np.sqrt(np.sort(np.abs(lam))[:n]) / (2 * np.pi)


def main(argv=None):
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("-n", "--modes", type=int, default=10, help="frequencies to list")
    p.add_argument("--simulate", type=float, default=0.0, metavar="SECONDS",
                   help="also integrate this long with gravity and print the TCP motion")
    args = p.parse_args(argv)
    d = load()
    _, mbs, _ = build(gravity=None, data=d)
    ours, theirs = frequencies(mbs, args.modes), d["freq_hz"]
    print("mode   exudyn_Hz          flexarm_Hz         diff")
    for k, f in enumerate(ours):
        ref = theirs[k] if k < len(theirs) else float("nan")
        print(f"{k + 1:4d}   {f:.12e}   {ref:.12e}   {f / ref - 1:+.2e}")
    if args.simulate > 0:
        _, mbs, items = build(data=d)
        sims = settings()
        sims.timeIntegration.endTime = args.simulate
        sims.timeIntegration.numberOfSteps = max(1, int(round(args.simulate / 5e-4)))
        mbs.SolveDynamic(sims)
        p = mbs.GetMarkerOutput(items["tcp_marker"], exu.OutputVariableType.Position)
        print("TCP moved by", np.round((p - d["tcp_position"]) * 1e3, 4), "mm")


if __name__ == "__main__":
    main()
'''


def standalone_script(data_name: str, info, gravity) -> str:
    """The script's text for the assembly file ``data_name`` (beside the script), the
    ``info`` strings (robot, pose, model label, versions) and ``gravity`` (3,) [m/s^2]
    (zeros: off).

    Examples
    --------
    >>> text = standalone_script("arm.npz", ["demo", "P1", "CB(10)", "flexarm 0.1"], [0, 0, -9.8])
    >>> "import flexarm" in text, 'DATA = HERE / "arm.npz"' in text
    (False, True)
    """
    robot, pose, label, versions = (str(v) for v in info)
    g = [float(v) for v in gravity]
    return (_TEMPLATE.replace("@ROBOT@", repr(robot)).replace("@POSE@", pose or "q")
            .replace("@LABEL@", label).replace("@VERSIONS@", versions)
            .replace("@DATA@", data_name)
            .replace("@SCRIPT@", data_name.rsplit(".", 1)[0] + ".py")
            .replace("@GRAVITY@", repr(g) if any(g) else "None"))
