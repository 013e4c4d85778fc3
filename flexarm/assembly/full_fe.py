"""Full-FE reference: the arm at a pose with *unreduced* links (the truth of every study).

Each link is its coupled FE model (:func:`~flexarm.reduction.coupled_model`: the same
regions and RBE2/RBE3 couplings the reduction uses, so the master nodes are the same
6-DOF seat nodes), written in the floating-frame coordinates of
:func:`~flexarm.assembly.flexible.body_coordinates`: the joint point's motion, the
other seats' elastic motion, then every interior FE DOF in the link frame.  The
bodies are joined exactly as in :func:`~flexarm.assembly.system.system_matrices`
(same joint models with rigid directions eliminated, same base support, same tool),
but with sparse matrices: only each body's proximal 6 rows depend on the pose.

One sparse factorisation of ``K`` (fast backend, :func:`flexarm.fe.factorize`) serves
both the TCP compliance (6 solves) and the shift-invert eigen-solve at ``sigma = 0``.
"""

from __future__ import annotations

import logging
import time
from collections.abc import Callable, Mapping
from dataclasses import dataclass

import numpy as np
import scipy.sparse as sp

from ..fe.eigen import modes as fe_modes
from ..fe.eigen import shift_invert
from ..fe.mass_properties import rigid_body_mass_matrix
from ..fe.solvers import factorize
from ..fe.typing import ArrayLike, FloatArray
from ..reduction import coupled_model
from ..robot.description import Robot
from ..robot.joints import joint_basis
from ..robot.kinematics import link_frames
from .bodies import point_mass_properties, rigid_transport
from .build import BuildOptions, Mesher, cylinder_regions, link_material, link_mesh, link_regions
from .emodel import link_mass_properties
from .system import ArmModel, rotation_blocks

__all__ = ["SparseBody", "FullFEModel", "full_fe_bodies", "sparse_bodies", "full_fe_matrices",
           "FullFEResult", "full_fe_analysis"]

log = logging.getLogger(__name__)


@dataclass(frozen=True, eq=False)
class SparseBody:
    """A body in floating-frame coordinates with sparse matrices (link frame).

    Attributes
    ----------
    name : str
    K, M : (n_b, n_b) sparse CSR
        First six DOFs: the proximal joint point (rotating with the link); the rest
        are link-frame quantities.
    points : mapping str -> (6, n_b) sparse CSR
        Attachment points (link frame).
    recovery : ((k, 3) float, (3 k, n_b) sparse CSR) or None
        The link's FE surface nodes: their link-frame positions [m] and their x, y, z
        translation [m] from the body coordinates (couplings included), for shapes at
        measurement points; None for a rigid body.
    """

    name: str
    K: sp.csr_matrix
    M: sp.csr_matrix
    points: Mapping[str, sp.csr_matrix]
    recovery: tuple | None = None

    @property
    def n_dofs(self) -> int:
        return int(self.K.shape[0])


def _interior_fe_dofs(coupling) -> np.ndarray:
    """(n_interior,) FE DOF of each interior coupled DOF (its own identity row of ``T``)."""
    T = coupling.T.tocsr()
    nnz = np.diff(T.indptr)
    rows = np.flatnonzero(nnz == 1)
    cols = T.indices[T.indptr[rows]]
    own = (cols < coupling.n_interior) & (T.data[T.indptr[rows]] == 1.0)
    out = np.full(coupling.n_interior, -1, dtype=np.int64)
    out[cols[own]] = rows[own]
    if np.any(out < 0):
        raise AssertionError("coupling T lost an interior DOF")  # internal invariant
    return out


def _floating_frame(coupling, points: np.ndarray, nodes: np.ndarray) -> sp.csr_matrix:
    """(n, n) ``S``: body DOFs [boundary; interior] from floating-frame coordinates.

    Every DOF is the rigid motion carried from the joint point (link origin) plus
    its own elastic coordinate; the first six coordinates are the joint point's motion
    (node 0 has no elastic coordinate of its own).
    """
    n = coupling.n_coupled
    fe = _interior_fe_dofs(coupling)
    Rb = rigid_transport(nodes).reshape(-1, 6)  # (nb, 6) boundary rows
    Ri = _translation_rows(points[fe // 3])[np.arange(fe.size), fe % 3]
    rows_t = np.vstack([Rb, Ri])  # (n, 6)
    r = np.repeat(np.arange(n), 6)
    c = np.tile(np.arange(6), n)
    diag = np.arange(6, n)
    return sp.csr_matrix((np.r_[rows_t.ravel(), np.ones(diag.size)], (np.r_[r, diag],
                                                                      np.r_[c, diag])),
                         shape=(n, n))


def _translation_rows(p: np.ndarray) -> np.ndarray:
    """(k, 3, 6) translation of points ``p`` (k, 3) [m] under the link-origin motion."""
    return rigid_transport(p)[:, :3, :]


def _fe_body(robot: Robot, i: int, opts: BuildOptions, mesher: Mesher | None) -> SparseBody:
    lk = robot.links[i]
    chain = robot.chain
    names = link_regions(robot, i, opts.tcp)
    att = {jt.name: np.asarray(jt.origin, float) for j, jt in enumerate(robot.joints)
           if int(chain.parents[j]) == i}
    if i == chain.tcp_body:
        att["tcp"] = chain.tool[:3, 3]
    if not names:  # rigid base
        mp = link_mass_properties(lk, "tets", opts.mesh_size, robot.options.mesher)
        pts = {k: sp.csr_matrix(rigid_transport(p)) for k, p in att.items()}
        return SparseBody(lk.name, sp.csr_matrix((6, 6)),
                          sp.csr_matrix(rigid_body_mass_matrix(mp, np.zeros(3))), pts)
    mesh = (mesher(lk, opts.mesh_size, opts.order) if mesher
            else link_mesh(lk, opts.mesh_size, opts.order, mesher=robot.options.mesher))
    cm = coupled_model(mesh, link_material(lk, opts.stiffness_scale),
                       cylinder_regions(lk, names), opts.coupling)
    c = cm.coupling
    n, nb = c.n_coupled, c.n_boundary
    order = np.concatenate([np.arange(n - nb, n), np.arange(n - nb)])  # boundary first
    nodes = np.asarray(c.node_positions, dtype=float)
    S = _floating_frame(c, mesh.points, nodes)
    P = sp.csr_matrix((np.ones(n), (order, np.arange(n))), shape=(n, n))
    P = (P @ S).tocsr()  # coupled DOFs from body coordinates
    D = sp.diags(np.r_[np.zeros(6), np.ones(n - 6)])
    K = (D @ (P.T @ cm.K @ P) @ D).tocsr()
    M = (P.T @ cm.M @ P).tocsr()
    Sb = S[:nb]  # boundary node DOFs from body coordinates
    for m in lk.lumped:
        mp = point_mass_properties(m.mass, m.position, m.inertia)
        k = int(np.argmin(np.linalg.norm(nodes - mp.center_of_mass, axis=1)))
        L = Sb[6 * k : 6 * k + 6]
        M = M + L.T @ sp.csr_matrix(rigid_body_mass_matrix(mp, nodes[k])) @ L
    pts = {}
    for key, p in att.items():
        k = names.index(key) if key in names else 0
        pts[key] = (sp.csr_matrix(rigid_transport(p - nodes[k])) @ Sb[6 * k : 6 * k + 6]).tocsr()
    K = 0.5 * (K + K.T)
    M = 0.5 * (M + M.T)
    return SparseBody(lk.name, K.tocsr(), M.tocsr(), pts, _recovery(c, mesh, P))


def _recovery(coupling, mesh, P: sp.csr_matrix) -> tuple:
    """:attr:`SparseBody.recovery`: the surface nodes' FE displacements ``T P`` from
    the body coordinates (``P``: coupled DOFs from body coordinates)."""
    surface = np.unique(mesh.boundary_faces())
    rows = (3 * surface[:, None] + np.arange(3)).ravel()
    return (np.asarray(mesh.points, float)[surface],
            (coupling.T.tocsr()[rows] @ P).tocsr())


def full_fe_bodies(robot: Robot,
                   options: BuildOptions = BuildOptions(),  # noqa: B008 (frozen)
                   mesher: Mesher | None = None,
                   progress: Callable[[str], None] | None = None) -> tuple[SparseBody, ...]:
    """Unreduced coupled FE model of every link (same meshes/regions as the build)."""
    opts = options.resolved(robot)
    out = []
    for i, lk in enumerate(robot.links):
        if progress:
            progress(f"{lk.name}: full FE model")
        out.append(_fe_body(robot, i, opts, mesher))
    return tuple(out)


def sparse_bodies(arm: ArmModel) -> tuple[SparseBody, ...]:
    """The dense bodies of an :class:`ArmModel` as :class:`SparseBody` s.

    Only valid for bodies with a single six-DOF node (rigid or floating-frame
    flexible bodies), whose other DOFs do not rotate.
    """
    if any(b.n_nodes != 1 for b in arm.bodies):
        raise ValueError("sparse_bodies needs one-node bodies (floating-frame coordinates)")
    return tuple(SparseBody(b.name, sp.csr_matrix(b.K), sp.csr_matrix(b.M),
                            {k: sp.csr_matrix(G) for k, G in b.points.items()})
                 for b in arm.bodies)


@dataclass(frozen=True, eq=False)
class FullFEModel:
    """Sparse system matrices at one pose.

    Attributes
    ----------
    K, M : (n_x, n_x) sparse CSR
        Stiffness and mass on the independent coordinates.
    G_tcp : (6, n_x) sparse CSR
        TCP motion (base frame) from the coordinates.
    body_maps : tuple of (n_b, n_x) sparse CSR
        Each body's coordinates (link frame) from the independent coordinates.
    springs : (n_s, n_s) float or None
        Foundation and joint springs on the first ``n_s`` coordinates (the foundation's
        first, then each joint's free directions in joint order).
    joint_slices : tuple of slice
        Each joint's coordinates within the first ``n_s``.
    """

    K: sp.csr_matrix
    M: sp.csr_matrix
    G_tcp: sp.csr_matrix
    body_maps: tuple = ()
    springs: FloatArray | None = None
    joint_slices: tuple = ()

    @property
    def n_dofs(self) -> int:
        return int(self.K.shape[0])


def full_fe_matrices(arm: ArmModel, bodies: tuple[SparseBody, ...], q: ArrayLike) -> FullFEModel:
    """Join sparse ``bodies`` with ``arm``'s joints, base and tool at pose ``q`` (n,) [rad].

    ``arm`` supplies kinematics, joint models, attachment names, foundation and
    wrist stiffness (its own bodies are ignored).
    """
    chain = arm.chain
    q = np.asarray(q, dtype=float)
    F = link_frames(chain, q)
    n_j = [len(jm.free_dofs) for jm in arm.joints]
    n_f = 6 if arm.foundation is not None else 0
    starts = np.cumsum([n_f + sum(n_j)] + [b.n_dofs - 6 for b in bodies])
    n_x = int(starts[-1])
    j_start = n_f + np.r_[0, np.cumsum(n_j)].astype(int)
    Ks = np.zeros((starts[0], starts[0]))
    Ks[:n_f, :n_f] = arm.foundation if n_f else 0.0
    for j, jm in enumerate(arm.joints):
        idx = np.arange(j_start[j], j_start[j + 1])
        Ks[idx, idx] = jm.free_stiffness
    if arm.wrist_stiffness is not None:
        n = chain.n_joints
        tors = [j_start[j] + list(arm.joints[j].free_dofs).index(3) for j in range(n - 3, n)]
        Ks[np.ix_(tors, tors)] = np.asarray(arm.wrist_stiffness, dtype=float)
    B: list[sp.csr_matrix] = []
    K = sp.block_diag([sp.csr_matrix(Ks), sp.csr_matrix((n_x - starts[0],) * 2)], format="csr")
    M = sp.csr_matrix((n_x, n_x))
    for i, b in enumerate(bodies):
        R6 = rotation_blocks(F[i, :3, :3], 6, 1)
        if i == 0:  # clamped, or the foundation coordinates (base frame = link-0 frame)
            top = sp.hstack([sp.csr_matrix(R6.T if n_f else (6, 6)),
                             sp.csr_matrix((6, n_x - 6))]).tocsr()
        else:
            j = i - 1
            p = int(chain.parents[j])
            Rp = rotation_blocks(F[p, :3, :3], 6, 1)
            base = sp.csr_matrix(Rp) @ bodies[p].points[arm.joint_points[j]] @ B[p]
            RJ = F[i, :3, :3] @ joint_basis(chain.axes[j])
            E = rotation_blocks(RJ, 6, 1)[:, arm.joints[j].free_dofs]
            Ej = sp.csr_matrix((E.ravel(), (np.repeat(np.arange(6), E.shape[1]),
                                            np.tile(np.arange(j_start[j], j_start[j + 1]), 6))),
                               shape=(6, n_x))
            top = sp.csr_matrix(R6.T) @ (base + Ej)
        m = b.n_dofs - 6
        rest = sp.csr_matrix((np.ones(m), (np.arange(m), starts[i] + np.arange(m))),
                             shape=(m, n_x))
        Bi = sp.vstack([top, rest]).tocsr()
        Bi.eliminate_zeros()
        B.append(Bi)
        K = K + Bi.T @ b.K @ Bi
        M = M + Bi.T @ b.M @ Bi
    c = chain.tcp_body
    Rc = rotation_blocks(F[c, :3, :3], 6, 1)
    G = (sp.csr_matrix(Rc) @ bodies[c].points[arm.tcp_point] @ B[c]).tocsr()
    K = 0.5 * (K + K.T)
    M = 0.5 * (M + M.T)
    joints = tuple(slice(int(a), int(b)) for a, b in zip(j_start[:-1], j_start[1:], strict=True))
    return FullFEModel(K.tocsr(), M.tocsr(), G, tuple(B), Ks, joints)


@dataclass(frozen=True)
class FullFEResult:
    """Modes and TCP compliance of the full-FE model at one pose.

    Attributes
    ----------
    freq_hz : (n,) float
        Lowest natural frequencies [Hz].
    C : (6, 6) float
        TCP compliance (base frame) [m/N, rad/(N m)].
    n_dofs : int
        Independent coordinates of the full model.
    seconds : dict
        Wall times [s] of assembly, factorisation, compliance and eigen-solve.
    tcp_shapes : (6, n) float, optional
        TCP motion of each mode (base frame) [m, rad], in the order of ``freq_hz``: what
        pairs these modes with another model's by MAC.
    """

    freq_hz: FloatArray
    C: FloatArray
    n_dofs: int
    seconds: dict
    tcp_shapes: FloatArray | None = None


def full_fe_analysis(arm: ArmModel, bodies: tuple[SparseBody, ...], q: ArrayLike,
                     n_modes: int = 10, backend: str | None = None) -> FullFEResult:
    """Lowest ``n_modes`` frequencies and the TCP compliance with one factorisation of K."""
    t0 = time.perf_counter()
    mdl = full_fe_matrices(arm, bodies, q)
    t1 = time.perf_counter()
    f = factorize(mdl.K, backend=backend, spd=True)
    t2 = time.perf_counter()
    Gt = mdl.G_tcp.toarray().T
    C = Gt.T @ f.solve(Gt)
    t3 = time.perf_counter()
    md = fe_modes(mdl.K, mdl.M, n_modes, eigensolver=shift_invert(0.0, backend), factor=f)
    t4 = time.perf_counter()
    log.info("full FE: %d DOF, %d modes in %.1f s", mdl.n_dofs, n_modes, t4 - t0)
    order = np.argsort(md.freq_hz)
    return FullFEResult(md.freq_hz[order], 0.5 * (C + C.T), mdl.n_dofs,
                        {"assemble": t1 - t0, "factorise": t2 - t1, "compliance": t3 - t2,
                         "eigen": t4 - t3}, (Gt.T @ md.vectors)[:, order])
