"""What a link must be before its CAD and masses become mass properties.

Every mass path (the E-model's surface integrals, the tetrahedra of a flexible link)
reads the link's CAD through :func:`link_surface`, the reader ``flexarm mesh`` uses
(:func:`~flexarm.meshes.surface.load_surface`: repaired, then refused unless closed,
manifold, consistently wound and enclosing a positive volume), and checks the result
with :func:`check_link_mass`.  Every error names the link (``links.<name>``) and, for
the CAD, the file.  Bounds: :class:`~flexarm.robot.tolerances.Tolerances`.
"""

from __future__ import annotations

import contextlib
from collections.abc import Iterator

from .tolerances import tol

__all__ = ["link_surface", "naming_link", "check_link_density", "check_link_mass"]


@contextlib.contextmanager
def naming_link(link) -> Iterator[None]:
    """Prefix a :class:`~flexarm.fe.errors.MeshError` or
    :class:`~flexarm.fe.errors.ReadError` about the link's CAD with ``links.<name>.mesh``.

    Examples
    --------
    >>> from types import SimpleNamespace
    >>> from flexarm.fe.errors import MeshError
    >>> with naming_link(SimpleNamespace(name="arm")):
    ...     raise MeshError("arm.stl: the surface is open (4 boundary edges)")
    Traceback (most recent call last):
    ...
    flexarm.fe.errors.MeshError: links.arm.mesh: arm.stl: the surface is open (4 boundary edges)
    """
    from ..fe.errors import MeshError, ReadError

    try:
        yield
    except (MeshError, ReadError) as exc:
        if str(exc).startswith("links."):
            raise
        raise type(exc)(f"links.{link.name}.mesh: {exc}") from None


def link_surface(link):
    """The link's CAD surface [m, link frame] as ``flexarm mesh`` reads it.

    Returns
    -------
    trimesh.Trimesh
        Closed, manifold, outward-wound surface enclosing a positive volume.

    Raises
    ------
    MeshError, ReadError
        Naming ``links.<name>.mesh`` and the file.

    Examples
    --------
    >>> from flexarm.robot import load_robot
    >>> surface = link_surface(load_robot().links[-1])
    >>> round(float(surface.volume), 9)  # the turning disc [m^3]
    0.000470006
    """
    from ..meshes import load_surface

    with naming_link(link):
        return load_surface(link.mesh, units=link.units)


def check_link_density(link) -> None:
    """Raise ``ValueError`` naming ``links.<name>.material.rho`` when a link with CAD has
    a density outside ``[tol.density_min, tol.density_max]`` [kg/m^3].

    Examples
    --------
    >>> from dataclasses import replace
    >>> from flexarm.robot import load_robot
    >>> disc = load_robot().links[-1]
    >>> check_link_density(disc)  # steel: fine
    >>> check_link_density(replace(disc, material=replace(disc.material, rho=0.0)))
    Traceback (most recent call last):
    ...
    ValueError: links.turning_disc.material.rho: 0 kg/m^3 is not a plausible density for \
a link's CAD solid (100 to 25000 kg/m^3)
    """
    rho = float(link.material.rho)
    if link.mesh is not None and not tol.density_min <= rho <= tol.density_max:
        raise ValueError(f"links.{link.name}.material.rho: {rho:g} kg/m^3 is not a plausible "
                         f"density for a link's CAD solid ({tol.density_min:g} to "
                         f"{tol.density_max:g} kg/m^3)")


def check_link_mass(link, mass: float, solid: float | None = None) -> None:
    """Raise ``ValueError`` naming the link unless its mass [kg] lies in
    ``(0, tol.link_mass_max]``; ``solid`` [kg] is its CAD's share, for the message.

    Examples
    --------
    >>> from types import SimpleNamespace
    >>> hand = SimpleNamespace(name="hand", mesh=None, lumped=())
    >>> check_link_mass(hand, 12.5)
    >>> check_link_mass(hand, 0.0)
    Traceback (most recent call last):
    ...
    ValueError: links.hand: the link has no mass (no CAD solid, lumped masses 0 kg): give \
it a mesh with a density or a lumped mass
    """
    if 0.0 < mass <= tol.link_mass_max:
        return
    lumped = sum(m.mass for m in link.lumped)
    parts = ("no CAD solid" if solid is None else f"CAD solid {solid:.4g} kg",
             f"lumped masses {lumped:.4g} kg")
    if not mass > 0:
        raise ValueError(f"links.{link.name}: the link has no mass ({', '.join(parts)}): give "
                         f"it a mesh with a density or a lumped mass")
    raise ValueError(f"links.{link.name}: {mass:.4g} kg is not a plausible link mass "
                     f"({', '.join(parts)}; at most {tol.link_mass_max:g} kg): are the CAD's "
                     f"units and the masses right?")
