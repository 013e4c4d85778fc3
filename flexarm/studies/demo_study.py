"""The demo's accuracy study: every variant of the built-in arm at P1 against the full-FE
reference, Tet4 and Tet10 (:func:`~flexarm.studies.arm_study.run_study`).

It is the costliest part of a cold demo, and most of it is the Tet10 reference (six
times the Tet4 reference's DOF).  Its three parts land in the package's caches as they
are computed (the references in ``study-reference``, the variants' links in
``superelements``), so a run of two processes computes them ahead, side by side
(:func:`study_references` in the worker, :func:`study_variants` here), and the study
itself then only reads them back.  The study is the same whichever way its parts were
computed: every part is keyed by what it depends on, not by who made it.
"""

from __future__ import annotations

from pathlib import Path

from ..robot import load_robot
from ..robot.description import Robot
from .arm_study import StudyResult, run_study, write_study
from .demo_cache import demo_result
from .demo_results import Progress

__all__ = ["POSE", "accuracy_study", "study_lines", "study_references", "study_sweep",
           "study_variants"]

#: The pose the study is run at.
POSE = "P1"


def study_sweep(robot: Robot) -> dict:
    """The demo's sweep: the robot's own mesh size, Guyan, CB(5) and CB(10), RBE2 and RBE3
    seats, and the Tet10 check of the mesh error (keyword arguments of
    :func:`~flexarm.studies.arm_study.run_study`).

    Examples
    --------
    >>> sweep = study_sweep(load_robot())
    >>> sweep["modes"], sweep["couplings"], sweep["tet10"]
    ((0, 5, 10), ('rbe2', 'rbe3'), True)
    """
    return {"sizes": (robot.options.mesh_size,), "modes": (0, 5, 10),
            "couplings": ("rbe2", "rbe3"), "tet10": True}


def accuracy_study(out: Path, progress: Progress, robot: Robot | None = None) -> StudyResult:
    """The study of :func:`study_sweep` at :data:`POSE` (kept between runs by
    :func:`~flexarm.studies.demo_cache.demo_result`), written into ``out / "study"``.

    The variants' times in the study (and its Pareto plot) are those of the run that
    computed them, as the build times of cached superelements are.
    """
    robot = robot or load_robot()
    sweep = study_sweep(robot)
    study = demo_result("study", lambda: run_study(
        robot, POSE, progress=lambda s: progress(f"study: {s}"), **sweep),
        robot.full_repr(), sorted(sweep.items()))
    write_study(study, out / "study")
    return study


def study_references(progress: Progress, robot: Robot | None = None) -> None:
    """Compute the study's two full-FE references (Tet4, then Tet10) into the cache: the
    study with no variants.  Takes most of a cold study's time."""
    robot = robot or load_robot()
    sweep = {**study_sweep(robot), "modes": (), "couplings": ()}
    run_study(robot, POSE, progress=lambda s: progress(f"study: {s}"), **sweep)


def study_variants(progress: Progress, robot: Robot | None = None) -> None:
    """Compute the study's Tet4 reference and variants into the cache: the study without
    the Tet10 check."""
    robot = robot or load_robot()
    sweep = {**study_sweep(robot), "tet10": False}
    run_study(robot, POSE, progress=lambda s: progress(f"study: {s}"), **sweep)


def study_lines(study: StudyResult) -> tuple[list[str], dict[str, float]]:
    """The study's lines in the flexible arm's section of ``index.md``, and its headline
    figure: the lower bound of the mesh error [%] when the Tet10 check ran."""
    figures = {}
    est = study.discretisation
    if est is not None and est.lower is not None:
        figures["flexible_mesh_error_min_pct"] = 100 * est.lower
    lines = [
        f"- Accuracy study at {study.pose} vs the full-FE reference ({study.reference.n_dofs} "
        f"DOF): [arm_study.csv](study/arm_study.csv); {study.verdict.replace(chr(10), '; ')}",
        "  ![error vs DOF](study/arm_study_error_vs_dof.png) ![Pareto](study/arm_study_pareto.png)",
    ]
    return lines, figures
