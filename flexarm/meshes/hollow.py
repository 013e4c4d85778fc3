"""Hollow a solid CAD hull into a cast shell of uniform wall thickness.

Robot description files (URDF) ship link meshes that are solid hulls -- often exactly
the convex hull -- of what really are hollow castings.  Scaling the density until the
total mass matches the datasheet keeps the hull's full section, so the link stays far
too stiff in bending; cutting the inside away down to a wall of thickness ``t`` gives the
datasheet mass *and* a plausible section.

The shell is the CAD surface plus the reversed surface of a cavity strictly inside it;
:mod:`flexarm.meshes.inward_offset` builds the cavity (an exact offset of the hull's
planes for convex surfaces, a manifold3d erosion for any other).  The wall for a given
mass and the bending-stiffness proxy live in :mod:`flexarm.meshes.wall` and are
re-exported here.

Imports only :mod:`flexarm.fe` and :mod:`flexarm.meshes`.
"""

from __future__ import annotations

import logging
from dataclasses import dataclass

import numpy as np
import trimesh

from ..fe.errors import MeshError
from .inward_offset import BALL_SEGMENTS, _Solid
from .wall import bending_ratio, wall_for_mass

__all__ = [
    "BALL_SEGMENTS",
    "HollowShell",
    "bending_ratio",
    "hollow_surface",
    "wall_for_mass",
]

logger = logging.getLogger(__name__)


@dataclass(frozen=True, eq=False)
class HollowShell:
    """A CAD solid hollowed to a uniform wall (what :func:`hollow_surface` returns).

    Attributes
    ----------
    mesh : trimesh.Trimesh
        Closed surface of the wall material [m]: the input surface's vertices and faces
        first, unchanged, then the reversed cavity surface.  Watertight, consistently
        wound, positive volume.  If ``is_solid``, the input surface itself.
    thickness : float
        The requested wall thickness [m].
    is_solid : bool
        Nothing is left inside at this thickness (it reaches the largest inscribed
        ball): the part stays solid and ``mesh`` is the input surface.
    cavity : trimesh.Trimesh or None
        Outward-wound surface of the removed inside [m] (several bodies if the inside
        splits up); None if ``is_solid``.
    method : {"convex", "erosion", "level set", "solid"}
        How the cavity was built (see :mod:`flexarm.meshes.inward_offset`).
    solid : trimesh.Trimesh or None
        The closed surface that was hollowed [m]: the input, or the surface of the
        union of its bodies where they overlap or touch.
    """

    mesh: trimesh.Trimesh
    thickness: float
    is_solid: bool
    cavity: trimesh.Trimesh | None
    method: str
    solid: trimesh.Trimesh | None = None

    @property
    def volume(self) -> float:
        """Volume of the wall material [m^3]."""
        return float(self.mesh.volume)


def _shell_mesh(outer: trimesh.Trimesh, cavity: trimesh.Trimesh) -> trimesh.Trimesh:
    """Outer surface as it is, then the cavity with every face reversed (inward normals)."""
    vertices = np.vstack([outer.vertices, cavity.vertices])
    faces = np.vstack([outer.faces, cavity.faces[:, ::-1] + len(outer.vertices)])
    return trimesh.Trimesh(vertices, faces, process=False)


def _check_thickness(thickness: float) -> float:
    """The wall thickness as a float [m]; ValueError unless finite and positive."""
    thickness = float(thickness)
    if not np.isfinite(thickness) or thickness <= 0:
        raise ValueError(f"wall thickness must be a positive length [m], got {thickness}")
    return thickness


def _shell(solid: _Solid, thickness: float, segments: int) -> HollowShell:
    """``solid`` hollowed to walls ``thickness`` [m] thick (kept solid if nothing is left)."""
    thickness = _check_thickness(thickness)
    cavity, method = solid.cavity(thickness, segments)
    if cavity is None:
        logger.info("%s: wall %.4g m leaves nothing inside (inscribed radius <= %.4g m): "
                    "kept solid", solid.name, thickness, solid.inradius)
        return HollowShell(solid.surface, thickness, True, None, "solid", solid.surface)
    mesh = _shell_mesh(solid.surface, cavity)
    if not (mesh.is_watertight and mesh.is_winding_consistent and mesh.volume > 0):
        raise MeshError(f"{solid.name}: the hollowed ({method}) surface is not a closed "
                        "shell; mesh it solid or scale the density instead")
    logger.debug("%s: wall %.4g m (%s): %.4g of %.4g m^3 left", solid.name, thickness,
                 method, mesh.volume, solid.volume)
    return HollowShell(mesh, thickness, False, cavity, method, solid.surface)


def hollow_surface(
    surface: trimesh.Trimesh,
    thickness: float,
    *,
    ball_segments: int = BALL_SEGMENTS,
    name: str = "surface",
) -> HollowShell:
    """Hollow a closed CAD surface to a shell with walls ``thickness`` thick.

    The cavity is the set of points at least ``thickness`` inside the surface: exact, by
    offsetting the hull's planes, for convex surfaces (up to CAD faceting noise); by a
    manifold3d erosion for any other closed surface (see
    :mod:`flexarm.meshes.inward_offset`).  A
    thickness at or beyond the radius of the largest inscribed ball leaves nothing inside:
    the part is kept solid and the result says so (``is_solid``) instead of raising, so
    that a small link of an arm hollowed at one wall simply stays solid.

    Parameters
    ----------
    surface : trimesh.Trimesh
        Closed, consistently wound surface enclosing a positive volume [m] (e.g. from
        :func:`~flexarm.meshes.load_surface`).  It is not modified.
    thickness : float
        Wall thickness [m], > 0.
    ball_segments : int
        Resolution of the ball swept along concave edges (erosion only).
    name : str
        What to call the part in messages.

    Returns
    -------
    HollowShell
        ``mesh`` (outer surface = the input's vertices and faces, then the reversed
        cavity), ``thickness``, ``is_solid``, ``cavity``, ``method``, ``volume``.

    Raises
    ------
    ValueError
        ``thickness`` is not a positive number.
    MeshError
        The surface is open, non-manifold, inconsistently wound or of no volume, or the
        erosion fails.

    Examples
    --------
    >>> import trimesh
    >>> shell = hollow_surface(trimesh.creation.box((0.4, 0.2, 0.1)), 0.01)
    >>> shell.method, bool(shell.mesh.is_watertight), shell.mesh.body_count
    ('convex', True, 2)
    >>> round(shell.volume * 1e6, 6), round((0.4*0.2*0.1 - 0.38*0.18*0.08) * 1e6, 6)
    (2528.0, 2528.0)
    >>> hollow_surface(trimesh.creation.box((0.4, 0.2, 0.1)), 0.05).is_solid
    True
    """
    return _shell(_Solid(surface, name), thickness, ball_segments)
