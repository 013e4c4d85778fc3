"""The main job on built-in data: ``flexarm demo``.

Each step writes its tables and pictures into one output folder and returns the
lines it adds to ``index.md``; a step whose optional part (e.g. off-screen rendering)
is unavailable says so in the index instead of failing the whole demo.  Expensive
results (tetrahedra) come from the on-disk cache, so a warm run is quick.
"""

from __future__ import annotations

import logging
import time
from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from ..fe import (
    MATERIALS,
    assemble,
    dof_split,
    mass_properties,
    modes,
    node_dofs,
    shift_invert,
)
from ..fe.files import atomic_path

__all__ = ["DemoReport", "run_demo"]

log = logging.getLogger(__name__)

Progress = Callable[[str], None]


@dataclass
class DemoReport:
    """What the demo produced: output folder, index lines and headline figures."""

    folder: Path
    lines: list[str] = field(default_factory=list)
    figures: dict[str, float] = field(default_factory=dict)
    seconds: float = 0.0


def _write_csv(path: Path, header: list[str], rows) -> None:
    with atomic_path(path) as tmp:
        body = "".join(",".join(f"{v:.10g}" if isinstance(v, float) else str(v) for v in r) + "\n"
                       for r in rows)
        tmp.write_text(",".join(header) + "\n" + body)


def _part_step(out: Path, report: DemoReport, progress: Progress, size: float) -> None:
    """One built-in cast link: CAD -> Tet10 -> free and clamped modes."""
    from ..meshes import (
        hollow_link_surface,
        mesh_quality,
        tetrahedralize,
        write_surface,
        write_volume_mesh,
    )

    material = MATERIALS["cast_iron"]
    surface = hollow_link_surface()
    write_surface(out / "link.stl", surface)
    progress(f"part: tetrahedralising the built-in link (edge {size * 1e3:g} mm, cached)")
    mesh = tetrahedralize(surface, size, order=2, name="demo link")
    quality = mesh_quality(mesh, surface)
    write_volume_mesh(out / "link.vtu", mesh)
    (out / "link_quality.txt").write_text(quality.table() + "\n")

    progress(f"part: assembling K, M ({mesh.n_dofs} DOF) and solving free modes")
    t0 = time.perf_counter()
    K, M = assemble(mesh, material)
    t_asm = time.perf_counter() - t0
    free = modes(K, M, 16)
    mp = mass_properties(mesh, material.rho)

    # Clamp the bearing bore of the hub at the link origin (axis y through x = z = 0).
    r = np.hypot(mesh.points[:, 0], mesh.points[:, 2])
    bore = np.flatnonzero((r < 0.06 + 1e-3) & (np.abs(mesh.points[:, 0]) < 0.11))
    split = dof_split(mesh.n_dofs, node_dofs(bore))
    progress("part: clamped modes (hub bore at the origin fixed)")
    clamped = modes(split.condense(K), split.condense(M), 10, eigensolver=shift_invert(0.0))

    rows = [[i + 1, float(f), int(rig)]
            for i, (f, rig) in enumerate(zip(free.freq_hz, free.is_rigid, strict=True))]
    _write_csv(out / "link_free_modes.csv", ["mode", "freq_Hz", "rigid"], rows)
    _write_csv(out / "link_clamped_modes.csv", ["mode", "freq_Hz"],
               [[i + 1, float(f)] for i, f in enumerate(clamped.freq_hz)])
    report.figures.update({
        "link_mass_kg": mp.mass,
        "link_rigid_modes": float(free.n_rigid),
        "link_first_free_Hz": float(free.freq_hz[~free.is_rigid][0]),
        "link_first_clamped_Hz": float(clamped.freq_hz[0]),
    })
    se_lines = _superelement_pictures(out, mesh, material, report, progress)
    report.lines += [
        "## One cast link (part level)",
        "",
        f"Built-in hollow link, {material.name} (E {material.E / 1e9:g} GPa, "
        f"ρ {material.rho:g} kg/m³): "
        f"{mesh.n_tets} Tet10, {mesh.n_dofs} DOF, mass {mp.mass:.2f} kg; assembly {t_asm:.2f} s.",
        "",
        "- CAD: [link.stl](link.stl) · volume mesh: [link.vtu](link.vtu) · "
        "quality: [link_quality.txt](link_quality.txt)",
        f"- Free modes ([link_free_modes.csv](link_free_modes.csv)): "
        f"{free.n_rigid} rigid-body modes, "
        f"first elastic {report.figures['link_first_free_Hz']:.1f} Hz",
        "- Clamped at the origin hub ([link_clamped_modes.csv](link_clamped_modes.csv)): "
        + ", ".join(f"{f:.1f}" for f in clamped.freq_hz[:6]) + " Hz",
        *se_lines,
        "",
    ]


def _superelement_pictures(out: Path, mesh, material, report: DemoReport,
                           progress: Progress) -> list[str]:
    """Craig-Bampton superelement of the link on its two hub bores, plus mode pictures."""
    from ..reduction import CylinderRegion, reduce_with_stats
    from ..reduction.formats import write as write_superelement

    bores = [CylinderRegion(name, (x, 0.0, 0.0), (0.0, 1.0, 0.0), 0.0, 0.065, 0.1)
             for name, x in (("hub_a", 0.0), ("hub_b", 0.8))]
    progress("part: Craig-Bampton superelement (RBE2 on both bores, 10 modes)")
    se, stats = reduce_with_stats(mesh, material, bores, "rbe2", "cb", 10)
    write_superelement(out / "link_cb10.h5", se)
    report.figures["link_superelement_dof"] = float(se.n_dofs)
    lines = [
        f"- Craig-Bampton superelement [link_cb10.h5](link_cb10.h5): {stats.n_full} → "
        f"{stats.n_reduced} DOF in {stats.total_seconds:.1f} s; fixed-interface modes "
        + ", ".join(f"{f:.0f}" for f in se.freq_hz[:5]) + " Hz",
    ]
    try:
        from ..reduction.render import render_mode

        render_mode(se, 1, out / "link_fixed_mode1.png", boundary="fixed")
        render_mode(se, 1, out / "link_free_mode1.gif", boundary="free")
        lines += ["", "  ![fixed-interface mode 1](link_fixed_mode1.png) "
                      "![free mode 1](link_free_mode1.gif)"]
    except Exception as exc:  # noqa: BLE001 - pictures are optional; say why they are missing
        lines += [f"- (no pictures: {exc})"]
    return lines


def _emodel_step(out: Path, report: DemoReport, progress: Progress) -> None:
    """The built-in arm as an E-model (rigid links + joint springs) at the thesis poses."""
    from ..assembly import emodel, identify_stiffness, stiffness_map, tcp_compliance
    from ..assembly import modes as arm_modes
    from ..assembly.analyses import frf
    from ..assembly.maps import plot_map, write_csv
    from ..robot.demo_arm import load_demo_robot
    from .plots import plot_frf

    robot = load_demo_robot()
    progress("arm: link mass properties from tetrahedral meshes (cached after the first run)")
    arm = emodel(robot, method="tets", mesh_size=robot.options.mesh_size)
    from ..assembly.emodel import total_mass

    mass = total_mass(robot, method="tets", mesh_size=robot.options.mesh_size)
    rows, lines = [], []
    for name in ("P1", "P2", "P3"):
        q = robot.pose(name)
        md = arm_modes(arm, q)
        C = tcp_compliance(arm, q)[:3, :3]
        defl = 800.0 * np.diag(C) * 1e3
        ident = identify_stiffness(arm, q)
        weakest = "xyz"[int(np.argmax(np.diag(C)))]
        rows.append([name, *[float(f) for f in md.freq_hz[:6]], *[float(d) for d in defl], weakest,
                     *[float(e) * 100 for e in ident.error_diag]])
        lines.append(f"| {name} | " + ", ".join(f"{f:.1f}" for f in md.freq_hz[:4]) + " | "
                     + " / ".join(f"{d:.2f}" for d in defl) + f" | {weakest.upper()} | "
                     + " / ".join(f"{e * 100:.1f}" for e in ident.error_diag) + " |")
        report.figures[f"emodel_{name}_f1_Hz"] = float(md.freq_hz[0])
        report.figures[f"emodel_{name}_defl_800N_y_mm"] = float(defl[1])
    report.figures["arm_mass_kg"] = mass
    header = (["pose"] + [f"f{i}_Hz" for i in range(1, 7)]
              + ["dx_800N_mm", "dy_800N_mm", "dz_800N_mm"]
              + ["weakest", "diag_err_x_pct", "diag_err_y_pct", "diag_err_z_pct"])
    _write_csv(out / "emodel_poses.csv", header, rows)

    progress("arm: Bode plot at P1 and a 60 x 60 stiffness map over joints 2 and 3")
    q1 = robot.pose("P1")
    f = np.geomspace(0.5, 200.0, 500)
    plot_frf(out / "emodel_bode_P1.png", f, frf(arm, q1, f), "E-model TCP receptance at P1")
    lo, hi = robot.lower, robot.upper
    m = stiffness_map(arm, q1, np.linspace(lo[1], hi[1], 60), np.linspace(lo[2], hi[2], 60))
    write_csv(out / "emodel_map.csv", m)
    pngs = plot_map(m, out / "emodel_map", surfaces=False)
    share_y = float(np.mean(m.least_stiff == 1))
    report.figures["emodel_map_y_weakest_share"] = share_y
    report.lines += [
        "## The arm as an E-model (rigid links + joint springs)",
        "",
        f"Built-in IRB 4600-class arm, {mass:.1f} kg; link mass properties are volume integrals"
        " over each link's tetrahedral mesh plus lumped motors and gearboxes.",
        "",
        "| pose | first modes [Hz] | TCP deflection at 800 N x / y / z [mm] | weakest "
        "| diagonal-model error x+ / y+ / z+ [%] |",
        "|---|---|---|---|---|",
        *lines,
        "",
        "- Table: [emodel_poses.csv](emodel_poses.csv) · Bode at P1: ![bode](emodel_bode_P1.png)",
        f"- Joint-space map (q2, q3) at P1's other joints: [emodel_map.csv](emodel_map.csv); "
        f"Y is the least stiff direction on {share_y * 100:.1f}% of the grid.",
        *[f"  - ![{p.stem}](emodel_map/{p.name})" for p in pngs],
        "",
    ]


def _measurement_step(out: Path, report: DemoReport, progress: Progress) -> None:
    """Shipped lab data with a hidden effect: compare -> diagnose -> apply -> compare."""
    from importlib.resources import files

    from ..assembly.emodel import emodel
    from ..robot.demo_arm import load_demo_robot
    from ..robot.formats import read as read_robot
    from ..robot.formats import write as write_robot
    from ..validation import read_measurements
    from ..validation.compare import compare_static, write_report
    from ..validation.diagnose import diagnose
    from ..validation.history import robot_with_effects, write_history

    source = Path(str(files("flexarm") / "data" / "lab" / "lab_hidden_effect.csv"))
    data_path = out / "measurements.csv"
    data_path.write_bytes(source.read_bytes())
    robot = load_demo_robot()
    arm = emodel(robot, method="surface")
    data = read_measurements(data_path)
    progress("measurements: nominal model vs lab data, then diagnosis")
    before = compare_static(arm, data)
    write_report(out / "measurements_v0", before)
    dg = diagnose(arm, data, poses=robot.poses)
    write_history(out / "diagnosis", dg)
    write_robot(out / "robot_v1.toml", robot_with_effects(robot, arm, dg.final_effects))
    robot1 = read_robot(out / "robot_v1.toml")
    effects1 = list(robot1.effects)
    after = compare_static(emodel(robot1, method="surface"), data, effects1)
    write_report(out / "measurements_v1", after)
    accepted = [st.explanation for st in dg.steps if st.accepted]
    report.figures.update({
        "measurements_chi2_red_nominal": before.chi2_red,
        "measurements_chi2_red_fitted_baseline": dg.steps[0].chi2_red,
        "measurements_chi2_red_final": after.chi2_red,
        "measurements_rms_nominal_um": before.rms * 1e6,
        "measurements_rms_final_um": after.rms * 1e6,
    })
    lo, hi = after.band
    rows = [f"| {st.label} | {st.chi2_red:.3f} | {st.rms_fit * 1e6:.1f} "
            f"| {st.rms_heldout * 1e6:.1f} |"
            for st in dg.steps]
    report.lines += [
        "## Measurements: where the model fails and which effect is missing",
        "",
        "Lab data shipped with flexarm (a virtual laser-tracker campaign, 15 µm noise, "
        "3 poses × 6 load directions × 0–800 N) on an arm whose joint stiffnesses are ±30% off "
        "the nominal file and which has one hidden physical effect. The diagnosis never sees "
        "the truth file.",
        "",
        f"- Nominal model: χ²_red {before.chi2_red:.2f}, RMS {before.rms * 1e6:.1f} µm "
        "([errors and plots](measurements_v0/))",
        *[f"- **Accepted**: {a}" for a in accepted],
        f"- Updated robot file [robot_v1.toml](robot_v1.toml): χ²_red {after.chi2_red:.3f} "
        f"(band {lo:.3f}–{hi:.3f}), RMS {after.rms * 1e6:.1f} µm "
        "([errors and plots](measurements_v1/))",
        "",
        "| model version | χ²_red | RMS fitted [µm] | RMS held-out [µm] |",
        "|---|---|---|---|",
        *rows,
        "",
        "![error history](diagnosis/history.png)",
        "",
    ]


def _flexible_step(out: Path, report: DemoReport, progress: Progress) -> None:
    """Superelement links at P1-P3: build, model comparison, a small study, pictures, map."""
    from ..assembly import stiffness_map, tcp_compliance
    from ..assembly.analyses import natural_frequencies
    from ..assembly.build import BuildOptions, build_robot
    from ..assembly.flexible import flexible_arm
    from ..assembly.maps import plot_map, write_csv
    from ..robot.demo_arm import load_demo_robot
    from .arm_study import run_study
    from .compare_models import compare_models

    robot = load_demo_robot()
    opts = BuildOptions().resolved(robot)
    builds = build_robot(robot, opts, progress=lambda s: progress(f"build: {s}"))
    arm = flexible_arm(robot, opts, builds)
    _write_csv(out / "build.csv",
               ["link", "tets", "dofs", "reduced_dofs", "f1_fixed_Hz", "seconds"],
               [[b.name, b.n_tets, b.n_fe_dofs, b.n_reduced,
                 float(b.freq_hz[0]) if len(b.freq_hz) else float("nan"), float(b.seconds)]
                for b in builds])

    progress("arm: E-model, Guyan, CB and CB + coupled wrist at P1, P2, P3")
    compare_models(robot, ("P1", "P2", "P3"), full_fe=False, out_dir=out / "models")
    rows = []
    for name in ("P1", "P2", "P3"):
        q = robot.pose(name)
        C = tcp_compliance(arm, q)[:3, :3]
        f1 = float(natural_frequencies(arm, q)[0])
        defl = 800.0 * np.diag(C) * 1e3
        weakest = "xyz"[int(np.argmax(np.diag(C)))]
        report.figures[f"flexible_{name}_f1_Hz"] = f1
        report.figures[f"flexible_{name}_defl_800N_y_mm"] = float(defl[1])
        rows.append(f"| {name} | {f1:.2f} | " + " / ".join(f"{d:.2f}" for d in defl)
                    + f" | {weakest.upper()} |")

    progress("arm: accuracy study at P1 against the full-FE reference (cached after the first run)")
    study = run_study(robot, "P1", sizes=(robot.options.mesh_size,), modes=(0, 5, 10),
                      couplings=("rbe2", "rbe3"), out_dir=out / "study",
                      progress=lambda s: progress(f"study: {s}"))

    progress("arm: flexible stiffness map over (q2, q3) and mode pictures")
    lo, hi = robot.lower, robot.upper
    m = stiffness_map(arm, robot.pose("P1"), np.linspace(lo[1], hi[1], 30),
                      np.linspace(lo[2], hi[2], 30))
    write_csv(out / "flexible_map.csv", m)
    pngs = plot_map(m, out / "flexible_map", surfaces=False)
    share_y = float(np.mean(m.least_stiff == 1))
    report.figures["flexible_map_y_weakest_share"] = share_y
    pictures = _arm_pictures(out, robot, arm, builds)

    report.lines += [
        "## The flexible arm (Craig-Bampton links joined by the same joint springs)",
        "",
        f"Links tetrahedralised at {opts.mesh_size * 1e3:g} mm, reduced by {opts.method.upper()}"
        f"({opts.n_modes}) with {opts.coupling.upper()} interfaces ([build.csv](build.csv)): "
        f"{sum(b.n_fe_dofs for b in builds)} FE DOF → {arm_dofs(arm)} arm coordinates.",
        "",
        "| pose | f1 [Hz] | TCP deflection at 800 N x / y / z [mm] | weakest |",
        "|---|---|---|---|",
        *rows,
        "",
        "- Model comparison (first 10 frequencies, TCP compliance): "
        "[model_comparison.csv](models/model_comparison.csv) · "
        "![Bode](models/model_comparison_bode.png)",
        f"- Accuracy study at P1 vs the full-FE reference ({study.reference.n_dofs} DOF): "
        f"[arm_study.csv](study/arm_study.csv); {study.verdict.replace(chr(10), '; ')}",
        "  ![error vs DOF](study/arm_study_error_vs_dof.png) ![Pareto](study/arm_study_pareto.png)",
        f"- Flexible stiffness map: [flexible_map.csv](flexible_map.csv); Y is the least stiff "
        f"direction on {share_y * 100:.1f}% of the grid.",
        *[f"  - ![{p.stem}](flexible_map/{p.name})" for p in pngs],
        *pictures,
        "",
    ]


def arm_dofs(arm) -> int:
    """Independent coordinates of an assembled arm (joint DOFs + body DOFs)."""
    from ..assembly.system import system_matrices

    return int(system_matrices(arm, np.zeros(arm.chain.n_joints)).K.shape[-1])


def _arm_pictures(out: Path, robot, arm, builds) -> list[str]:
    try:
        from .render_arm import render_arm_mode

        q = robot.pose("P1")
        # 800 x 600: software GL renders each GIF frame in ~0.25 s instead of ~0.45 s
        render_arm_mode(robot, q, 1, out / "arm_P1_mode1.gif", arm=arm, builds=builds,
                        pose_name="P1", ellipsoid=True, n_frames=10, window_size=(800, 600))
        render_arm_mode(robot, q, 2, out / "arm_P1_mode2.png", arm=arm, builds=builds,
                        pose_name="P1")
        return ["- Mode shapes at P1 (links recovered to the full field, TCP compliance "
                "ellipsoid): ![mode 1](arm_P1_mode1.gif) ![mode 2](arm_P1_mode2.png)"]
    except Exception as exc:  # noqa: BLE001 - pictures are optional; say why they are missing
        return [f"- (no arm pictures: {exc})"]


#: Progress channel of a worker process (set by :func:`_init_worker`).
_worker_say: Progress | None = None


def _init_worker(queue) -> None:
    global _worker_say
    _worker_say = queue.put


def _steps_job(folder: str, names: tuple[str, ...]) -> list[tuple[list[str], dict[str, float]]]:
    """Demo steps ``names`` in a worker process: each step's index lines and figures.

    Progress lines go to the parent through the queue given to :func:`_init_worker`.
    """
    from threadpoolctl import threadpool_limits

    say = _worker_say or (lambda s: None)
    out = []
    # The parent keeps the other core busy; two BLAS pools of two threads would fight.
    with threadpool_limits(1):
        for name in names:
            report = DemoReport(Path(folder))
            _STEPS[name](Path(folder), report, say)
            out.append((report.lines, report.figures))
    return out


_STEPS = {"emodel": _emodel_step, "measurements": _measurement_step}


def run_demo(folder="flexarm-demo", progress: Progress | None = None, size: float = 0.03,
             part: bool = False, jobs: int = 2) -> DemoReport:
    """Run every demo step into ``folder`` and write its ``index.md``.

    Parameters
    ----------
    folder : path-like
        Output folder (created).
    progress : callable, optional
        Receives one line per step (from a helper thread while a worker runs).
    size : float
        Edge length of the part-level mesh [m].
    part : bool
        Also run the single-part pipeline (full FE modes of one cast link).
    jobs : int
        Processes to use: with 2 or more, the E-model and measurement steps (which need
        no superelements) run in a second process while the flexible-arm step runs
        here, and the off-screen render probe starts at once in the background.  ``1``
        runs everything in order in this process.  The index is the same either way.
    """
    progress = progress or (lambda s: log.info(s))
    out = Path(folder)
    out.mkdir(parents=True, exist_ok=True)
    report = DemoReport(out)
    t0 = time.perf_counter()
    if jobs > 1 and not _can_spawn():
        progress("demo: no process semaphores here (/dev/shm?), running the steps in order")
        jobs = 1
    if jobs <= 1:
        if part:
            _part_step(out, report, progress, size)
        _emodel_step(out, report, progress)
        _flexible_step(out, report, progress)
        _measurement_step(out, report, progress)
    else:
        _run_parallel(out, report, progress, size, part)
    report.seconds = time.perf_counter() - t0
    head = ["# flexarm demo", "", f"Run time {report.seconds:.1f} s.", ""]
    with atomic_path(out / "index.md") as tmp:
        tmp.write_text("\n".join(head + report.lines) + "\n")
    return report


def _can_spawn() -> bool:
    """True when this platform gives multiprocessing its locks (some containers have
    no /dev/shm, and every queue needs a semaphore)."""
    import multiprocessing

    try:
        multiprocessing.get_context("spawn").SimpleQueue()
    except (OSError, ImportError):
        return False
    return True


def _run_parallel(out: Path, report: DemoReport, progress: Progress, size: float,
                  part: bool) -> None:
    """Flexible arm here; E-model and measurements in a spawned worker (same index)."""
    import multiprocessing
    import threading
    from concurrent.futures import ProcessPoolExecutor

    from ..assembly.emodel import total_mass
    from ..reduction.render import prefetch_render_backend
    from ..robot.demo_arm import load_demo_robot

    prefetch_render_backend()
    # Mesh every link here first (reads the caches when warm): the worker's E-model mass
    # properties and this process's superelements must come from the same tetrahedra,
    # and pytetwild gives a different mesh each time it runs.
    robot = load_demo_robot()
    progress("arm: tetrahedral meshes of the links (cached after the first run)")
    total_mass(robot, "tets", robot.options.mesh_size)
    # spawn, not fork: this process may already hold MKL/OpenMP threads.
    ctx = multiprocessing.get_context("spawn")
    queue = ctx.SimpleQueue()

    def relay():
        while (line := queue.get()) is not None:
            progress(line)

    relay_thread = threading.Thread(target=relay, name="flexarm-demo-progress", daemon=True)
    relay_thread.start()
    try:
        with ProcessPoolExecutor(1, mp_context=ctx, initializer=_init_worker,
                                 initargs=(queue,)) as pool:
            future = pool.submit(_steps_job, str(out), ("emodel", "measurements"))
            first, flexible = DemoReport(out), DemoReport(out)
            if part:
                _part_step(out, first, progress, size)
            _flexible_step(out, flexible, progress)
            (em_lines, em_figs), (ms_lines, ms_figs) = future.result()
    finally:
        queue.put(None)
        relay_thread.join()
    report.lines += first.lines + em_lines + flexible.lines + ms_lines
    report.figures.update({**first.figures, **em_figs, **flexible.figures, **ms_figs})
