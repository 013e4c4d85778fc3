"""Whole-arm accuracy study: mesh size x CB modes x interface representation.

Every *variant* (tet edge ``h``, Craig-Bampton modes per link ``n`` with ``0`` =
Guyan, interface representation) is built, assembled at one pose and compared with
the **full-FE reference**: the unreduced links at the finest mesh, joined through
the same joints, base and tool (:func:`~flexarm.assembly.full_fe.full_fe_analysis`,
RBE2 seats by default).  Per variant the study records

* the largest and the mean relative error of the first ``n_freq`` arm frequencies;
* the largest and the mean relative error of the TCP compliance diagonal (6 terms,
  base frame);
* the reduced system DOF and the FE DOF of the links;
* the build time (reduction of all links, as first measured: a cached build reports
  the seconds recorded with its superelement), the solve time (assembly at the pose,
  eigenvalues, compliance) and, per mesh size, the time to mesh (or load from the
  mesh cache) all links -- shared by every variant of that size, so it is listed but
  not charged to the variants.

Interface representations: ``rbe2``/``rbe3`` (one 6-DOF node per seat, the cached
builds of :func:`~flexarm.assembly.build.build_robot`) and ``k<N>`` (``N`` seat nodes
kept as 3-DOF masters, then tied rigidly to the seat centre in the reduced space: a
bolt-like connection through ``N`` points, ``BuildOptions(masters=N)``).

Outputs: ``arm_study.csv``, ``arm_study_error_vs_dof.png`` (log-log),
``arm_study_pareto.png`` (error vs time) and ``arm_study_verdict.txt``.
"""

from __future__ import annotations

import csv
import dataclasses
import logging
import time
from collections.abc import Callable, Sequence
from dataclasses import asdict
from pathlib import Path

import numpy as np

from ..assembly.analyses import natural_frequencies, tcp_compliance
from ..assembly.build import BuildOptions, LinkBuild, Mesher, build_robot, link_mesh, link_mesh_id
from ..assembly.flexible import flexible_arm
from ..fe.cache import cache_key, cached
from ..fe.files import atomic_folder, atomic_path
from ..fe.text import eta_text
from ..fe.typing import FloatArray
from ..robot.description import Robot
from .arm_study_plots import plot_error_vs_dof, plot_pareto
from .arm_study_results import DiscretisationEstimate, Reference, StudyResult, StudyRow

__all__ = ["PRESETS", "StudyRow", "Reference", "StudyResult", "parse_representation",
           "reference_result", "run_variant", "run_study", "verdict", "write_study",
           "discretisation_estimate", "discretisation_text",
           "plot_error_vs_dof", "plot_pareto"]

log = logging.getLogger(__name__)

#: Version of the reference cache layout.
STUDY_VERSION = 2

#: Named sweeps. ``sizes=None``: 1.5 x and 1 x the robot's mesh size.
PRESETS = {
    "small": {"sizes": None, "modes": (0, 5, 10), "couplings": ("rbe2", "rbe3")},
    "full": {"sizes": None, "modes": (0, 5, 10, 20), "couplings": ("rbe2", "rbe3", "k4", "k8")},
}


def parse_representation(text: str) -> tuple[str, int | None]:
    """``"rbe2"`` -> ``("rbe2", None)``, ``"k8"`` -> ``("nodes", 8)``.

    >>> parse_representation("k4")
    ('nodes', 4)
    """
    t = text.strip().lower()
    if t in ("rbe2", "rbe3"):
        return t, None
    if t.startswith("k") and t[1:].isdigit() and int(t[1:]) >= 3:
        return "nodes", int(t[1:])
    raise ValueError(f"interface representation must be rbe2, rbe3 or k<N> (N >= 3), "
                     f"got '{text}'")


def reference_result(robot: Robot, q, mesh_size: float, coupling: str = "rbe2",
                     n_freq: int = 10, mesher: Mesher | None = None, cache: bool = True,
                     progress: Callable[[str], None] | None = None) -> Reference:
    """Full-FE frequencies and TCP compliance diagonal at pose ``q`` (n,) [rad].

    The links are unreduced (:func:`~flexarm.assembly.full_fe.full_fe_bodies`); the
    joints, base support, tool and wrist come from :func:`flexible_arm`, so they are
    those of every variant.  Cached (JSON, ``study-reference``) by the robot,
    its meshes, the pose and the options; ``seconds`` is the time of the first run.
    """
    from ..assembly.full_fe import full_fe_analysis, full_fe_bodies

    say = progress or (lambda message: None)
    opts = BuildOptions("cb", 0, coupling, mesh_size).resolved(robot)
    q = np.asarray(q, dtype=float)
    meshes = [None if lk.mesh is None and mesher is None else
              link_mesh_id(lk, mesher or robot.options.mesher, opts.mesh_size, opts.order)
              for lk in robot.links]
    key = cache_key("study-reference", STUDY_VERSION, robot.full_repr(), q, opts.mesh_size,
                    opts.order, opts.tcp, coupling, n_freq, meshes)

    def compute() -> dict:
        say(f"full-FE reference at {mesh_size * 1e3:.0f} mm ({coupling})")
        t0 = time.perf_counter()
        bodies = full_fe_bodies(robot, opts, mesher, say)
        # joints, base, tool and wrist exactly as the flexible variants; the full FE takes
        # only these from the arm (its bodies are replaced), so the Guyan arm of the Tet4
        # links serves every element order: a Tet10 reference reuses the Tet4 one's builds
        # instead of reducing its Tet10 links for nothing
        linear = dataclasses.replace(robot, options=dataclasses.replace(robot.options,
                                                                        element_order=1))
        gy = BuildOptions("guyan", 0, coupling, mesh_size)
        arm = flexible_arm(linear, gy, build_robot(linear, gy, cache, mesher))
        res = full_fe_analysis(arm, bodies, q, n_freq)
        dt = time.perf_counter() - t0
        say(f"full-FE reference: {res.n_dofs} DOF in {dt:.1f} s")
        return {"freq_hz": np.asarray(res.freq_hz).tolist(), "C_diag": np.diag(res.C).tolist(),
                "n_dofs": res.n_dofs, "seconds": dt}

    entry = cached("study-reference", key, compute, enabled=cache)
    d = entry.value
    if entry.is_hit:
        say(f"full-FE reference from cache ({d['n_dofs']} DOF)")
    return Reference(np.array(d["freq_hz"]), np.array(d["C_diag"]), d["n_dofs"], mesh_size,
                     coupling, d["seconds"])


def _premesh(robot: Robot, size: float, order: int, mesher: Mesher | None) -> float:
    """Mesh every link at ``size`` (tet cache) so that builds time only the reduction [s]."""
    t0 = time.perf_counter()
    for lk in robot.links:
        if mesher is not None:
            mesher(lk, size, order)
        elif lk.mesh is not None:
            link_mesh(lk, size, order, mesher=robot.options.mesher)
    return time.perf_counter() - t0


def _build_seconds(builds: Sequence[LinkBuild]) -> float:
    """Meshing + reduction time [s] of the builds, as first measured (also when cached)."""
    return float(sum(lb.build_seconds for lb in builds))


def _p_refinement(robot: Robot, q, ref: Reference, coupling: str, n_freq: int,
                  mesher: Mesher | None, cache: bool, say) -> tuple:
    """Per mode, the Tet4 reference's frequency over the Tet10 one on the same mesh, - 1."""
    say(f"full FE with Tet10 elements at {ref.mesh_size * 1e3:.0f} mm (mesh error)")
    higher = dataclasses.replace(robot, options=dataclasses.replace(robot.options,
                                                                    element_order=2))
    ref10 = reference_result(higher, q, ref.mesh_size, coupling, n_freq, mesher, cache, say)
    return tuple(_relative_signed(ref.freq_hz, ref10.freq_hz))


def _relative_signed(a: FloatArray, b: FloatArray) -> FloatArray:
    """``a / b - 1`` over the common length."""
    n = min(len(a), len(b))
    return np.asarray(a[:n]) / np.asarray(b[:n]) - 1.0


def _relative(a: FloatArray, b: FloatArray) -> FloatArray:
    n = min(len(a), len(b))
    return np.abs(np.asarray(a[:n]) / np.asarray(b[:n]) - 1.0)


def run_variant(robot: Robot, q, ref: Reference, mesh_size: float, coupling: str,
                n_modes: int, mesher: Mesher | None = None, cache: bool = True,
                progress: Callable[[str], None] | None = None,
                mesh_seconds: float = 0.0) -> StudyRow:
    """Build, assemble and solve one variant and compare it with ``ref``.

    ``coupling`` is ``"rbe2"``, ``"rbe3"`` or ``"k<N>"``; ``n_modes = 0`` is Guyan;
    ``mesh_seconds`` is only recorded.
    """
    kind, k = parse_representation(coupling)
    method = "guyan" if n_modes == 0 else "cb"
    opts = BuildOptions(method, int(n_modes), kind if k is None else "rbe2", mesh_size,
                        masters=k)
    builds = build_robot(robot, opts, cache, mesher, progress)
    t0 = time.perf_counter()
    arm = flexible_arm(robot, opts, builds)
    f = natural_frequencies(arm, q)[: len(ref.freq_hz)]
    C = np.diag(tcp_compliance(arm, q))
    dt = time.perf_counter() - t0
    ef = _relative(f, ref.freq_hz)
    ec = _relative(C, ref.C_diag)
    label = "Guyan" if n_modes == 0 else f"CB({n_modes})"
    return StudyRow(float(mesh_size), coupling, int(n_modes), label, int(arm.layout["n"]),
                    int(sum(lb.n_fe_dofs for lb in builds)), float(ef.max()), float(ef.mean()),
                    float(ec.max()), float(ec.mean()), _build_seconds(builds), dt,
                    float(mesh_seconds), tuple(float(v) for v in f), tuple(float(v) for v in C))


def verdict(rows: Sequence[StudyRow], levels=(0.01, 0.001),
            reference_coupling: str | None = None) -> str:
    """Cheapest variant whose worst error is within each level (fractions).

    Cheapest = fewest reduced DOF (the cost of every pose), then least build + solve
    time (measured times are noisy on a shared machine; the DOF count is not).  With
    ``reference_coupling``, an interface representation that stays outside the loosest
    level for every mesh and mode count is named as a different model of the seats,
    not a coarser one (more modes will not close that gap).
    """
    lines = []
    for lev in levels:
        ok = sorted((r for r in rows if r.error <= lev), key=lambda r: (r.n_reduced, r.seconds))
        if ok:
            r = ok[0]
            lines.append(f"within {100 * lev:g}%: {r.label} {r.coupling} at "
                         f"{r.mesh_size * 1e3:.0f} mm ({r.n_reduced} DOF, f err "
                         f"{100 * r.freq_err_max:.3g}%, C err {100 * r.C_err_max:.3g}%, "
                         f"{r.seconds:.2f} s)")
        else:
            lines.append(f"within {100 * lev:g}%: none")
    if reference_coupling is not None:
        for c in dict.fromkeys(r.coupling for r in rows):
            best = min(r.error for r in rows if r.coupling == c)
            if c != reference_coupling and best > max(levels):
                lines.append(f"{c}: at best {100 * best:.3g}% from the {reference_coupling} "
                             f"reference, whatever the modes: it models the joint seats "
                             f"differently (compare with reference_coupling='{c}')")
    return "\n".join(lines)


def discretisation_estimate(rows: Sequence[StudyRow], reference_coupling: str,
                            order: int = 1, p_refined: Sequence[float] = (),
                            h_fine: float | None = None) -> DiscretisationEstimate | None:
    """The mesh error of the finest size (None when there is nothing to estimate it from).

    Richardson from the two finest sizes: the variant with the reference coupling and
    the most modes stands in for the full model at each size (its reduction error is far
    smaller), and their FE DOF counts give the effective edge ratio.  ``p_refined`` are
    the finest full FE's frequencies over those with one element order more, minus 1
    (:class:`~flexarm.studies.arm_study_results.DiscretisationEstimate`).

    Examples
    --------
    >>> from flexarm.studies.arm_study_results import StudyRow
    >>> row = lambda h, n, f: StudyRow(h, "rbe2", 10, "CB(10)", 90, n, 0, 0, 0, 0, 0, 0,
    ...                                freq_hz=(f,))
    >>> discretisation_estimate([row(0.06, 1000, 10.3), row(0.03, 8000, 10.0)], "rbe2").text()
    'discretisation error at 30 mm (Tet4): Richardson from 60 and 30 mm (effective edge ratio \
2.00, CB(10) rbe2) gives about 1%; the reduction errors above are against the full FE (Tet4) \
at 30 mm'
    """
    ref = [r for r in rows if r.coupling == reference_coupling and len(r.freq_hz)]
    sizes = sorted({r.mesh_size for r in ref})
    pref = tuple(float(v) for v in p_refined)
    if len(sizes) < 2:
        if not pref:
            return None
        return DiscretisationEstimate(h_fine if h_fine else sizes[0], order, p_refined=pref)
    h2, h1 = sizes[0], sizes[1]
    n = max(r.n_modes for r in ref)
    fine, coarse = (next(r for r in ref if r.mesh_size == h and r.n_modes == n)
                    for h in (h2, h1))
    k = min(len(fine.freq_hz), len(coarse.freq_hz))
    f2, f1 = np.asarray(fine.freq_hz[:k]), np.asarray(coarse.freq_hz[:k])
    ratio = (fine.n_fe_dofs / coarse.n_fe_dofs) ** (1 / 3) if coarse.n_fe_dofs else None
    return DiscretisationEstimate(h2, order, fine.label, reference_coupling,
                                  float(np.max(np.abs(f1 - f2) / f2)), ratio, h1, pref)


def discretisation_text(estimate: DiscretisationEstimate | None) -> str:
    """The verdict's line on the mesh error (what to do when it is not estimated)."""
    if estimate is None:
        return ("discretisation error: not estimated (one mesh size; the errors above are "
                "against the full FE model at that size, give two sizes or tet10=True to "
                "estimate it)")
    return estimate.text()


def run_study(robot: Robot, pose: str = "P1", sizes: Sequence[float] | None = None,
              modes: Sequence[int] | None = None, couplings: Sequence[str] | None = None,
              out_dir=None, progress: Callable[[str], None] | None = None, n_freq: int = 10,
              reference_coupling: str = "rbe2", mesher: Mesher | None = None,
              cache: bool = True, preset: str = "full", tet10: bool = False) -> StudyResult:
    """Sweep the variants against the full-FE reference at the finest size.

    Parameters
    ----------
    robot : Robot
    pose : str
        Pose name (``"P1"``) or ``"q1,...,qn"`` in degrees.
    sizes : sequence of float, optional
        Tet edge lengths [m]; default 1.5 x and 1 x the robot's ``mesh_size``.
    modes : sequence of int, optional
        CB modes per link (0 = Guyan); default: the preset's.
    couplings : sequence of str, optional
        ``rbe2``, ``rbe3``, ``k<N>``; default: the preset's.
    out_dir : path, optional
        Where CSV, PNGs and the verdict go (:func:`write_study`).
    progress : callable (str) -> None, optional
        One line per variant (and per built link).
    reference_coupling : {"rbe2", "rbe3"}
        Seat coupling of the full-FE reference.
    mesher : callable, optional
        As for :func:`~flexarm.assembly.build.build_robot` (tests).
    preset : {"small", "full"}
        Named sweep (:data:`PRESETS`) that fills in what is not given.
    tet10 : bool
        Also solve the full FE with one element order more (Tet10 for a Tet4 robot) on
        the finest mesh: a lower bound of the mesh error that needs no second size
        (:func:`discretisation_estimate`).  Costs about six times the reference's DOF.
    """
    from ..robot.description import pose_from_string

    if preset not in PRESETS:
        raise ValueError(f"preset must be one of {', '.join(PRESETS)}, got '{preset}'")
    modes = PRESETS[preset]["modes"] if modes is None else modes
    couplings = PRESETS[preset]["couplings"] if couplings is None else couplings
    sizes = PRESETS[preset]["sizes"] if sizes is None else sizes
    say = progress or (lambda message: None)
    q = pose_from_string(robot, pose)
    if sizes is None:
        h = robot.options.mesh_size
        sizes = (1.5 * h, h)
    sizes = sorted({float(s) for s in sizes}, reverse=True)
    for c in couplings:
        parse_representation(c)  # fail before any heavy work
    if tet10 and robot.options.element_order != 1:
        raise ValueError("tet10=True needs a Tet4 robot (element_order = 1)")
    ref = reference_result(robot, q, sizes[-1], reference_coupling, n_freq, mesher, cache, say)
    quiet = None if progress is None else (lambda m: log.info(m))
    rows = []
    n_var = len(sizes) * len(modes) * len(couplings)
    order = robot.options.element_order
    t0 = time.perf_counter()
    for h in sizes:
        say(f"meshing all links at {h * 1e3:.0f} mm (cached)")
        t_mesh = _premesh(robot, h, order, mesher)
        for c in couplings:
            for n in modes:
                r = run_variant(robot, q, ref, h, c, int(n), mesher, cache, quiet, t_mesh)
                rows.append(r)
                say(f"[{len(rows)}/{n_var}] {h * 1e3:.0f} mm {c} {r.label}: {r.n_reduced} DOF, "
                    f"f err {100 * r.freq_err_max:.3g}%, C err {100 * r.C_err_max:.3g}% "
                    f"(build {r.build_seconds:.1f} s, solve {r.solve_seconds * 1e3:.1f} ms)"
                    + eta_text(time.perf_counter() - t0, len(rows), n_var))
    p_refined = (_p_refinement(robot, q, ref, reference_coupling, n_freq, mesher, cache, say)
                 if tet10 else ())
    mesh_error = discretisation_estimate(rows, reference_coupling, order, p_refined,
                                         sizes[-1])
    text = (verdict(rows, reference_coupling=reference_coupling) + "\n"
            + discretisation_text(mesh_error))
    result = StudyResult(tuple(rows), ref, pose, text, discretisation=mesh_error)
    if out_dir is not None:
        result = dataclasses.replace(result, files=write_study(result, out_dir))
    return result


def write_study(result: StudyResult, out_dir) -> tuple[Path, ...]:
    """Write ``arm_study.csv``, the two PNGs and ``arm_study_verdict.txt`` to ``out_dir``,
    with ``arm_study_mesh_error.csv`` (per-mode Tet4 / Tet10 frequencies) after a Tet10
    check (all or none: they are written aside and moved in together)."""
    final = Path(out_dir)
    with atomic_folder(final) as out:
        files = _write_study(result, out)
    return tuple(final / f.name for f in files)


def _write_study(result: StudyResult, out: Path) -> tuple[Path, ...]:
    path = out / "arm_study.csv"
    with atomic_path(path) as tmp, open(tmp, "w", newline="") as fh:
        keys = [k for k in StudyRow.__dataclass_fields__ if k not in ("freq_hz", "C_diag")]
        n_f = len(result.reference.freq_hz)
        head = keys + [f"f{i + 1}_Hz" for i in range(n_f)] + [f"C{i + 1}{i + 1}" for i in range(6)]
        w = csv.writer(fh)
        w.writerow(head)
        ref = result.reference
        w.writerow([ref.mesh_size, ref.coupling, -1, "full-FE", ref.n_dofs, ref.n_dofs, 0, 0, 0,
                    0, 0, ref.seconds, 0, *ref.freq_hz, *ref.C_diag])
        for r in result.rows:
            d = asdict(r)
            fs = list(r.freq_hz) + [""] * (n_f - len(r.freq_hz))
            w.writerow([d[k] for k in keys] + fs + list(r.C_diag))
    txt = out / "arm_study_verdict.txt"
    with atomic_path(txt) as tmp:
        tmp.write_text(f"pose {result.pose}; reference: full FE {ref.n_dofs} DOF at "
                       f"{ref.mesh_size * 1e3:.0f} mm ({ref.coupling}), "
                       f"{ref.seconds:.1f} s\n{result.verdict}\n")
    extra = ()
    est = result.discretisation
    if est is not None and est.p_refined:
        extra = (out / "arm_study_mesh_error.csv",)
        with atomic_path(extra[0]) as tmp, open(tmp, "w", newline="") as fh:
            w = csv.writer(fh)
            w.writerow(["mode", "f_Hz", "f_higher_order_Hz", "rel_change"])
            for i, (f, d) in enumerate(zip(ref.freq_hz, est.p_refined, strict=False), start=1):
                w.writerow([i, f, f / (1 + d), d])
    return (path, plot_error_vs_dof(out / "arm_study_error_vs_dof.png", result),
            plot_pareto(out / "arm_study_pareto.png", result), txt, *extra)
