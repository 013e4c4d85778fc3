"""The one wall that gives a mass, and what hollowing does to bending (a crude proxy).

:func:`wall_for_mass` hollows every part of an arm to the same wall thickness, chosen so
that the parts plus the lumped masses weigh the datasheet mass; :func:`bending_ratio`
compares the second moments of volume of a hollowed part and its solid.

Imports only :mod:`flexarm.fe` and :mod:`flexarm.meshes`.
"""

from __future__ import annotations

import logging
from collections.abc import Sequence

import numpy as np
import trimesh
from scipy.optimize import brentq

from .inward_offset import BALL_SEGMENTS, _Solid
from .tolerances import tol

__all__ = ["bending_ratio", "wall_for_mass"]

logger = logging.getLogger(__name__)


def wall_for_mass(surfaces: Sequence[trimesh.Trimesh], densities, target_mass: float,
                  lumped_mass=0.0, *, ball_segments: int = BALL_SEGMENTS,
                  xtol: float = 1e-9, names: Sequence[str] | None = None) -> float:
    """The one wall thickness at which the hollowed parts and the lumped masses weigh
    ``target_mass``.

    Every part gets the same wall; a part whose inscribed ball is thinner than the wall
    stays solid (as in :func:`~flexarm.meshes.hollow.hollow_surface`).

    Parameters
    ----------
    surfaces : sequence of trimesh.Trimesh
        Closed link surfaces [m].
    densities : float or sequence of float
        Density of each part [kg/m^3] (one value for all, or one per surface).
    target_mass : float
        Total mass to match, e.g. the datasheet mass of the arm [kg].
    lumped_mass : float or sequence of float
        Masses not modelled by the surfaces (motors, gearboxes, cables) [kg]; summed.
    ball_segments : int
        See :func:`~flexarm.meshes.hollow.hollow_surface` (non-convex parts only).
    xtol : float
        Absolute tolerance of the returned thickness [m].
    names : sequence of str, optional
        What to call each part in messages (default ``surface 0``, ``surface 1``, ...).

    Returns
    -------
    float
        Wall thickness [m].  If the target is exactly the solid mass, the smallest wall
        that leaves every part solid.

    Raises
    ------
    ValueError
        No surfaces, a non-positive density, the target at or below the lumped masses
        (no wall would be left), or above the solid parts plus the lumped masses (even
        solid hulls are too light: scale the density instead).

    Examples
    --------
    Two boxes hollowed at 12 mm, plus 5 kg of motors, weigh ``target``; recover 12 mm:

    >>> import trimesh
    >>> boxes = [trimesh.creation.box((0.4, 0.2, 0.1)), trimesh.creation.box((0.2, 0.2, 0.2))]
    >>> walls = [0.4 * 0.2 * 0.1 - 0.376 * 0.176 * 0.076, 0.2**3 - 0.176**3]  # [m^3]
    >>> target = 7200.0 * walls[0] + 2700.0 * walls[1] + 5.0
    >>> round(target, 3)
    33.269
    >>> t = wall_for_mass(boxes, [7200.0, 2700.0], target, lumped_mass=5.0)
    >>> round(t * 1e3, 6)  # [mm]
    12.0
    """
    names = [f"surface {i}" for i in range(len(surfaces))] if names is None else names
    solids = [_Solid(s, n) for s, n in zip(surfaces, names, strict=True)]
    if not solids:
        raise ValueError("wall_for_mass needs at least one surface")
    rho = _densities(densities, len(solids))
    lumped = float(np.sum(lumped_mass))
    target = float(target_mass)
    solid_mass = float(rho @ [s.volume for s in solids])
    _check_target(target, lumped, solid_mass)
    return _solve_wall(solids, rho, lumped, target, solid_mass, ball_segments, xtol)


def _densities(densities, n: int) -> np.ndarray:
    """Density of each of ``n`` parts [kg/m^3] from one value or ``n``; all positive."""
    try:
        rho = np.broadcast_to(np.asarray(densities, dtype=np.float64), (n,))
    except ValueError:
        raise ValueError(f"need one density or {n}, got {densities}") from None
    if not (np.isfinite(rho).all() and (rho > 0).all()):
        raise ValueError(f"densities must be positive [kg/m^3], got {rho.tolist()}")
    return rho


def _check_target(target: float, lumped: float, solid_mass: float) -> None:
    """Raise ValueError unless some wall gives ``target`` [kg]: it must lie above the
    lumped masses and not above the solid parts plus the lumped masses."""
    if target <= lumped:
        raise ValueError(
            f"target mass {target:g} kg is not above the lumped masses ({lumped:g} kg): "
            "no wall thickness can give it"
        )
    if target > (lumped + solid_mass) * (1 + tol.hollow_mass_match):
        raise ValueError(
            f"target mass {target:g} kg is above the solid parts plus lumped masses "
            f"({solid_mass:g} + {lumped:g} kg): even solid hulls are too light; "
            "scale the density instead"
        )


def _solve_wall(solids, rho, lumped, target, solid_mass, segments, xtol) -> float:
    """Wall [m] at which the shells of ``solids`` (densities ``rho``) weigh ``target`` [kg].

    The total mass grows continuously and monotonically with the wall, from the lumped
    masses (no wall) to the solid parts plus the lumped masses.  Convex parts cost
    milliseconds per wall, so Brent's bracketing method finds the crossing on their exact
    shell volumes.  An eroded part costs seconds per wall: it enters as its cavity volume
    at the last wall evaluated, shrinking at the rate of its cavity's area (the exact
    derivative), which makes the outer loop Newton's method; it stops when the next step
    is below ``xtol`` or :attr:`~flexarm.meshes.tolerances.Tolerances.hollow_wall_step`
    of the wall, at the last wall evaluated (so hollowing at it reuses the erosion).
    """
    t_max = max(s.inradius for s in solids)
    if target >= (lumped + solid_mass) * (1 - tol.hollow_mass_match):
        return t_max
    costly = [i for i, s in enumerate(solids) if not s.is_convex]
    # (wall, cavity volume, cavity area) of each eroded part: at no wall, the part itself
    model = {i: (0.0, solids[i].volume, float(solids[i].surface.area)) for i in costly}

    def cavity(i: int, t: float) -> float:
        s = solids[i]
        if t <= 0:
            return s.volume  # no wall: all cavity
        if i not in model:
            return s.cavity_volume(t, segments)
        if s._solid_at(t):
            return 0.0
        t_k, v_k, a_k = model[i]
        return max(v_k - a_k * (t - t_k), 0.0)

    def excess(t: float) -> float:
        shells = [s.volume - cavity(i, t) for i, s in enumerate(solids)]
        return lumped + float(rho @ shells) - target

    thickness = brentq(excess, 0.0, t_max, xtol=xtol)
    for step in range(tol.hollow_wall_iterations):
        if not costly:
            break
        for i in costly:
            model[i] = (thickness, solids[i].cavity_volume(thickness, segments),
                        solids[i].eroded_area(thickness, segments))
        following = brentq(excess, 0.0, t_max, xtol=xtol)
        logger.info("wall search, step %d: %.6g m, next %.6g m", step + 1, thickness,
                    following)
        if abs(following - thickness) <= max(xtol, tol.hollow_wall_step * thickness):
            break
        thickness = following
    logger.info("wall %.4g m gives %.6g kg", thickness, target)
    return float(thickness)


def _spread(mesh: trimesh.Trimesh) -> np.ndarray:
    """Second moments of volume (3, 3) [m^5], int (x - c)(x - c)^T dV about the centroid c."""
    inertia = trimesh.triangles.mass_properties(mesh.triangles, density=1.0).inertia
    # inertia = tr(C) I - C  =>  tr(inertia) = 2 tr(C)
    return 0.5 * np.trace(inertia) * np.eye(3) - inertia



def bending_ratio(solid: trimesh.Trimesh, shell) -> np.ndarray:
    """Crude bending-stiffness proxy: shell over solid second moments of volume.

    For each principal axis e_k of the solid (largest spread first) the ratio

        r_k = int_shell (e_k . (x - c_shell))^2 dV  /  int_solid (e_k . (x - c_solid))^2 dV,

    i.e. the diagonal of the covariance ("second moment of volume") of each body about
    its own centroid, in the solid's principal frame.  It is *not* the inertia tensor (whose
    diagonal mixes two directions) and not a mass-normalised quantity.

    What it is: for a prismatic member along e_0 with a uniform wall, ``r_1`` and ``r_2``
    are the ratios of the second moments of area of the cross-section, i.e. of the
    bending stiffness EI for deflection along e_1 and e_2 with the same E, up to the end
    walls' O(t / length) share.  ``r_0`` measures spread along the member, not bending.
    What it is not: a finite-element stiffness.  It ignores shear (which matters for
    short, thin-walled links), torsion (the closed thin-walled section's Bredt constant
    differs), local wall bending and ovalisation, hubs, ribs and end conditions; for a
    blocky part (base, wrist) even the beam picture is weak.  The mass changes by
    ``shell.volume / solid.volume``, for thin walls smaller than ``r_1`` and ``r_2``:
    hollowing lowers the stiffness less than the mass.

    Parameters
    ----------
    solid : trimesh.Trimesh
        The closed solid surface [m].
    shell : ~flexarm.meshes.hollow.HollowShell or trimesh.Trimesh
        The hollowed part (its ``mesh``) or any closed surface [m].

    Returns
    -------
    numpy.ndarray
        (3,) ratios, dimensionless, in the order of the solid's principal axes by
        decreasing spread (1 for a solid ``shell``).

    Examples
    --------
    A bar 1 m long and 0.1 m square hollowed to 5 mm walls: a tube whose section keeps
    1 - 0.9^4 of its second moment of area, plus 2 t / length of the inner section's in
    the end walls, 1 - 0.99 * 0.9^4:

    >>> import trimesh
    >>> from flexarm.meshes import hollow_surface
    >>> bar = trimesh.creation.box((1.0, 0.1, 0.1))
    >>> r = bending_ratio(bar, hollow_surface(bar, 0.005))
    >>> [round(float(x), 4) for x in r], round(1 - 0.99 * 0.9**4, 4)
    ([0.2141, 0.3505, 0.3505], 0.3505)
    """
    mesh = shell if isinstance(shell, trimesh.Trimesh) else shell.mesh  # a HollowShell
    c_solid = _spread(solid)
    spread, axes = np.linalg.eigh(c_solid)
    order = np.argsort(spread)[::-1]
    spread, axes = spread[order], axes[:, order]
    return np.einsum("ik,ij,jk->k", axes, _spread(mesh), axes) / spread
