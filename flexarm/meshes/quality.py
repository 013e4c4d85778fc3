"""Element quality of a tetrahedral mesh (vectorised over all elements).

Quality is measured on the corner tetrahedron of each element (exact for the
straight-sided Tet10 that :meth:`TetMesh.to_tet10` makes).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..fe.mesh import TetMesh
from .tolerances import tol

__all__ = ["QualityReport", "mesh_quality", "dihedral_angles", "radius_ratios",
           "triangle_min_angles"]

# Face k is the face opposite corner k, wound so its normal points out of a
# positively oriented tetrahedron.
_OPPOSITE_FACES = np.array([[1, 2, 3], [0, 3, 2], [0, 1, 3], [0, 2, 1]], dtype=np.int64)
# The six edges, as the pair of faces that meet there (edge (i, j) joins the
# faces opposite the two other corners).
_FACE_PAIRS = np.array([[2, 3], [0, 3], [1, 3], [1, 2], [0, 2], [0, 1]], dtype=np.int64)


def _corners(points: np.ndarray, tets: np.ndarray) -> np.ndarray:
    return np.asarray(points, dtype=np.float64)[np.asarray(tets)[:, :4]]


def dihedral_angles(points: np.ndarray, tets: np.ndarray) -> np.ndarray:
    """Interior dihedral angles at the six edges of every tetrahedron.

    Parameters
    ----------
    points : (n, 3) float
        Node coordinates [m].
    tets : (m, 4) or (m, 10) int
        Elements (only the corners are used).

    Returns
    -------
    (m, 6) float
        Angles [deg] at edges (0,1), (1,2), (0,2), (0,3), (1,3), (2,3); 0 where a
        face has no area.

    Examples
    --------
    >>> m = TetMesh.unit_tet()
    >>> dihedral_angles(m.points, m.tets).round(4).tolist()
    [[90.0, 54.7356, 90.0, 90.0, 54.7356, 54.7356]]
    """
    p = _corners(points, tets)
    f = p[:, _OPPOSITE_FACES]  # (m, 4, 3 corners, 3)
    normals = np.cross(f[:, :, 1] - f[:, :, 0], f[:, :, 2] - f[:, :, 0])
    length = np.linalg.norm(normals, axis=2, keepdims=True)
    with np.errstate(invalid="ignore", divide="ignore"):
        unit = np.where(length > 0, normals / length, 0.0)
    a = unit[:, _FACE_PAIRS[:, 0]]
    b = unit[:, _FACE_PAIRS[:, 1]]
    cos = -np.einsum("mek,mek->me", a, b)
    angles = np.degrees(np.arccos(np.clip(cos, -1.0, 1.0)))
    flat = (length[:, _FACE_PAIRS[:, 0], 0] == 0) | (length[:, _FACE_PAIRS[:, 1], 0] == 0)
    return np.where(flat, 0.0, angles)


def triangle_min_angles(points: np.ndarray, triangles: np.ndarray) -> np.ndarray:
    """Smallest interior angle [deg] of every triangle (0 where a side has no length).

    A tetrahedron built on a surface triangle whose smallest angle is small has a small
    dihedral angle too: as the triangle's corners fall on one line (or two of them on one
    point), two of the tetrahedron's faces through the fourth corner fall on one plane.

    Examples
    --------
    >>> p = np.array([[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.5, 0.01, 0.0]])
    >>> triangle_min_angles(p, np.array([[0, 1, 2], [0, 1, 3]])).round(3).tolist()
    [45.0, 1.146]
    """
    c = np.asarray(points, dtype=np.float64)[np.asarray(triangles)]  # (k, 3 corners, 3)
    sides = np.roll(c, -1, axis=1) - c  # side i runs from corner i to corner i + 1
    length = np.linalg.norm(sides, axis=2)
    # the angle at corner i lies between side i and the reversed side i - 1
    cos = -np.einsum("kij,kij->ki", sides, np.roll(sides, 1, axis=1))
    with np.errstate(invalid="ignore", divide="ignore"):
        cos = cos / (length * np.roll(length, 1, axis=1))
    angles = np.degrees(np.arccos(np.clip(np.nan_to_num(cos, nan=1.0), -1.0, 1.0)))
    return np.where((length > 0).all(axis=1), angles.min(axis=1), 0.0)


def radius_ratios(points: np.ndarray, tets: np.ndarray) -> np.ndarray:
    """Normalised radius ratio ``3 r_in / r_circ`` of every tetrahedron.

    1 for a regular tetrahedron, 0 for a flat one, negative for an inverted one.

    Parameters
    ----------
    points : (n, 3) float
        Node coordinates [m].
    tets : (m, 4) or (m, 10) int
        Elements (only the corners are used).

    Returns
    -------
    (m,) float

    Examples
    --------
    >>> regular = np.array([[1, 1, 1], [1, -1, -1], [-1, 1, -1], [-1, -1, 1]], float)
    >>> radius_ratios(regular, np.array([[0, 2, 1, 3]])).round(12).tolist()
    [1.0]
    >>> m = TetMesh.unit_tet()
    >>> radius_ratios(m.points, m.tets).round(6).tolist()  # sqrt(3) - 1
    [0.732051]
    """
    p = _corners(points, tets)
    a, b, c = (p[:, k] - p[:, 0] for k in (1, 2, 3))
    triple = np.einsum("ij,ij->i", a, np.cross(b, c))  # 6 V
    f = p[:, _OPPOSITE_FACES]
    area = 0.5 * np.linalg.norm(
        np.cross(f[:, :, 1] - f[:, :, 0], f[:, :, 2] - f[:, :, 0]), axis=2
    ).sum(axis=1)
    # Circumcentre relative to corner 0, times 2 * 6V (kept finite for flat tets).
    centre = (
        np.einsum("i,ij->ij", np.einsum("ij,ij->i", a, a), np.cross(b, c))
        + np.einsum("i,ij->ij", np.einsum("ij,ij->i", b, b), np.cross(c, a))
        + np.einsum("i,ij->ij", np.einsum("ij,ij->i", c, c), np.cross(a, b))
    )
    # r_in = 3V / area = triple / (2 area);  r_circ = |centre| / (2 |triple|)
    # => 3 r_in / r_circ = 3 triple |triple| / (area |centre|)
    denominator = area * np.linalg.norm(centre, axis=1)
    ok = denominator > 0
    ratio = np.zeros(len(p))
    ratio[ok] = 3.0 * triple[ok] * np.abs(triple[ok]) / denominator[ok]
    return ratio


@dataclass(frozen=True)
class QualityReport:
    """Size and element quality of a tetrahedral mesh.

    Attributes
    ----------
    n_nodes, n_tets, order : int
        Mesh size; ``order`` 1 (Tet4) or 2 (Tet10).
    min_dihedral_deg, mean_dihedral_deg : float
        Smallest dihedral angle of the mesh, and the mean over elements of each
        element's smallest one [deg] (a regular tetrahedron has 70.53).
    min_radius_ratio, mean_radius_ratio : float
        Normalised radius ratio ``3 r_in / r_circ`` (regular = 1).
    volume : float
        Sum of element volumes [m^3].
    volume_error : float or None
        ``(volume - V_surface) / V_surface`` against the source surface, if given.
    n_slivers : int
        Elements with a dihedral angle below ``tol.sliver_dihedral_deg``.
    """

    n_nodes: int
    n_tets: int
    order: int
    min_dihedral_deg: float
    mean_dihedral_deg: float
    min_radius_ratio: float
    mean_radius_ratio: float
    volume: float
    volume_error: float | None
    n_slivers: int

    def table(self) -> str:
        """Human-readable multi-line summary."""
        kind = "Tet4" if self.order == 1 else "Tet10"
        vol = f"{self.volume:.6g} m^3"
        if self.volume_error is not None:
            vol += f" ({self.volume_error:+.2e} vs surface)"
        rows = [
            ("nodes", f"{self.n_nodes}"),
            ("elements", f"{self.n_tets} {kind}"),
            (
                "dihedral min / mean",
                f"{self.min_dihedral_deg:.2f} / {self.mean_dihedral_deg:.2f} deg",
            ),
            (
                "radius ratio min / mean",
                f"{self.min_radius_ratio:.3f} / {self.mean_radius_ratio:.3f}",
            ),
            ("volume", vol),
            (f"slivers (< {tol.sliver_dihedral_deg:g} deg)", f"{self.n_slivers}"),
        ]
        width = max(len(k) for k, _ in rows)
        return "\n".join(f"{k:<{width}}  {v}" for k, v in rows)


def mesh_quality(mesh: TetMesh, surface=None) -> QualityReport:
    """Quality report of a tetrahedral mesh, optionally against its source surface.

    Parameters
    ----------
    mesh : TetMesh
        Tet4 or Tet10 mesh [m].
    surface : trimesh.Trimesh, optional
        Closed surface the mesh was made from; gives ``volume_error``.

    Returns
    -------
    QualityReport

    Examples
    --------
    >>> report = mesh_quality(TetMesh.box((1.0, 1.0, 1.0), (2, 2, 2)))
    >>> report.n_tets, round(report.min_dihedral_deg, 2), report.n_slivers
    (48, 45.0, 0)
    >>> print(report.table().splitlines()[1])
    elements                 48 Tet4
    """
    if mesh.n_tets == 0:
        raise ValueError("mesh_quality needs at least one element, got (0, 4) tets")
    min_angles = dihedral_angles(mesh.points, mesh.tets).min(axis=1)
    ratios = radius_ratios(mesh.points, mesh.tets)
    volume = float(mesh.volumes().sum())
    error = None
    if surface is not None:
        reference = float(surface.volume)
        error = (volume - reference) / reference
    return QualityReport(
        n_nodes=mesh.n_nodes,
        n_tets=mesh.n_tets,
        order=mesh.order,
        min_dihedral_deg=float(min_angles.min()),
        mean_dihedral_deg=float(min_angles.mean()),
        min_radius_ratio=float(ratios.min()),
        mean_radius_ratio=float(ratios.mean()),
        volume=volume,
        volume_error=error,
        n_slivers=int((min_angles < tol.sliver_dihedral_deg).sum()),
    )
