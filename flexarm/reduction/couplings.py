"""Couplings of interface regions onto their master DOFs, as exact transformations.

Every coupling is one sparse matrix ``T`` with ``u = T x``: ``u`` (3 n_nodes,) are the
FE DOFs, ``x = [x_interior; x_boundary]`` the *coupled* DOFs.  The boundary block holds
the masters, 6 per interface node (or 3 per kept region node), in interface order, so
a reduction only has to split ``x`` at ``n_interior``.  No penalty numbers anywhere:

* ``rbe2``: rigid spider.  Every slave DOF is eliminated: ``u_s = u_m + theta_m x r_s``.
* ``rbe3``: weighted average, no added stiffness.  The master motion is the weighted
  least-squares rigid fit of the slave motion, ``q_m = W u_S`` with weights = tributary
  surface area.  To make the master an *independent* DOF (the one a superelement is
  reduced onto) six slave DOFs are made dependent instead, chosen by pivoted QR of ``W``
  (like Nastran's UM set), and solved from the constraint:
  ``u_d = W_d^-1 (q_m - W_o u_o)``.  All other slaves stay free, so the only thing the
  coupling adds is the averaging constraint itself.
* ``nodes``: ``k`` region nodes (3 DOFs each, farthest-point sampled) or all of them are
  the masters; the other region nodes stay free.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import scipy.linalg as sla
import scipy.sparse as sp

from ..fe.geometry import skew
from ..fe.mesh import TET10_EDGES, TET_FACES, TetMesh
from ..fe.topology import single_rows
from ..fe.typing import FloatArray, IntArray
from .interfaces import Interface, check_spread

__all__ = [
    "Coupling",
    "couple",
    "tributary_areas",
    "farthest_points",
    "rigid_transport",
    "rbe3_weights_matrix",
    "COUPLINGS",
]

COUPLINGS = ("rbe2", "rbe3", "nodes")


def rigid_transport(r: FloatArray) -> FloatArray:
    """(..., 3, 6) translation of points at offsets ``r`` (..., 3) [m] from a 6-DOF node.

    ``u_p = [I, -S(r)] [u; theta] = u + theta x r``.

    >>> rigid_transport(np.array([1.0, 0, 0])) @ [0, 0, 0, 0, 0, 1.0]
    array([0., 1., 0.])
    """
    r = np.asarray(r, dtype=float)
    R = np.zeros(r.shape[:-1] + (3, 6))
    R[..., :, :3] = np.eye(3)
    R[..., :, 3:] = -skew(r)
    return R


@dataclass(frozen=True, eq=False)
class Coupling:
    """Transformation from coupled DOFs to FE DOFs.

    Attributes
    ----------
    T : (3 n_nodes, n_coupled) sparse CSR
        ``u = T x`` with ``x = [interior; boundary]``.
    n_boundary : int
        Master DOFs, last in ``x``: ``dofs_per_node`` per boundary node.
    kind : {"rbe2", "rbe3", "nodes"}
    dofs_per_node : {6, 3}
    node_positions : (n_b, 3) float
        Boundary (master) node positions [m].
    node_interface : (n_b,) int
        Index of the interface each boundary node belongs to.
    master_nodes : (n_b,) int
        FE node of each master (``-1`` for a coupled 6-DOF node).
    """

    T: sp.csr_matrix
    n_boundary: int
    kind: str
    dofs_per_node: int
    node_positions: FloatArray
    node_interface: IntArray
    master_nodes: IntArray

    @property
    def n_coupled(self) -> int:
        return int(self.T.shape[1])

    @property
    def n_interior(self) -> int:
        return self.n_coupled - self.n_boundary


def _boundary_triangles(mesh: TetMesh) -> np.ndarray:
    """(f, 3) int triangles of the boundary, Tet10 faces split into 4 sub-triangles."""
    faces = mesh.corner_tets[:, TET_FACES].reshape(-1, 3)
    on_b = single_rows(faces, mesh.n_nodes)
    if mesh.order == 1:
        return faces[on_b]
    # Local mid-edge node of each ordered corner pair of a Tet10.
    mid = np.zeros((4, 4), dtype=np.int64)
    mid[TET10_EDGES[:, 0], TET10_EDGES[:, 1]] = np.arange(4, 10)
    mid[TET10_EDGES[:, 1], TET10_EDGES[:, 0]] = np.arange(4, 10)
    loc = np.concatenate([TET_FACES, mid[TET_FACES, np.roll(TET_FACES, -1, axis=1)]], axis=1)
    f6 = mesh.tets[:, loc].reshape(-1, 6)[on_b]  # c0, c1, c2, m01, m12, m20
    c0, c1, c2, m01, m12, m20 = f6.T
    return np.concatenate([
        np.column_stack([c0, m01, m20]), np.column_stack([m01, c1, m12]),
        np.column_stack([m20, m12, c2]), np.column_stack([m01, m12, m20]),
    ])


def tributary_areas(mesh: TetMesh) -> FloatArray:
    """(n_nodes,) surface area [m^2] attributed to each node (a third of each triangle).

    Tet10 boundary faces are split into their four sub-triangles first, so mid-edge
    nodes get area too.  Interior nodes get 0.

    >>> a = tributary_areas(TetMesh.box((1.0, 1.0, 1.0), (2, 2, 2)))
    >>> round(float(a.sum()), 12)  # six unit faces
    6.0
    """
    tri = _boundary_triangles(mesh)
    p = mesh.points[tri]
    area = 0.5 * np.linalg.norm(np.cross(p[:, 1] - p[:, 0], p[:, 2] - p[:, 0]), axis=1)
    return np.bincount(tri.ravel(), np.repeat(area / 3.0, 3), minlength=mesh.n_nodes)


def farthest_points(points: FloatArray, k: int) -> IntArray:
    """(k,) indices into ``points`` (n, 3) spread by farthest-point sampling.

    Starts at the point farthest from the centroid (lowest index on ties), then adds
    the point farthest from all chosen ones.  Deterministic.

    >>> farthest_points(np.array([[0, 0, 0], [1, 0, 0], [0.4, 0, 0]], float), 2).tolist()
    [1, 0]
    """
    pts = np.asarray(points, dtype=float)
    k = min(int(k), len(pts))
    chosen = [int(np.argmax(np.linalg.norm(pts - pts.mean(axis=0), axis=1)))]
    dist = np.linalg.norm(pts - pts[chosen[0]], axis=1)
    for _ in range(k - 1):  # one pass per master, vectorised over the region
        nxt = int(np.argmax(dist))
        chosen.append(nxt)
        dist = np.minimum(dist, np.linalg.norm(pts - pts[nxt], axis=1))
    return np.array(chosen, dtype=np.int64)


def rbe3_weights_matrix(points: FloatArray, weights: FloatArray, ref: FloatArray) -> FloatArray:
    """(6, 3k) ``W``: master [u; theta] at ``ref`` as the weighted rigid fit of slave motion.

    Minimises ``sum_i w_i |u_i - u_m - theta_m x r_i|^2``; a rigid slave motion is
    reproduced exactly.  ``points`` (k, 3) [m], ``weights`` (k,) > 0.
    """
    R = rigid_transport(points - ref)  # (k, 3, 6)
    G = np.einsum("k,kai,kaj->ij", weights, R, R)
    Rw = R * weights[:, None, None]
    return np.linalg.solve(G, Rw.reshape(-1, 6).T)


def _node_masters(mesh: TetMesh, itf: Interface, n_masters: int | None) -> IntArray:
    """(k,) FE nodes of one region kept as 3-DOF masters, in region order.

    ``n_masters`` nodes spread by farthest-point sampling, or all region nodes (None).
    """
    pts = mesh.points[itf.nodes]
    pick = np.arange(len(pts)) if n_masters is None else farthest_points(pts, n_masters)
    check_spread(itf.name, pts[pick], "master nodes")
    return itf.nodes[np.sort(pick)]


def _rbe2_rows(mesh: TetMesh, itf: Interface, mcols: IntArray) -> tuple[IntArray, list]:
    """Rigid spider of one interface: (eliminated FE DOFs, their row blocks).

    Each block is ``(rows, cols_fe, cols_master, values)`` with ``-1`` where the column
    is not of that kind; ``mcols`` (6,) are the master's columns in the boundary block.
    """
    pts = mesh.points[itf.nodes]
    dofs = (3 * itf.nodes[:, None] + np.arange(3)).ravel()
    R = rigid_transport(pts - itf.position).reshape(-1, 6)
    block = (np.repeat(dofs, 6), np.full(R.size, -1), np.tile(mcols, len(dofs)), R.ravel())
    return dofs, [block]


def _rbe3_rows(mesh: TetMesh, itf: Interface, areas: FloatArray,
               mcols: IntArray) -> tuple[IntArray, list]:
    """Weighted-average master of one interface: (dependent FE DOFs, their row blocks).

    Blocks as in :func:`_rbe2_rows`; ``areas`` (n_nodes,) [m^2] are the tributary areas
    weighting the slaves.
    """
    pts = mesh.points[itf.nodes]
    w = areas[itf.nodes]
    if not w.sum() > 0:  # a node set off the surface: no area, plain average
        w = np.ones_like(w)
    live = w > 0
    check_spread(itf.name, pts[live], "nodes with surface area")
    W = rbe3_weights_matrix(pts[live], w[live], itf.position)
    live_dofs = (3 * itf.nodes[live][:, None] + np.arange(3)).ravel()
    # Pivoted QR picks the six slave DOFs W depends on most, so W_d is well conditioned.
    piv = sla.qr(W, pivoting=True, mode="r")[1]
    dep, oth = np.sort(piv[:6]), np.sort(piv[6:])
    Wd_inv = np.linalg.inv(W[:, dep])
    A_m = Wd_inv  # (6 dep, 6 master)
    A_o = -Wd_inv @ W[:, oth]  # (6 dep, n_other)
    rows = live_dofs[dep]
    return rows, [
        (np.repeat(rows, 6), np.full(36, -1), np.tile(mcols, 6), A_m.ravel()),
        (np.repeat(rows, len(oth)), np.tile(live_dofs[oth], 6), np.full(A_o.size, -1),
         A_o.ravel()),
    ]


def _transformation(n_full: int, elim_all: IntArray, bnd_fe: IntArray, blocks: list,
                    n_b: int) -> sp.csr_matrix:
    """``T`` (n_full, n_interior + n_b): identity on the kept FE DOFs, then the blocks.

    Parameters
    ----------
    n_full : int
        FE DOFs.
    elim_all : (m,) int
        FE DOFs that are not interior (eliminated slaves, or kept node masters).
    bnd_fe : (k,) int
        FE DOFs that are themselves boundary DOFs (``nodes`` coupling; else empty).
    blocks : list of (rows, cols_fe, cols_master, values)
        Rows of eliminated DOFs; a column is an FE DOF (``cols_fe >= 0``) or a master
        DOF (``cols_master``, counted from the start of the boundary block).
    n_b : int
        Boundary (master) DOFs.
    """
    keep = np.ones(n_full, dtype=bool)
    keep[elim_all] = False
    interior = np.flatnonzero(keep)
    n_int = interior.size
    col_of = np.full(n_full, -1, dtype=np.int64)
    col_of[interior] = np.arange(n_int)
    col_of[bnd_fe] = n_int + np.arange(bnd_fe.size)
    rows = [interior, bnd_fe]
    cols = [np.arange(n_int), n_int + np.arange(bnd_fe.size)]
    vals = [np.ones(n_int), np.ones(bnd_fe.size)]
    for r, cf, cm, v in blocks:
        c = np.where(cf >= 0, col_of[np.maximum(cf, 0)], n_int + cm)
        rows.append(r), cols.append(c), vals.append(v)
    T = sp.csr_matrix(
        (np.concatenate(vals), (np.concatenate(rows), np.concatenate(cols))),
        shape=(n_full, n_int + n_b),
    )
    T.sum_duplicates()
    T.sort_indices()
    return T


def couple(mesh: TetMesh, ifaces: tuple[Interface, ...], kind: str = "rbe2",
           n_masters: int | None = None) -> Coupling:
    """The coupling transformation of all interfaces.

    Parameters
    ----------
    mesh : TetMesh
    ifaces : tuple of Interface
        Checked interfaces (see :func:`~flexarm.reduction.interfaces.interfaces`).
    kind : {"rbe2", "rbe3", "nodes"}
    n_masters : int, optional
        For ``kind="nodes"``: masters per region (``None`` = all region nodes).

    Examples
    --------
    >>> from flexarm.reduction.interfaces import CylinderRegion, interfaces
    >>> m = TetMesh.box((1.0, 0.1, 0.1), (4, 1, 1))
    >>> a = CylinderRegion("a", (0, .05, .05), (1, 0, 0), 0, 1, 1e-3)
    >>> c = couple(m, interfaces(m, [a]), "rbe2")
    >>> c.T.shape, c.n_boundary
    ((60, 54), 6)
    """
    if kind not in COUPLINGS:
        raise ValueError(f"coupling must be one of {', '.join(COUPLINGS)}, got '{kind}'")
    dpn = 3 if kind == "nodes" else 6
    areas = tributary_areas(mesh) if kind == "rbe3" else None
    # Per interface: eliminated FE DOFs, their rows over (FE-DOF or master) columns.
    elim: list[np.ndarray] = []
    blocks = []  # (rows, cols_fe (-1 if master), cols_master (-1 if fe), values)
    positions, owners, masters = [], [], []
    n_b_nodes = 0
    for i, itf in enumerate(ifaces):
        if kind == "nodes":
            nodes = _node_masters(mesh, itf, n_masters)
            positions.append(mesh.points[nodes])
            owners.append(np.full(len(nodes), i))
            masters.append(nodes)
            n_b_nodes += len(nodes)
            continue
        positions.append(itf.position[None])
        owners.append(np.array([i]))
        masters.append(np.array([-1]))
        mcols = 6 * n_b_nodes + np.arange(6)
        n_b_nodes += 1
        if kind == "rbe2":
            dofs, rows = _rbe2_rows(mesh, itf, mcols)
        else:
            dofs, rows = _rbe3_rows(mesh, itf, areas, mcols)
        elim.append(dofs)
        blocks += rows
    if kind == "nodes":
        bnd_fe = (3 * np.concatenate(masters)[:, None] + np.arange(3)).ravel()
        elim_all = bnd_fe
    else:
        bnd_fe = np.zeros(0, dtype=np.int64)
        elim_all = np.concatenate(elim)
    n_b = dpn * n_b_nodes
    T = _transformation(mesh.n_dofs, elim_all, bnd_fe, blocks, n_b)
    return Coupling(T, n_b, kind, dpn, np.concatenate(positions), np.concatenate(owners),
                    np.concatenate(masters))
