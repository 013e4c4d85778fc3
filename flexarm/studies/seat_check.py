"""Can a robot file be built?  The regions the build needs, checked on the CAD.

:func:`build_problems` asks, link by link, what the build asks of the tet mesh, on the
link's CAD sample instead (:func:`~flexarm.robot.seat_sample.link_sample`: seconds, no
meshing): every region the link's superelement needs is there
(:func:`~flexarm.assembly.build.link_regions`), holds CAD surface that could carry six
rigid-body DOFs, and shares none with another region of the link.  ``import-urdf`` runs
it on the file it wrote and fails when the file cannot be built; regions suggested for
review are listed by :func:`review_regions` (they may build, but nobody confirmed them).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from ..assembly.build import link_regions
from ..reduction.tolerances import tol as red_tol
from ..robot.description import Robot
from ..robot.seat_geometry import coupling_rank
from ..robot.seat_mesh import seat_mesh_nodes
from ..robot.seat_pairs import PAIR_GAP, SeatPair, seat_pairs
from ..robot.seat_review import is_review
from ..robot.seat_sample import link_sample
from .show_pairs import MIN_PAIR_NODES

__all__ = ["PairCheck", "build_problems", "pair_checks", "pairs_line", "review_regions"]


def build_problems(robot: Robot) -> tuple[str, ...]:
    """One line per reason the build would refuse a link's regions (empty: none).

    Examples
    --------
    >>> from flexarm.robot import load_robot
    >>> build_problems(load_robot())
    ()
    """
    problems = []
    for i, lk in enumerate(robot.links):
        if lk.mesh is None:
            continue
        try:
            names = link_regions(robot, i)
        except ValueError as exc:
            problems.append(str(exc))
            continue
        points = link_sample(lk).points
        inside = {n: lk.regions[n].contains(points) for n in names}
        for n in names:
            k = int(inside[n].sum())
            if k < red_tol.min_region_nodes or coupling_rank(points[inside[n]]) < 6:
                problems.append(f"links.{lk.name}.regions.{n}: holds {k} CAD sample points "
                                "that cannot carry 6 rigid-body DOFs (it misses the surface)")
        for a, na in enumerate(names):
            for nb in names[a + 1:]:
                shared = int((inside[na] & inside[nb]).sum())
                if shared:
                    problems.append(f"links.{lk.name}: regions '{na}' and '{nb}' overlap "
                                    f"({shared} shared CAD sample points)")
    return tuple(problems)


def review_regions(robot: Robot) -> tuple[str, ...]:
    """``link:region`` of every region marked ``review = true``.

    >>> from flexarm.robot import load_robot
    >>> review_regions(load_robot())
    ()
    """
    return tuple(f"{lk.name}:{n}" for lk in robot.links for n, r in lk.regions.items()
                 if is_review(r))


@dataclass(frozen=True)
class PairCheck:
    """One joint's two seats on the CAD: their :class:`~flexarm.robot.seat_pairs.SeatPair`
    (metres) and about how many FE nodes each will hold on the build's tet mesh of edge
    ``mesh_size`` [m], refined over a seat that needs it
    (:func:`~flexarm.robot.seat_mesh.seat_mesh_nodes`)."""

    pair: SeatPair
    parent_nodes: int
    child_nodes: int
    mesh_size: float

    @property
    def problem(self) -> str:
        """What is wrong with the pair on the CAD, in one phrase ("" when the seats face
        each other; the node counts are estimates, for ``flexarm build`` to check)."""
        return "" if self.pair.ok else self.pair.status

    @property
    def few_nodes(self) -> bool:
        """Whether either side would hold fewer than the pair check's nodes (estimate)."""
        return min(self.parent_nodes, self.child_nodes) < MIN_PAIR_NODES

    def warning(self) -> str:
        """One line naming the joint, its links and what is wrong (the gap)."""
        p = self.pair
        return (f"{p.joint}: its seats on {p.parent} and {p.child} do not pair up: "
                f"{self.problem}; give one with --seat {p.parent}:{p.joint}=... or "
                f"--seat {p.child}:{p.joint}=...")


def pair_checks(robot: Robot, mesh_size: float | None = None) -> tuple[PairCheck, ...]:
    """:class:`PairCheck` of every joint whose links have CAD, at the mesh edge
    ``mesh_size`` [m] (default the robot's).

    Examples
    --------
    >>> from flexarm.robot import load_robot
    >>> c = pair_checks(load_robot())[1]  # the demo arm's joint 2: a shaft through a bore
    >>> c.pair.joint, c.problem, c.parent_nodes, c.child_nodes
    ('joint_2', '', 44, 68)
    """
    h = robot.options.mesh_size if mesh_size is None else float(mesh_size)
    estimates = {}
    out = []
    for p in seat_pairs(robot):
        nodes = []
        for link in (p.parent, p.child):
            if link not in estimates:
                estimates[link] = seat_mesh_nodes(robot.links[robot.link_index[link]], h)
            nodes.append(int(math.floor(estimates[link].get(p.joint, 0.0) + 1e-9)))
        out.append(PairCheck(p, nodes[0], nodes[1], h))
    return tuple(out)


def pairs_line(checks) -> str:
    """One line: how many pairs hold, their gaps [mm] and the fewest nodes a side.

    Examples
    --------
    >>> from flexarm.robot import load_robot
    >>> print(pairs_line(pair_checks(load_robot())))  # doctest: +NORMALIZE_WHITESPACE
    seat pairs: 5 of 6 within 5 mm along the joint axis or spanning it (gaps -82.1 to
    185.6 mm); at least about 10 FE nodes a side at 30 mm (`flexarm build` counts them on
    the mesh)
    """
    if not checks:
        return "seat pairs: none (no joint has CAD on both links)"
    good = sum(not c.problem for c in checks)
    gaps = [1e3 * c.pair.gap for c in checks if math.isfinite(c.pair.gap)]
    span = f" (gaps {min(gaps):.1f} to {max(gaps):.1f} mm)" if gaps else ""
    fewest = min(min(c.parent_nodes, c.child_nodes) for c in checks)
    few = [c.pair.joint for c in checks if c.few_nodes]
    where = f" ({', '.join(few)}: fewer than {MIN_PAIR_NODES})" if few else ""
    return (f"seat pairs: {good} of {len(checks)} within {PAIR_GAP * 1e3:g} mm along the "
            f"joint axis or spanning it{span}; at least about {fewest} FE nodes a side at "
            f"{checks[0].mesh_size * 1e3:g} mm{where} (`flexarm build` counts them on the "
            "mesh)")
