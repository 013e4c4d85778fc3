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

from ..assembly.build import link_regions
from ..reduction.tolerances import tol as red_tol
from ..robot.description import Robot
from ..robot.seat_geometry import coupling_rank
from ..robot.seat_review import is_review
from ..robot.seat_sample import link_sample

__all__ = ["build_problems", "review_regions"]


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
