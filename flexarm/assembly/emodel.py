"""The E-model: rigid links with their meshes' mass properties, joined by joint springs.

Each link becomes a one-node rigid :class:`~flexarm.assembly.bodies.Body` at its
link frame origin (the joint from its parent), carrying the mass properties of
its tetrahedral mesh (volume integrals of the solid) plus its lumped masses.
The flexible arm differs only in replacing these bodies by superelements.
"""

from __future__ import annotations

import logging

import numpy as np

from ..fe.cache import cache_key, cached
from ..fe.files import file_digest
from ..fe.mass_properties import MassProperties, mass_properties
from ..robot.description import Link, Robot
from ..robot.link_checks import check_link_mass, link_surface, naming_link
from .bodies import combine_mass_properties, point_mass_properties, rigid_body
from .system import ArmModel

__all__ = ["link_mass_properties", "emodel", "total_mass", "with_total_mass"]

log = logging.getLogger(__name__)

METHODS = ("tets", "surface")


def _mesh_mass_properties(link: Link, method: str, mesh_size: float,
                          mesher: str = "tetwild") -> MassProperties:
    """Mass properties of a link's CAD solid: volume integrals over its (cached) tetrahedra,
    or the closed-surface integrals of the CAD (cached by the file's bytes).  Either way
    the CAD is read as ``flexarm mesh`` reads it
    (:func:`~flexarm.robot.link_checks.link_surface`): an open, non-manifold or empty
    surface is refused, naming the link."""
    if method == "tets":
        from .build import link_mesh

        with naming_link(link):
            mesh = link_mesh(link, mesh_size, mesher=mesher)
        return mass_properties(mesh, link.material.rho)
    # "checked": entries of the unchecked reader (trimesh's own) are not reused
    key = cache_key("mass-properties", "checked", file_digest(link.mesh), link.units,
                    link.material.rho)
    d = cached("mass-properties", key, lambda: _surface_mass_properties(link)).value
    return MassProperties(d["mass"], np.array(d["center_of_mass"]), np.array(d["inertia"]))


def _surface_mass_properties(link: Link) -> dict:
    log.info("mass properties of %s (CAD surface)", link.name)
    tm = link_surface(link).mass_properties
    rho = link.material.rho
    return {"mass": rho * float(tm.volume), "center_of_mass": np.asarray(tm.center_mass).tolist(),
            "inertia": (rho * np.asarray(tm.inertia)).tolist()}


def link_mass_properties(link: Link, method: str = "surface", mesh_size: float | None = None,
                         mesher: str = "tetwild"):
    """:class:`MassProperties` of a link (solid mesh + lumped masses) in its link frame.

    Parameters
    ----------
    link : Link
    method : {"tets", "surface"}
        ``"tets"``: volume integrals over the tetrahedral mesh of the CAD
        (``meshes.tetrahedralize``, cached); ``"surface"``: trimesh's closed-surface
        integrals of the CAD itself (fast; for watertight CAD only).
    mesh_size : float
        Tet edge length [m], needed for ``"tets"``; the integrals are exact for any tet
        mesh.
    mesher : {"tetwild", "gmsh"}
        Tetrahedraliser for ``"tets"`` (the robot's ``model.mesher``).
    """
    if method not in METHODS:
        raise ValueError(f"method must be one of {METHODS}, got '{method}'")
    if method == "tets" and mesh_size is None:
        raise ValueError("link mass properties from tets need the mesh size [m]")
    parts = [] if link.mesh is None else [_mesh_mass_properties(link, method, mesh_size,
                                                                 mesher)]
    solid = parts[0].mass if parts else None
    parts += [point_mass_properties(m.mass, m.position, m.inertia) for m in link.lumped]
    if not parts:
        raise ValueError(f"links.{link.name}: no mesh and no lumped masses (a massless link)")
    check_link_mass(link, sum(p.mass for p in parts), solid)
    return combine_mass_properties(parts)


def total_mass(robot: Robot, method: str = "surface", mesh_size: float | None = None) -> float:
    """Total mass of the robot [kg] (links and lumped masses); ``mesh_size`` [m] of
    ``method="tets"`` defaults to the robot's."""
    size = robot.options.mesh_size if mesh_size is None else mesh_size
    return sum(link_mass_properties(lk, method, size, robot.options.mesher).mass
               for lk in robot.links)


def with_total_mass(robot: Robot, mass_kg: float, method: str = "surface",
                    mesh_size: float | None = None) -> Robot:
    """``robot`` with every link's density scaled by one factor so that its total mass
    (CAD solids + lumped masses) is ``mass_kg`` [kg].

    For CAD that is a solid hull of a hollow casting (URDF collision meshes): the
    datasheet mass is known, the wall thickness is not.  Stiffness (E, nu) is kept.
    """
    import dataclasses

    mesh_size = robot.options.mesh_size if mesh_size is None else mesh_size
    solid = sum(_mesh_mass_properties(lk, method, mesh_size, robot.options.mesher).mass
                for lk in robot.links if lk.mesh is not None)
    lumped = total_mass(robot, method, mesh_size) - solid
    if not np.isfinite(mass_kg) or mass_kg <= lumped or solid <= 0:
        raise ValueError(f"total mass {mass_kg:g} kg must exceed the lumped masses "
                         f"({lumped:g} kg) of a robot with CAD solids")
    factor = (mass_kg - lumped) / solid
    links = tuple(
        lk if lk.mesh is None else dataclasses.replace(
            lk, material=dataclasses.replace(lk.material, rho=lk.material.rho * factor,
                                             name=f"{lk.material.name} (hollow-equivalent)"))
        for lk in robot.links)
    log.info("densities scaled by %.4f for a total of %.1f kg", factor, mass_kg)
    return dataclasses.replace(robot, links=links)


def emodel(robot: Robot, method: str = "surface", mesh_size: float | None = None,
           equivalent: bool = True) -> ArmModel:
    """The rigid-link E-model :class:`ArmModel` of ``robot``.

    Parameters
    ----------
    robot : Robot
    method : {"tets", "surface"}
        Mass properties of the links, see :func:`link_mass_properties`.
    mesh_size : float, optional
        Tet edge length [m] for ``"tets"`` (default: the robot's ``model.mesh_size``).
    equivalent : bool
        Use each joint's *equivalent* E-model joint (``joint.emodel``: bearing in
        series with the bending of the links it carries, stored in the robot file,
        see :mod:`~flexarm.assembly.equivalent`) where the robot gives one; False
        uses the physical joints (``joint.model``), the rigid-link limit of the
        flexible arm.

    Examples
    --------
    >>> from flexarm.robot.demo_arm import load_demo_robot
    >>> arm = emodel(load_demo_robot(), method="surface")
    >>> arm.layout["n"]  # 6 torsion + 3 x 2 bearing tilts
    12
    """
    log.info("E-model of %s", robot.name)
    mesh_size = robot.options.mesh_size if mesh_size is None else mesh_size
    chain = robot.chain
    points: list[dict] = [{} for _ in robot.links]
    for j, jt in enumerate(robot.joints):
        points[int(chain.parents[j])][jt.name] = jt.origin
    points[chain.tcp_body]["tcp"] = chain.tool[:3, 3]
    bodies = tuple(
        rigid_body(lk.name, link_mass_properties(lk, method, mesh_size, robot.options.mesher),
                   np.zeros(3), points[i])
        for i, lk in enumerate(robot.links)
    )
    foundation = None
    if robot.base.kind == "spring":
        foundation = np.asarray(robot.base.stiffness, dtype=float)
    wrist = None if robot.wrist_stiffness is None else np.asarray(robot.wrist_stiffness)
    log.info("E-model of %s done", robot.name)
    joints = tuple(j.emodel if equivalent and j.emodel is not None else j.model
                   for j in robot.joints)
    return ArmModel(chain, bodies, joints, robot.joint_names,
                    "tcp", foundation, robot.base.damping_ratio, wrist, robot.joint_names,
                    np.column_stack([robot.lower, robot.upper]))
