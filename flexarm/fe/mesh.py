"""The tetrahedral mesh every layer shares.

Node order of a Tet10 follows VTK (and meshio's ``tetra10``): corners 0-3, then the
mid-edge nodes of edges (0,1), (1,2), (0,2), (0,3), (1,3), (2,3).
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, field, replace
from types import MappingProxyType

import numpy as np

from .errors import MeshError
from .notebook import names
from .structured import box_tets, promote_tet10
from .tolerances import tol
from .topology import TET10_EDGES, TET_FACES, outer_faces, single_rows

__all__ = ["TetMesh", "TET10_EDGES", "TET_FACES"]



def _frozen_sets(node_sets: Mapping[str, np.ndarray] | None) -> Mapping[str, np.ndarray]:
    out = {}
    for name, ids in (node_sets or {}).items():
        arr = np.asarray(ids, dtype=np.int64).ravel()
        arr.setflags(write=False)
        out[str(name)] = arr
    return MappingProxyType(out)


@dataclass(frozen=True, eq=False)
class TetMesh:
    """A linear (Tet4) or quadratic (Tet10) tetrahedral mesh.

    Parameters
    ----------
    points : (n, 3) float
        Node coordinates [m] in the part's own frame.
    tets : (m, 4) or (m, 10) int
        Node indices per element, VTK order, positive orientation.
    node_sets : mapping of str to (k,) int, optional
        Named node sets (e.g. ``"fixed"``, an interface region).

    Examples
    --------
    >>> mesh = TetMesh.unit_tet()
    >>> mesh.n_nodes, mesh.n_tets, mesh.order
    (4, 1, 1)
    >>> float(mesh.volumes().sum())  # 1/6 m^3
    0.16666666666666666
    """

    points: np.ndarray
    tets: np.ndarray
    node_sets: Mapping[str, np.ndarray] = field(default_factory=dict)

    def __post_init__(self) -> None:
        points = np.ascontiguousarray(self.points, dtype=np.float64)
        tets = np.ascontiguousarray(self.tets, dtype=np.int64)
        if points.ndim != 2 or points.shape[1] != 3:
            raise ValueError(f"points must be (n, 3), got {points.shape}")
        if tets.ndim != 2 or tets.shape[1] not in (4, 10):
            raise ValueError(f"tets must be (m, 4) or (m, 10), got {tets.shape}")
        if tets.size and (tets.min() < 0 or tets.max() >= len(points)):
            bad = int(tets.min()) if tets.min() < 0 else int(tets.max())
            raise MeshError(f"tets reference node {bad} but the mesh has {len(points)} nodes")
        sets = _frozen_sets(self.node_sets)
        for name, ids in sets.items():
            if ids.size and (ids.min() < 0 or ids.max() >= len(points)):
                raise MeshError(f"node set '{name}' references nodes outside the mesh")
        points.setflags(write=False)
        tets.setflags(write=False)
        object.__setattr__(self, "points", points)
        object.__setattr__(self, "tets", tets)
        object.__setattr__(self, "node_sets", sets)

    def __repr__(self) -> str:
        """One line: element type, counts, bounding box [m], volume [m^3], node sets.

        Examples
        --------
        >>> TetMesh.box((0.4, 0.04, 0.04), (4, 1, 1))
        TetMesh(Tet4, 20 nodes, 24 elements, box [0, 0.4] x [0, 0.04] x [0, 0.04] m, \
volume 0.00064 m^3)
        """
        kind = "Tet4" if self.order == 1 else "Tet10"
        text = f"TetMesh({kind}, {self.n_nodes} nodes, {self.n_tets} elements"
        if self.n_nodes:
            lo, hi = self.bounds()
            box = " x ".join(f"[{a:.4g}, {b:.4g}]" for a, b in zip(lo, hi, strict=True))
            text += f", box {box} m, volume {float(self.volumes().sum()):.4g} m^3"
        if self.node_sets:
            text += f", node sets {names(self.node_sets)}"
        return text + ")"

    # ---------------------------------------------------------------- sizes
    @property
    def n_nodes(self) -> int:
        return int(self.points.shape[0])

    @property
    def n_tets(self) -> int:
        return int(self.tets.shape[0])

    @property
    def n_dofs(self) -> int:
        """Three translations per node (DOF index ``3*node + component``)."""
        return 3 * self.n_nodes

    @property
    def order(self) -> int:
        """1 for Tet4, 2 for Tet10."""
        return 1 if self.tets.shape[1] == 4 else 2

    @property
    def corner_tets(self) -> np.ndarray:
        """(m, 4) int: the corner nodes of every element."""
        return self.tets[:, :4]

    @property
    def corner_nodes(self) -> np.ndarray:
        """(k,) int: sorted indices of nodes that are an element corner."""
        return np.unique(self.corner_tets)

    # ------------------------------------------------------------- geometry
    def volumes(self) -> np.ndarray:
        """(m,) float: signed volume of each element's corner tetrahedron [m^3]."""
        p = self.points[self.corner_tets]
        d = p[:, 1:] - p[:, :1]
        return np.einsum("ij,ij->i", d[:, 0], np.cross(d[:, 1], d[:, 2])) / 6.0

    def bounds(self) -> np.ndarray:
        """(2, 3) float: min and max corner of the bounding box [m]."""
        return np.stack([self.points.min(axis=0), self.points.max(axis=0)])

    def boundary_faces(self, outer: bool = False) -> np.ndarray:
        """(k, 3) int: corner triangles on the boundary, oriented outward.

        A face is on the boundary when exactly one element owns it.  ``outer``: only the
        outer skins, not the walls of inner cavities (:func:`~.topology.outer_faces`).
        """
        faces = self.corner_tets[:, TET_FACES].reshape(-1, 3)
        faces = faces[single_rows(faces, self.n_nodes)]
        return faces[outer_faces(self.points, faces)] if outer else faces

    def boundary_nodes(self, outer: bool = False) -> np.ndarray:
        """(k,) int: every node on the boundary surface (mid-edge nodes included for Tet10);
        ``outer``: on the outer skins only (no node of a hollow link's cavity wall)."""
        faces = self.boundary_faces(outer)
        nodes = set(np.unique(faces).tolist())
        if self.order == 2:
            edges = np.sort(self.corner_tets[:, TET10_EDGES].reshape(-1, 2), axis=1)
            mids = self.tets[:, 4:].reshape(-1)
            bedges = np.sort(
                np.concatenate([faces[:, [0, 1]], faces[:, [1, 2]], faces[:, [2, 0]]]), axis=1
            )
            n = self.n_nodes
            is_b = np.isin(edges[:, 0] * n + edges[:, 1], bedges[:, 0] * n + bedges[:, 1])
            nodes.update(np.unique(mids[is_b]).tolist())
        return np.array(sorted(nodes), dtype=np.int64)

    # ------------------------------------------------------- new instances
    def scaled(self, factor: float) -> TetMesh:
        """Copy with coordinates multiplied by ``factor`` (e.g. 1e-3 for mm -> m)."""
        return replace(self, points=self.points * float(factor))

    def translated(self, offset) -> TetMesh:
        """Copy moved by ``offset`` (3,) [m]."""
        return replace(self, points=self.points + np.asarray(offset, dtype=np.float64))

    def with_node_sets(self, node_sets: Mapping[str, np.ndarray]) -> TetMesh:
        """Copy with extra (or replaced) named node sets."""
        merged = dict(self.node_sets)
        merged.update(node_sets)
        return replace(self, node_sets=merged)

    def check(self, name: str = "mesh", volumes: np.ndarray | None = None) -> TetMesh:
        """Raise :class:`MeshError` if empty, degenerate or inverted; return self.

        ``volumes`` are :meth:`volumes` when the caller has already computed them.
        """
        if self.n_tets == 0:
            raise MeshError(f"{name}: the mesh has no tetrahedra")
        vol = self.volumes() if volumes is None else volumes
        scale = np.abs(vol).mean()
        if not np.isfinite(self.points).all():
            raise MeshError(f"{name}: node coordinates contain NaN or inf")
        n_bad = int((vol < -tol.degenerate_volume * scale).sum())
        if n_bad:
            first = int(np.flatnonzero(vol < -tol.degenerate_volume * scale)[0])
            raise MeshError(f"{name}: {n_bad} inverted tetrahedra (first: element {first})")
        n_flat = int((np.abs(vol) <= tol.degenerate_volume * scale).sum())
        if n_flat:
            first = int(np.flatnonzero(np.abs(vol) <= tol.degenerate_volume * scale)[0])
            raise MeshError(f"{name}: {n_flat} zero-volume tetrahedra (first: element {first})")
        return self

    # ------------------------------------------------------------ examples
    @classmethod
    def unit_tet(cls) -> TetMesh:
        """The reference tetrahedron (0,0,0), (1,0,0), (0,1,0), (0,0,1) [m]."""
        pts = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]], dtype=float)
        return cls(pts, np.array([[0, 1, 2, 3]]))

    @classmethod
    def box(cls, size=(1.0, 1.0, 1.0), divisions=(2, 2, 2), order: int = 1, origin=(0, 0, 0)):
        """A structured box split into 6 tetrahedra per hexahedron (Kuhn split).

        Parameters
        ----------
        size : (3,) float
            Edge lengths [m].
        divisions : (3,) int
            Hexahedra along x, y, z.
        order : {1, 2}
            Tet4 or Tet10 (straight mid-edge nodes).
        origin : (3,) float
            Minimum corner [m].

        Examples
        --------
        >>> m = TetMesh.box((1.0, 0.1, 0.1), (10, 1, 1), order=2)
        >>> m.n_tets, m.order
        (60, 2)
        >>> round(float(m.volumes().sum()), 12)
        0.01
        """

        points, tets = box_tets(size, divisions, origin)
        mesh = cls(points, tets)
        return mesh.to_tet10() if order == 2 else mesh

    def to_tet10(self) -> TetMesh:
        """Copy promoted to Tet10 with straight mid-edge nodes (no-op for Tet10)."""
        if self.order == 2:
            return self

        points, tets = promote_tet10(self.points, self.tets)
        return TetMesh(points, tets, dict(self.node_sets))

    def to_tet4(self) -> TetMesh:
        """Copy keeping only the corner nodes (renumbered); node sets keep corner nodes."""
        if self.order == 1:
            return self
        corners = self.corner_nodes
        new_id = np.full(self.n_nodes, -1, dtype=np.int64)
        new_id[corners] = np.arange(len(corners))
        sets = {k: new_id[v[np.isin(v, corners)]] for k, v in self.node_sets.items()}
        return TetMesh(self.points[corners], new_id[self.corner_tets], sets)
