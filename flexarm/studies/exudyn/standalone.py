"""The arm's Exudyn model as files that need Exudyn and NumPy only (``flexarm
export-exudyn``, the default ``--self-contained``).

:func:`write_standalone` writes, next to each other:

- ``<stem>.py``, the script (:mod:`~flexarm.studies.exudyn.script_standalone`): it
  builds the ``mbs`` from the files below with ``import exudyn`` and ``numpy`` alone and,
  run as a program, prints its eigenfrequencies next to flexarm's;
- ``<stem>.npz``, the assembly (:class:`StandaloneArm`, one array per field): body
  frames at the pose, rigid-body inertia, joint markers, springs and dampers, the TCP,
  gravity, flexarm's frequencies;
- ``<stem>_<i>_<link>.npz`` per flexible link, Exudyn's own
  ``ObjectFFRFreducedOrderInterface.SaveToFile`` file: the mode basis on the link's FE
  nodes, lumped-mass points and marker stars, the reduced mass and stiffness, and the
  floating-frame inertia integrals.

The assembly mirrors :func:`~flexarm.studies.exudyn.model.exudyn_arm` item by item, so
the script's system is that one (its frequencies equal ``flexarm modes``).
"""

from __future__ import annotations

import re
from collections.abc import Callable
from dataclasses import asdict, dataclass
from pathlib import Path

import numpy as np

from ... import __version__
from ...assembly.analyses import natural_frequencies
from ...assembly.arm import Arm
from ...fe.files import atomic_files, atomic_path, write_npz
from ...fe.typing import ArrayLike, FloatArray, IntArray
from ...robot.joints import joint_basis
from ...robot.kinematics import link_frames
from .bodies import FFRFLink
from .damping import ProportionalDamping, fit_damping
from .model import GRAVITY, _joint_stiffness, exportable, ffrf_interface, ffrf_links, require_exudyn
from .script_standalone import standalone_script

__all__ = ["StandaloneArm", "standalone_arm", "write_standalone", "link_file_name"]

#: Frequencies of flexarm's model stored for the script's check (the lowest ones).
N_FREQUENCIES = 24


@dataclass(frozen=True, eq=False)
class StandaloneArm:
    """Everything the standalone script needs besides the link files (SI units).

    Bodies ``i`` in chain order, joints ``j`` connecting ``joint_parent[j]`` to body
    ``j + 1``; "body frame" is a body's reference frame (the link frame).

    Attributes
    ----------
    body_names : (nb,) str
    frames : (nb, 4, 4) float
        Body frames at the pose in the base frame (rotation, position [m]).
    link_files : (nb,) str
        Exudyn CMS file of each flexible body, relative to the script ("" for rigid ones).
    mass : (nb,) float
        Rigid bodies: mass [kg] (0 for flexible ones).
    inertia : (nb, 3, 3) float
        Rigid bodies: inertia tensor about the body origin [kg m^2], body frame.
    com : (nb, 3) float
        Rigid bodies: centre of mass [m], body frame.
    beta : (nb,) float
        Flexible bodies: stiffness-proportional damping [s].
    foundation : (6, 6) float
        Base spring [N/m, N m/rad] between ground and base; all zeros: base clamped.
    foundation_tau : float
        Its damper time constant [s] (damping = tau x stiffness).
    joint_names : (nj,) str
    joint_parent : (nj,) int
    joint_nodes : (nj, 7) int
        Flexible parent: its mesh nodes of the joint point's marker star (point first);
        -1 for a rigid parent.
    joint_point : (nj, 3) float
        Joint point [m] in the parent's body frame.
    joint_rotation_parent, joint_rotation_child : (nj, 3, 3) float
        Joint frame (axis, radial 1, radial 2) in the parent's and the child's body frame.
    joint_locked : (nj, 6) int
        1 where the joint is rigid (translations x, y, z then rotations, joint frame).
    joint_stiffness, joint_damping : (nj, 6) float
        Diagonal springs [N/m, N m/rad] and dampers [N s/m, N m s/rad], joint frame.
    tcp_body : int
    tcp_nodes : (7,) int
        TCP marker star of a flexible TCP body (-1 when rigid).
    tcp_point : (3,) float
        TCP [m] in its body frame.
    tcp_position : (3,) float
        TCP [m] in the base frame at the pose.
    gravity : (3,) float
        [m/s^2], base frame (zeros: off).
    q : (n,) float
        The pose [rad].
    freq_hz : (k,) float
        flexarm's lowest natural frequencies of this model at ``q`` [Hz].
    info : (4,) str
        Robot, pose, model label, and the versions that wrote the files.
    """

    body_names: np.ndarray
    frames: FloatArray
    link_files: np.ndarray
    mass: FloatArray
    inertia: FloatArray
    com: FloatArray
    beta: FloatArray
    foundation: FloatArray
    foundation_tau: float
    joint_names: np.ndarray
    joint_parent: IntArray
    joint_nodes: IntArray
    joint_point: FloatArray
    joint_rotation_parent: FloatArray
    joint_rotation_child: FloatArray
    joint_locked: IntArray
    joint_stiffness: FloatArray
    joint_damping: FloatArray
    tcp_body: int
    tcp_nodes: IntArray
    tcp_point: FloatArray
    tcp_position: FloatArray
    gravity: FloatArray
    q: FloatArray
    freq_hz: FloatArray
    info: np.ndarray


def link_file_name(stem: str, i: int, name: str) -> str:
    """``<stem>_<i>_<name>.npz`` with the link name reduced to file-safe characters."""
    return f"{stem}_{i}_{re.sub(r'[^A-Za-z0-9_.-]+', '_', name)}.npz"


def _point(G: FloatArray) -> FloatArray:
    """Named point [m] from its rigid transport ``G[:3, 3:6] = -skew(p)``."""
    return np.array([G[1, 5], G[2, 3], G[0, 4]])


def _star(links: list, i: int, name: str) -> IntArray:
    return (np.full(7, -1, dtype=np.int64) if links[i] is None
            else np.asarray(links[i].points[name], dtype=np.int64))


def standalone_arm(arm: Arm, q: ArrayLike, links: list, stem: str = "arm_exudyn",
                   gravity: ArrayLike | None = GRAVITY,
                   damping: ProportionalDamping | None = None, pose: str = "") -> StandaloneArm:
    """The :class:`StandaloneArm` of ``arm`` at pose ``q`` (n,) [rad] with the
    :func:`~flexarm.studies.exudyn.model.ffrf_links` ``links``; link files named after
    ``stem``.  ``damping`` defaults to
    :func:`~flexarm.studies.exudyn.damping.fit_damping` at ``q``."""
    model = exportable(arm)
    q = np.asarray(q, dtype=float)
    F = link_frames(model.chain, q)
    pd = fit_damping(model, q) if damping is None else damping
    nb, chain = len(model.bodies), model.chain
    mass, inertia, com = np.zeros(nb), np.zeros((nb, 3, 3)), np.zeros((nb, 3))
    for i, (body, link) in enumerate(zip(model.bodies, links, strict=True)):
        if link is None:
            Mb = np.asarray(body.M, dtype=float)
            mass[i], inertia[i] = Mb[0, 0], Mb[3:6, 3:6]
            B = Mb[:3, 3:6] / Mb[0, 0]  # = -skew(c)
            com[i] = [B[1, 2], B[2, 0], B[0, 1]]
    nj = len(model.joints)
    parents = np.asarray(chain.parents[:nj], dtype=np.int64)
    Jb = np.array([joint_basis(chain.axes[j]) for j in range(nj)]).reshape(nj, 3, 3)
    R0 = np.array([F[p, :3, :3].T @ F[j + 1, :3, :3] @ Jb[j]
                   for j, p in enumerate(parents)]).reshape(nj, 3, 3)
    stiffness, locked, tau = np.zeros((nj, 6)), np.zeros((nj, 6), dtype=np.int64), np.zeros((nj, 6))
    for j, jm in enumerate(model.joints):
        k, lk = _joint_stiffness(jm)
        stiffness[j], locked[j] = k, lk
        tau[j, jm.free_dofs] = pd.joint_tau[j]
    c, tcp = chain.tcp_body, model.tcp_point
    G = model.bodies[c].points[tcp]
    info = np.array([arm.robot.name, pose, arm.spec.label,
                     f"flexarm {__version__}, exudyn {require_exudyn().__version__}"])
    return StandaloneArm(
        body_names=np.array([b.name for b in model.bodies]), frames=np.asarray(F, dtype=float),
        link_files=np.array(["" if lk is None else link_file_name(stem, i, lk.name)
                             for i, lk in enumerate(links)]),
        mass=mass, inertia=inertia, com=com, beta=np.asarray(pd.link_beta, dtype=float),
        foundation=(np.zeros((6, 6)) if model.foundation is None
                    else np.asarray(model.foundation, dtype=float)),
        foundation_tau=float(pd.foundation_tau), joint_names=np.array(arm.robot.joint_names),
        joint_parent=parents,
        joint_nodes=np.array([_star(links, p, model.joint_points[j])
                              for j, p in enumerate(parents)]).reshape(nj, 7),
        joint_point=np.array([_point(model.bodies[p].points[model.joint_points[j]])
                              for j, p in enumerate(parents)]).reshape(nj, 3),
        joint_rotation_parent=R0, joint_rotation_child=Jb, joint_locked=locked,
        joint_stiffness=stiffness, joint_damping=tau * stiffness,
        tcp_body=int(c), tcp_nodes=_star(links, c, tcp), tcp_point=_point(G),
        tcp_position=F[c, :3, :3] @ _point(G) + F[c, :3, 3],
        gravity=np.zeros(3) if gravity is None else np.asarray(gravity, dtype=float),
        q=q, freq_hz=natural_frequencies(model, q)[:N_FREQUENCIES], info=info)


def write_standalone(path, arm: Arm, q: ArrayLike, pose: str = "",
                     gravity: ArrayLike | None = GRAVITY, links: list | None = None,
                     progress: Callable[[str], None] | None = None) -> list[Path]:
    """Write the script ``path`` (``.py``), its ``.npz`` and the link files beside it
    (module docstring), every file or none (:func:`~flexarm.fe.files.atomic_files`:
    Ctrl-C or a full disk leave an older export as it was), the script last; returns
    the written paths, script first."""
    path = Path(path)
    if path.suffix != ".py":
        raise ValueError(f"{path}: the Exudyn model is written as a Python script (.py)")
    require_exudyn()
    links = ffrf_links(arm, progress) if links is None else links
    sa = standalone_arm(arm, q, links, path.stem, gravity, pose=pose)
    flexible = [(path.with_name(str(name)), link)
                for name, link in zip(sa.link_files, links, strict=True) if link is not None]
    written = [path, path.with_suffix(".npz"), *(p for p, _ in flexible)]
    with atomic_files(*written) as (script, data, *link_files):
        for tmp, (_, link) in zip(link_files, flexible, strict=True):
            _write_link(tmp, link)
        with atomic_path(data) as tmp:
            write_npz(tmp, asdict(sa))
        with atomic_path(script) as tmp:
            tmp.write_text(standalone_script(written[1].name, sa.info, sa.gravity))
    return written


def _write_link(path: Path, link: FFRFLink) -> None:
    cms = ffrf_interface(link)
    with atomic_path(path) as tmp:
        cms.SaveToFile(str(tmp))  # Exudyn keeps a name ending in .npz as it is
