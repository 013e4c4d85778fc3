"""The demo's arm-level steps: the built-in robot as an E-model (rigid links + joint
springs) and as the flexible arm (Craig-Bampton links), each at the thesis poses,
with a stiffness map over joints 2 and 3.

Both steps build their arm with :func:`~flexarm.assembly.arm.build_arm` and report
through the same API the ``compliance``, ``frf``, ``map``, ``compare-models``, ``study``
and ``show-arm`` commands use.  The model comparison, the stiffness maps and the accuracy
study (:mod:`~flexarm.studies.demo_study`) are kept between runs
(:func:`~flexarm.studies.demo_cache.demo_result`); their tables and pictures are written
every run.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING

from ..assembly.arm import Arm, ArmSpec, build_arm
from ..assembly.build import LinkBuild
from ..robot import load_robot
from .compliance import ComplianceReport, compliance_report
from .demo_cache import demo_result
from .demo_results import Progress, StepResult, write_table
from .demo_study import accuracy_study, study_lines

if TYPE_CHECKING:
    from .arm_study import StudyResult

__all__ = ["POSES", "FlexibleArmPart", "emodel_step", "flexible_arm_step", "flexible_step"]

#: The thesis poses every table of the demo covers.
POSES = ("P1", "P2", "P3")


def emodel_step(out: Path, progress: Progress) -> StepResult:
    """The E-model at :data:`POSES`: modes, deflections, diagonal-model error, a Bode
    plot and a 60 x 60 stiffness map at P1.

    Link mass properties are volume integrals over the same tetrahedral meshes the
    flexible arm is built from.  Writes ``emodel_poses.csv``, ``emodel_bode_P1/``
    (``frf_bode.png`` and the ``frf.csv`` behind it), ``emodel_map.csv`` and
    ``emodel_map/`` into ``out``.
    """
    from ..assembly.emodel import total_mass

    robot = load_robot()
    progress("arm: link mass properties from tetrahedral meshes (cached after the first run)")
    arm = build_arm(robot, ArmSpec("emodel", mass="tets"))
    mass = total_mass(robot, arm.spec.mass, arm.spec.mesh_size)
    rows, table, figures = _emodel_poses(arm)
    figures["arm_mass_kg"] = mass
    write_table(out / "emodel_poses.csv",
                ["pose", *(f"f{i}_Hz" for i in range(1, 7)),
                 *(f"d{d}_800N_mm" for d in "xyz"), "weakest",
                 *(f"diag_err_{d}_pct" for d in "xyz")], rows)

    progress("arm: Bode plot at P1 and a 60 x 60 stiffness map over joints 2 and 3")
    bode_line = _bode(out / "emodel_bode_P1", arm, "P1")
    share_y, map_lines = _joint_map(out, arm, "emodel_map", 60)
    figures["emodel_map_y_weakest_share"] = share_y
    lines = [
        "## The arm as an E-model (rigid links + joint springs)",
        "",
        f"Built-in IRB 4600-class arm, {mass:.1f} kg; link mass properties are volume integrals"
        " over each link's tetrahedral mesh plus lumped motors and gearboxes.",
        "",
        "| pose | first modes [Hz] | TCP deflection at 800 N x / y / z [mm] | weakest "
        "| diagonal-model error x+ / y+ / z+ [%] |",
        "|---|---|---|---|---|",
        *table,
        "",
        "- Table: [emodel_poses.csv](emodel_poses.csv)",
        bode_line,
        f"- Joint-space map (q2, q3) at P1's other joints: [emodel_map.csv](emodel_map.csv); "
        f"Y is the least stiff direction on {share_y * 100:.1f}% of the grid.",
        *map_lines,
        "",
    ]
    return StepResult(lines, figures)


def flexible_step(out: Path, progress: Progress) -> StepResult:
    """The flexible arm: link builds, model comparison, map and pictures
    (:func:`flexible_arm_step`), then the accuracy study
    (:func:`~flexarm.studies.demo_study.accuracy_study`).

    Writes ``build.csv``, ``models/``, ``study/``, ``flexible_map.csv``,
    ``flexible_map/`` and the mode pictures ``arm_P1_mode1.gif``, ``arm_P1_mode2.png``
    into ``out``.
    """
    part = flexible_arm_step(out, progress)
    progress("arm: accuracy study at P1 against the full-FE reference (cached after the first run)")
    return part.with_study(accuracy_study(out, progress))


@dataclass(frozen=True)
class FlexibleArmPart:
    """The flexible arm's section of ``index.md`` but for the accuracy study, which goes
    between ``head`` and ``tail``, and its headline figures (:meth:`with_study`).

    Attributes
    ----------
    head, tail : tuple of str
        Index lines before and after the study's.
    figures : tuple of (str, float)
        Headline figures of the poses, in order.
    map_share : float
        Share of the stiffness map's grid where y is the least stiff direction [-].
    """

    head: tuple[str, ...]
    tail: tuple[str, ...]
    figures: tuple[tuple[str, float], ...]
    map_share: float

    def with_study(self, study: StudyResult) -> StepResult:
        """The whole step, with the lines and the figure of ``study``."""
        lines, figures = study_lines(study)
        return StepResult([*self.head, *lines, *self.tail],
                          {**dict(self.figures), **figures,
                           "flexible_map_y_weakest_share": self.map_share})


def flexible_arm_step(out: Path, progress: Progress) -> FlexibleArmPart:
    """The flexible arm but for its accuracy study: link builds, model comparison, poses,
    stiffness map and mode pictures.

    Writes ``build.csv``, ``models/``, ``flexible_map.csv``, ``flexible_map/``,
    ``arm_P1_mode1.gif`` and ``arm_P1_mode2.png`` into ``out``.
    """
    from .compare_models import compare_models

    robot = load_robot()
    arm = build_arm(robot, ArmSpec("cb"), progress=lambda s: progress(f"build: {s}"))
    write_table(out / "build.csv",
                ["link", "tets", "dofs", "reduced_dofs", "f1_fixed_Hz", "seconds"],
                [_build_row(b) for b in arm.builds])

    progress("arm: E-model, Guyan, CB and CB + coupled wrist at P1, P2, P3")
    # the comparison's links are the cached superelements above; its modes and receptances
    # at three poses are what a warm run would otherwise compute again
    demo_result("models", lambda: compare_models(robot, POSES, full_fe=False),
                robot.full_repr()).write(out / "models")
    rows, figures = _flexible_poses(arm)

    progress("arm: flexible stiffness map over (q2, q3) and mode pictures")
    share_y, map_lines = _joint_map(out, arm, "flexible_map", 30)
    opts = arm.spec.build_options().resolved(robot)
    head = (
        "## The flexible arm (Craig-Bampton links joined by the same joint springs)",
        "",
        f"Links tetrahedralised at {opts.mesh_size * 1e3:g} mm, reduced by {opts.method.upper()}"
        f"({opts.n_modes}) with {opts.coupling.upper()} interfaces ([build.csv](build.csv)): "
        f"{sum(b.n_fe_dofs for b in arm.builds)} FE DOF → {arm.model.layout['n']} arm "
        "coordinates.",
        "",
        "| pose | f1 [Hz] | TCP deflection at 800 N x / y / z [mm] | weakest |",
        "|---|---|---|---|",
        *rows,
        "",
        "- Model comparison (first 10 frequencies, TCP compliance): "
        "[model_comparison.csv](models/model_comparison.csv) · "
        "![Bode](models/model_comparison_bode.png)",
    )
    tail = (
        f"- Flexible stiffness map: [flexible_map.csv](flexible_map.csv); Y is the least stiff "
        f"direction on {share_y * 100:.1f}% of the grid.",
        *map_lines,
        *_arm_pictures(out, arm),
        "",
    )
    return FlexibleArmPart(head, tail, tuple(figures.items()), share_y)


def _emodel_poses(arm: Arm) -> tuple[list[list], list[str], dict[str, float]]:
    """Per pose of :data:`POSES`: the ``emodel_poses.csv`` row (first 6 frequencies
    [Hz], deflections at 800 N [mm], weakest direction, diagonal-model errors [%]), the
    index table row, and the headline figures."""
    from ..assembly.analyses import modes

    rows, table, figures = [], [], {}
    for name in POSES:
        q = arm.robot.pose(name)
        freq = modes(arm.model, q).freq_hz
        rep = compliance_report(arm.model, q)
        defl, err = rep.deflection * 1e3, rep.error_diag * 100
        rows.append([name, *map(float, freq[:6]), *map(float, defl), rep.weakest,
                     *map(float, err)])
        table.append(f"| {name} | " + ", ".join(f"{f:.1f}" for f in freq[:4]) + " | "
                     + _mm(rep) + f" | {rep.weakest.upper()} | "
                     + " / ".join(f"{e:.1f}" for e in err) + " |")
        figures.update(_pose_figures("emodel", name, float(freq[0]), rep))
    return rows, table, figures


def _flexible_poses(arm: Arm) -> tuple[list[str], dict[str, float]]:
    """Per pose of :data:`POSES`: the index table row (f1 [Hz], deflections at 800 N
    [mm], weakest direction) and the headline figures."""
    from ..assembly.analyses import natural_frequencies

    rows, figures = [], {}
    for name in POSES:
        q = arm.robot.pose(name)
        f1 = float(natural_frequencies(arm.model, q)[0])
        rep = compliance_report(arm.model, q)
        rows.append(f"| {name} | {f1:.2f} | {_mm(rep)} | {rep.weakest.upper()} |")
        figures.update(_pose_figures("flexible", name, f1, rep))
    return rows, figures


def _mm(rep: ComplianceReport) -> str:
    """TCP deflection x / y / z [mm] under the report's load."""
    return " / ".join(f"{d * 1e3:.2f}" for d in rep.deflection)


def _pose_figures(model: str, pose: str, f1: float, rep: ComplianceReport) -> dict[str, float]:
    """The headline figures of ``model`` at ``pose``: f1 [Hz] and the y deflection [mm]."""
    return {f"{model}_{pose}_f1_Hz": f1,
            f"{model}_{pose}_defl_800N_y_mm": float(rep.deflection[1] * 1e3)}


def _build_row(b: LinkBuild) -> list:
    """One ``build.csv`` row: link, tets, FE DOF, reduced DOF, f1 fixed [Hz], time [s]."""
    f1 = float(b.freq_hz[0]) if len(b.freq_hz) else float("nan")
    return [b.name, b.n_tets, b.n_fe_dofs, b.n_reduced, f1, float(b.seconds)]


def _bode(folder: Path, arm: Arm, pose: str) -> str:
    """Bode plot of the TCP receptance of ``arm`` at ``pose`` up to 200 Hz, with the CSV
    behind it (:meth:`~flexarm.studies.frf.FrfReport.write`: ``frf_bode.png`` and
    ``frf.csv`` in ``folder``); the index line."""
    from .frf import frf_report

    bode = frf_report(arm.model, arm.robot.pose(pose), fmax=200.0, n=500,
                      title=f"{arm.spec.label} TCP receptance at {pose}")
    png, csv = bode.write(folder)
    rel = f"{folder.name}/"
    return (f"- Bode at {pose}: ![bode]({rel}{png.name}) · data: "
            f"[{csv.name}]({rel}{csv.name})")


def _joint_map(out: Path, arm: Arm, name: str, n: int) -> tuple[float, list[str]]:
    """Stiffness map of ``arm`` on an ``n`` x ``n`` grid over the limits of joints 2 and
    3, the others at P1 (``<name>.csv`` and heat maps in ``<name>/``, titled with the
    model's label and the pose): the share of the grid [-] where y is the least stiff
    direction, and the index lines of the heat maps."""
    from ..assembly.maps import limits_map, plot_map, write_csv

    robot = arm.robot
    m = demo_result(name, lambda: limits_map(arm.model, robot.pose("P1"), robot.lower,
                                             robot.upper, n, label=arm.spec.label,
                                             pose_name="P1"),
                    robot.full_repr(), arm.spec, n)
    write_csv(out / f"{name}.csv", m)
    pngs = plot_map(m, out / name, surfaces=False)
    return float(m.least_stiff_share[1]), [f"  - ![{p.stem}]({name}/{p.name})" for p in pngs]


def _arm_pictures(out: Path, arm: Arm) -> list[str]:
    """Mode 1 (GIF, with the TCP compliance ellipsoid) and mode 2 (PNG) of ``arm`` at P1;
    the index line, or why there are no pictures."""
    try:
        from .render_arm import render_arm_mode

        q = arm.robot.pose("P1")
        # 800 x 600: software GL renders each GIF frame in ~0.25 s instead of ~0.45 s
        render_arm_mode(arm, q, 1, out / "arm_P1_mode1.gif", ellipsoid=True, pose_name="P1",
                        n_frames=10, window_size=(800, 600))
        render_arm_mode(arm, q, 2, out / "arm_P1_mode2.png", pose_name="P1")
        return ["- Mode shapes at P1 (links recovered to the full field, TCP compliance "
                "ellipsoid): ![mode 1](arm_P1_mode1.gif) ![mode 2](arm_P1_mode2.png)"]
    except Exception as exc:  # noqa: BLE001 - pictures are optional; say why they are missing
        return [f"- (no arm pictures: {exc})"]
