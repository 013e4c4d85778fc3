"""One solid from several closed surfaces (manifold3d's boolean union).

CAD that arrives in pieces (a URDF link with several geometry elements, a fixed child
merged into its parent) is one part: overlapping pieces must count once in the volume,
and touching ones must share their contact face, or the surface is not a manifold that
a tetrahedraliser can fill.
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np
import trimesh

from ..fe.errors import MeshError
from .tolerances import tol

__all__ = ["union"]


def union(meshes: Sequence[trimesh.Trimesh], name: str = "parts") -> trimesh.Trimesh:
    """The closed surface [m] of the union of closed ``meshes``.

    Pieces that are not closed volumes cannot be united: they are put side by side
    (a surface the caller must check before meshing it).

    Examples
    --------
    >>> a = trimesh.creation.box((1.0, 1.0, 1.0))
    >>> b = trimesh.creation.box((1.0, 1.0, 1.0), trimesh.transformations.translation_matrix(
    ...     [0.5, 0.0, 0.0]))
    >>> u = union([a, b])
    >>> u.is_watertight, round(float(u.volume), 9)  # 1.5 m^3, not 2
    (True, 1.5)
    """
    if len(meshes) == 1:
        return meshes[0]
    meshes = [m.copy() for m in meshes]
    for m in meshes:  # an STL stores every triangle's corners apart
        m.merge_vertices()
    if not all(m.is_volume for m in meshes):
        return trimesh.util.concatenate(list(meshes))
    from manifold3d import Manifold, Mesh64

    solid = None
    for m in meshes:
        piece = Manifold(Mesh64(vert_properties=np.ascontiguousarray(m.vertices, dtype=np.float64),
                                tri_verts=np.ascontiguousarray(m.faces, dtype=np.uint64)))
        if piece.status().name != "NoError":
            raise MeshError(f"{name}: manifold3d rejects a piece ({piece.status()})")
        solid = piece if solid is None else solid + piece
    size = float(max(np.ptp(m.vertices, axis=0).max() for m in meshes))
    # pieces that touch tangentially (a cylinder grazing another's end face) leave
    # sub-nanometre edges, which a later vertex merge would tear open: collapse them here
    out = solid.simplify(tol.union_merge * size).to_mesh64()
    united = trimesh.Trimesh(np.array(out.vert_properties, dtype=np.float64)[:, :3],
                             np.array(out.tri_verts, dtype=np.int64), process=False)
    return _without_slivers(united, tol.union_merge * float(np.ptp(united.vertices, axis=0).max()))


def _without_slivers(mesh: trimesh.Trimesh, merge: float) -> trimesh.Trimesh:
    """``mesh`` with vertices within about ``merge`` [m] of each other merged and the faces
    that collapse dropped, if the result is still closed.  Pieces read from float32 files
    touch a few nanometres apart, and their union keeps those nanometre slivers: a file
    reader's repair would drop them and open the surface."""
    digits = int(np.floor(-np.log10(merge)))
    clean = mesh.copy()
    clean.merge_vertices(digits_vertex=digits)
    clean.update_faces(clean.nondegenerate_faces(height=merge))
    clean.remove_unreferenced_vertices()
    return clean if clean.is_volume else mesh
