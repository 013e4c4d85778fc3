"""Tolerances of paths, quaternions, RAPID values and bearing seats (``tol.<name>``)."""

from __future__ import annotations

from dataclasses import dataclass

__all__ = ["Tolerances", "tol"]


@dataclass(frozen=True)
class Tolerances:
    #: Unit-quaternion check of RAPID robtargets (they are printed to ~1e-4..1e-9).
    quaternion_norm: float = 1e-4
    #: Deepest bracket nesting read in a RAPID value [-] (a tooldata aggregate nests 3
    #: deep): deeper is refused on its line, before it could exhaust the stack.
    rapid_max_nesting: int = 32
    #: Three points are collinear when the triangle area is below this times ``|a| |b|``.
    collinear: float = 1e-9
    #: Below this angle [rad] SLERP falls back to normalised linear interpolation.
    slerp_small_angle: float = 1e-9
    #: KUKA's A, B, C: below this cos(B) [-] the rotation is at B = ±90 deg, where only
    #: A ∓ C is defined (A is set to 0, C takes the rest).
    euler_gimbal: float = 1e-12
    #: Bearing seats: share of the angular sectors about an axis [-] that a surface must
    #: cover to close a ring (a plane that merely contains the axis covers two of twelve).
    seat_ring_coverage: float = 0.75
    #: Bearing seats: a surface point faces a direction when the cosine between its normal
    #: and that direction is at least this [-] (0.5: within 60 degrees).
    seat_facing: float = 0.5
    #: Bearing seats: an end face is followed outwards while its front stays within this
    #: slope [m axial drop per m radius] of its point on the axis (hull faces are faceted).
    seat_face_slope: float = 0.5
    #: Bearing seats: tet-mesh surface nodes a face seat is grown to catch at the mesh size,
    #: as a multiple [-] of the rank-6 minimum (``min_region_nodes`` of the reduction layer).
    seat_mesh_nodes_factor: int = 4
    #: Bearing seats: the finest local tet edge a seat is meshed with, as a share [-] of
    #: the mesh size (:mod:`flexarm.robot.seat_mesh`; a seat smaller still keeps fewer
    #: nodes, and the import report says so).
    seat_local_edge_min: float = 0.125
    #: Bearing seats: CAD sample points [-] a seat must hold (a sample: far more than the
    #: rank-6 minimum of 3 nodes).
    seat_min_sample_points: int = 20
    #: Bearing seats: other surface a face seat's cylinder may take inside its rim, as a
    #: share [-] of the seat's own surface (sample points; more: a side wall, shrink it).
    seat_foreign_area: float = 0.15
    #: Plausible density of a link's CAD solid [kg/m^3]: below, a foam or a slipped
    #: unit; above, denser than any metal.  Hollow castings meshed as solid hulls with the
    #: datasheet mass (``with_total_mass``) land between ~300 and the metal's.
    density_min: float = 100.0
    density_max: float = 25000.0
    #: Heaviest plausible lumped mass (motor, gearbox, balancer) [kg].
    lumped_mass_max: float = 1e4
    #: Heaviest plausible link (CAD solid and lumped masses) [kg]: the base of the largest
    #: industrial robots weighs a few tonnes.
    link_mass_max: float = 5e4
    #: Plausible range of (largest CAD extent) / (the robot's reach: the sum of its joint
    #: offsets) for a link that carries no joint (the flange): 0.02..0.06 over the demo
    #: arm, the IRB 4600, the UR10 and the M-20iA; a wrong unit moves it by 25..1000.
    leaf_size_ratio: tuple[float, float] = (2e-3, 10.0)


tol = Tolerances()
