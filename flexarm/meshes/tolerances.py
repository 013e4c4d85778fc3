"""Tolerances of CAD checks, hollowing and tetrahedralisation (``tol.<name>``)."""

from __future__ import annotations

from dataclasses import dataclass

__all__ = ["Tolerances", "tol"]


@dataclass(frozen=True)
class Tolerances:
    #: Plausible size of one robot part [m]: outside this, the units are probably wrong.
    part_size_min: float = 1e-3
    part_size_max: float = 20.0
    #: CAD surfaces: smallest / largest principal extent below this counts as flat.
    surface_flatness: float = 1e-9
    #: CAD surfaces: enclosed volume below this times (largest extent)^3 counts as zero.
    surface_min_volume: float = 1e-9
    #: Tetrahedra with a dihedral angle below this [deg] are slivers (the mesher retries).
    sliver_dihedral_deg: float = 5.0
    #: Gmsh: CPU time [s] every meshing try may take in its child process before it is
    #: stopped and the next try runs (Gmsh's remesh of some clean surfaces never returns) ...
    gmsh_try_cpu_floor: float = 20.0
    #: ... plus this many CPU seconds per element the try makes (the CAD's and the
    #: pre-mesh's triangles, the volume's tetrahedra): ten times Gmsh's 1.25 ms
    #: (``TETS_PER_SECOND``); the M-20iA's links at 30 mm take 2.7-13.8 CPU-s, 7.8 to 51
    #: times less than their budgets of 35-277 CPU-s (child start included, 2026-11-27).
    gmsh_try_cpu_per_element: float = 0.0125
    #: Gmsh's volume on the pre-mesh is not meshed when a pre-mesh triangle has an angle
    #: below this [deg]: a tetrahedron on it is a sliver (the published UR10's united
    #: hulls and hollowed shells at 30 mm: 2 to 3,823 such triangles per link, and then
    #: 4 to 8,695 slivers below ``sliver_dihedral_deg`` in every volume, 2026-12-07).
    premesh_needle_deg: float = 2.0
    #: pytetwild envelope: allowed surface deviation / bounding-box diagonal ...
    tet_envelope: float = 1e-3
    #: ... or this share of the target edge, where that is larger: a mesh at that edge
    #: cannot follow the surface closer (Gmsh's chords of a 45 mm radius at a 30 mm edge
    #: leave 2.5 mm), and fTetWild refines every small part to its envelope (the UR10's
    #: 0.18 m wrist_1_link at 30 mm: 40.8 CPU-s and 26,662 tetrahedra at 1e-3 of the
    #: diagonal, 5.8 CPU-s and 4,000 at 8e-3).  Three times it stays within the seat
    #: margin of a tenth of the edge (:func:`flexarm.robot.seat_geometry.seat_margin`).
    tet_envelope_edge: float = 1.0 / 30.0
    #: ``|V_tets - V_surface| / V_surface`` above which tetrahedralisation logs a warning.
    tet_volume_warn: float = 1e-2
    #: Hollowing: deepest surface vertex below the convex hull, over the largest extent,
    #: for the surface to count as convex (STL exports of convex hulls stay below ~6e-5).
    hollow_convex_depth: float = 1e-4
    #: Hollowing: hull volume the surface may miss, over the hull volume, to count as convex.
    hollow_convex_volume: float = 1e-3
    #: Hollowing: a cavity thinner than this times the largest extent (inscribed radius
    #: minus wall) counts as none: the part stays solid.
    hollow_solid: float = 1e-6
    #: Hollowing: an offset hull qhull cannot build is no cavity (a sheet only rounding
    #: errors thick) if the inscribed radius exceeds the wall by less than this times the
    #: largest extent; otherwise the qhull error is raised.
    hollow_flat_cavity: float = 1e-5
    #: Hollowing (erosion): eroded pieces with volume below this times the largest extent
    #: cubed are the zero-volume slivers manifold3d leaves where face prisms touch convex
    #: edges, and are dropped.
    hollow_sliver_volume: float = 1e-12
    #: Hollowing (erosion): a face whose twice area is at most this times its longest edge
    #: squared is a needle or a point without a trustworthy normal (capsules on its edges).
    hollow_needle_face: float = 1e-8
    #: Hollowing (erosion): an edge whose far corner lies less than this times the largest
    #: extent below the other face's plane counts as concave (coplanar edges get a capsule).
    hollow_flat_edge: float = 1e-9
    #: Wall for a mass: relative margin on (solid parts + lumped masses) within which a
    #: target counts as the solid mass (returns the inscribed radius; above: too light).
    hollow_mass_match: float = 1e-12
    #: Wall for a mass with eroded parts: Newton steps stop when the next step is below
    #: this share of the wall [-] (4 um on a 4 mm wall: below the 0.7 % an erosion
    #: takes off at concave edges).
    hollow_wall_step: float = 1e-3
    #: Wall for a mass with eroded parts: at most this many erosions per part.
    hollow_wall_iterations: int = 6
    #: Corners of an inward-offset hull within this times the part size [-] of each other
    #: are one corner (keeps the cavity closed through a float32 STL and a repair).
    hollow_point_merge: float = 1e-5

    #: A cavity face whose height is below this times the part size [-] is flat: flipped
    #: with its neighbour so no reader's repair drops it.
    hollow_flat_face: float = 1e-7
    #: A level-set cavity is simplified to this times the wall [-]: its flat stretches
    #: lose the grid's triangles, its curved ones keep the wall to 1 %.
    level_set_simplify: float = 1e-2

    #: Features of a united solid smaller than this times its size [-] are simplified
    #: away (the nanometre gaps of pieces read from float32 files).
    union_merge: float = 1e-6

    #: Self-touching surfaces: an edge end nearer than this times the diagonal [-] to a
    #: face it does not share counts as touching it.
    self_intersection_gap: float = 1e-6
    #: Self-touching surfaces: features of their union smaller than this times the
    #: diagonal [-] are simplified away (the sliver where two sheets touched; 0.2 mm on a
    #: 2 m link, far below any mesh size).
    self_intersection_merge: float = 1e-4
    #: Self-touching surfaces: a body united with itself may change its volume by this
    #: fraction [-] (a rounding touch); more means it really crosses itself (dirty CAD).
    self_intersection_volume: float = 1e-4


tol = Tolerances()
