"""Measurements: ``lab`` (virtual lab), ``compare``, ``diagnose``."""

from __future__ import annotations

import argparse

from ..fe.text import text_table
from ._common import Progress, add_robot_args, arm_from, command, out


def _validation_arm(args):
    """Robot (with its optional [nonlinear] table) and its E-model."""
    arm = arm_from(args, model="emodel")
    return arm.robot, arm.model, list(arm.robot.effects)


def _add_validation_common(p: argparse.ArgumentParser) -> None:
    add_robot_args(p, ("emodel",), pose=False, flexible=False)
    p.add_argument("--flexible", action="store_true", help="build the flexible model (link "
                   "flexibility); the E-model then takes its masses from the same tet meshes")
    p.add_argument("--flex-mesh", type=float, default=0.06,
                   help="tet size [m] of that coarse flexible model (default 0.06, cached)")
    p.add_argument("--flex-modes", type=int, default=4,
                   help="Craig-Bampton modes per link of that flexible model (default 4)")


def _flexible_models(args, robot, arm):
    """(E-model, flexible model) when --flexible, else (arm, None)."""
    if not args.flexible:
        return arm, None
    from ..assembly.build import BuildOptions
    from ..assembly.emodel import emodel
    from ..assembly.flexible import flexible_arm

    with Progress(f"flexible model (mesh {args.flex_mesh} m, cached after the first run)"):
        fa = flexible_arm(robot, BuildOptions(mesh_size=args.flex_mesh, n_modes=args.flex_modes))
    return emodel(robot, method="tets", mesh_size=args.flex_mesh), fa


def _with_links(effects, flexible) -> list:
    """Effects plus the flexible model's links (``links:c=1``) when one was built."""
    from ..robot.effects import Effect

    if flexible is None or any(e.kind == "links" for e in effects):
        return list(effects)
    return list(effects) + [Effect("links", None, (("compliance", 1.0),))]


def _parse_noise(text: str, quantity: str = "length") -> float:
    """'15um' -> 1.5e-5 (SI); a bare number is SI."""
    from ..validation.units import si_factor

    m = __import__("re").fullmatch(r"([0-9.eE+-]+)\s*([a-z]*)", text.strip())
    if not m:
        raise ValueError(f"noise '{text}': expected a number with a unit like 15um")
    return float(m.group(1)) * (float(si_factor(quantity, m.group(2))) if m.group(2) else 1.0)


def _add_lab(p: argparse.ArgumentParser) -> None:
    _add_validation_common(p)
    p.add_argument("--effect", action="append", default=[],
                   help="hidden effect, e.g. backlash:j2=0.1mrad (repeatable)")
    p.add_argument("--noise", default="15um", help="tracker noise, e.g. 15um")
    p.add_argument("--poses", default="P1,P2,P3", help="named poses")
    p.add_argument("--loads", default="0:800:100", help="load levels [N] start:stop:step")
    p.add_argument("--dirs", default="x,y,z", help="load directions, e.g. x,y,z,-z")
    p.add_argument("--cycles", action="store_true", help="load then unload each series")
    p.add_argument("--seed", type=int, default=0)
    p.add_argument("--ref-noise", default="0um", help="extra error of each series' reference "
                   "reading, e.g. 45um (tracker re-lock; stated in the sigma column)")
    p.add_argument("--modal", default=None, help="also write natural frequencies to this CSV")
    p.add_argument("--n-modes", type=int, default=4, help="modes per pose in --modal")
    p.add_argument("--freq-noise", type=float, default=0.5, help="frequency noise [%%]")
    p.add_argument("-o", "--output", required=True, help="static CSV to write")


@command("lab", "virtual lab: static series from the model + hidden effects + tracker noise",
         _add_lab)
def _run_lab(args) -> int:
    from ..robot.effects import parse_effect
    from ..validation import write_modal
    from ..validation.lab import LabPlan, parse_dirs, parse_loads, virtual_lab, write_lab
    from ..validation.modal import virtual_modal

    robot, arm, base_effects = _validation_arm(args)
    noise = _parse_noise(args.noise)
    effects = list(base_effects) + [parse_effect(s, len(robot.joints)) for s in args.effect]
    args.flexible = args.flexible or any(e.kind == "links" for e in effects)
    arm, flexible = _flexible_models(args, robot, arm)
    plan = LabPlan({p: robot.pose(p) for p in args.poses.split(",")}, parse_loads(args.loads),
                   parse_dirs(args.dirs), args.cycles)
    ref_noise = _parse_noise(args.ref_noise)
    data = virtual_lab(arm, plan, effects, noise, args.seed, flexible, ref_noise)
    truth = {"effects": [e.to_dict() for e in effects], "noise_m": noise, "seed": args.seed,
             "robot": args.robot or "demo", "ref_noise_m": ref_noise}
    if flexible is not None:
        truth["flexible_mesh_m"] = args.flex_mesh
    if args.modal:
        modal = virtual_modal(arm, plan.poses, effects, args.n_modes, args.freq_noise / 100,
                              args.seed, flexible)
        truth["freq_noise"] = args.freq_noise / 100
        out(f"wrote {write_modal(args.modal, modal, ('virtual lab data (flexarm lab)',))} "
               f"({len(modal.freq_hz)} frequencies)")
    path, tpath = write_lab(args.output, data, truth)
    out(f"wrote {path} ({len(data.series)} readings, {data.n_series} series) and {tpath}")
    return 0


def _add_compare(p: argparse.ArgumentParser) -> None:
    p.add_argument("data", help="measurement CSV: static, modal or frf (recognised by columns)")
    _add_validation_common(p)
    p.add_argument("--noise", type=float, default=15.0, help="tracker noise [um] (no sigma column)")
    p.add_argument("--freq-noise", type=float, default=0.5, help="frequency noise [%%] (modal)")
    p.add_argument("-o", "--output", default=None, help="report folder (CSV, PNG)")


def _compare_dynamic(args, data) -> int:
    """`compare` on modal or FRF data: error table, chi2_red (modal), plots."""
    from ..validation import ModalData
    from ..validation import compare_dynamic as cd

    robot, arm, effects = _validation_arm(args)
    arm, flexible = _flexible_models(args, robot, arm)
    effects = _with_links(effects, flexible)
    if isinstance(data, ModalData):
        cmp = cd.compare_modal(arm, data, effects, args.freq_noise / 100, flexible)
        out(text_table(["pose", "mode", "measured_Hz", "model_Hz", "error_Hz", "error_%"],
                      [[r.pose, r.mode, r.measured_hz, r.model_hz, r.error_hz,
                        r.error_pct] for r in cmp.table], "{:.3f}"))
        out(f"chi2_red = {cmp.chi2_red:.3f} (band {cmp.band[0]:.3f}-{cmp.band[1]:.3f} for "
               f"{args.freq_noise}% frequency noise), RMS error {cmp.rms_pct:.2f}%")
        write = cd.write_modal_report
    else:
        cmp = cd.compare_frf(arm, data, effects, flexible)
        out(text_table(["pose", "in", "out", "rms_log10|H|", "peak_meas_Hz", "peak_model_Hz",
                       "peak_err_%"], [[r.pose, r.input, r.output, r.rms_log10_mag,
                                        r.peak_meas_hz, r.peak_model_hz,
                                        r.peak_error_pct] for r in cmp.table], "{:.3f}"))
        write = cd.write_frf_report
    if args.output:
        for p in write(args.output, cmp):
            out(f"wrote {p}")
    return 0


@command("compare", "model predictions vs static measurements: errors, chi2_red, plots",
         _add_compare)
def _run_compare(args) -> int:
    from ..validation import FrfData, ModalData, read_measurements
    from ..validation.compare import compare_static, write_report

    data = read_measurements(args.data)
    if isinstance(data, (ModalData, FrfData)):
        return _compare_dynamic(args, data)
    robot, arm, effects = _validation_arm(args)
    arm, flexible = _flexible_models(args, robot, arm)
    effects = _with_links(effects, flexible)
    cmp = compare_static(arm, data, effects, args.noise * 1e-6, flexible)
    out(text_table(["series", "mean_abs_mm", "max_abs_mm", "relative", "max_meas_mm"],
                  [[r.series, r.mean_abs_mm, r.max_abs_mm, r.relative,
                    r.max_meas_mm] for r in cmp.table], "{:.4f}"))
    lo, hi = cmp.band
    out(f"chi2_red = {cmp.chi2_red:.3f} (band {lo:.3f}-{hi:.3f} for the stated noise), "
           f"RMS = {cmp.rms * 1e6:.1f} um")
    if args.output:
        for p in write_report(args.output, cmp):
            out(f"wrote {p}")
    return 0


def _add_diagnose(p: argparse.ArgumentParser) -> None:
    p.add_argument("data", help="static measurement CSV")
    _add_validation_common(p)
    p.add_argument("--noise", type=float, default=15.0, help="tracker noise [um] (no sigma column)")
    p.add_argument("--apply", action="store_true", help="write a robot TOML with the accepted "
                   "effects and fitted parameters (-o)")
    p.add_argument("-o", "--output", default=None, help="robot TOML for --apply")
    p.add_argument("--report", default=None, help="folder for the history CSV/JSON/PNG")
    p.add_argument("--noise-model", default="shared", choices=["shared", "independent"],
                   help="shared reference reading (GLS, default) or independent rows (only "
                   "to show the shared-reference trap)")
    p.add_argument("--modal", default=None, help="measured natural frequencies CSV (joins the "
                   "fits; implies --flexible)")
    p.add_argument("--freq-noise", type=float, default=0.5, help="frequency noise [%%]")


@command("diagnose", "find which physical effect the model misses in static measurements",
         _add_diagnose)
def _run_diagnose(args) -> int:
    from ..robot.formats import write as write_robot
    from ..validation import read_measurements
    from ..validation.diagnose import diagnose
    from ..validation.history import robot_with_effects, write_history

    if args.apply and not args.output:
        raise ValueError("--apply needs -o NEW_ROBOT.toml")
    robot, arm, effects = _validation_arm(args)
    if effects:
        raise ValueError("diagnose starts from a linear model: the robot file already has "
                         "a [nonlinear] table")
    data = read_measurements(args.data)
    modal = None if args.modal is None else read_measurements(args.modal)
    args.flexible = args.flexible or modal is not None
    arm, flexible = _flexible_models(args, robot, arm)
    dg = diagnose(arm, data, args.noise * 1e-6, args.noise_model, poses=robot.poses, modal=modal,
                  flexible=flexible, freq_noise=args.freq_noise / 100)
    ident = dg.identifiability
    out(f"identifiability: condition {ident.condition:.3g}, singular "
           f"values {', '.join(f'{v:.3g}' for v in ident.singular_values)}")
    for j, s in ident.sign_changes.items():
        out(f"  {j} torque changes sign in: {', '.join(s) if s else 'no series'}")
    for k, v in ident.leave_one_pose_out.items():
        out(f"  leave-one-pose-out chi2_red on {k}: {v:.3f}")
    for i, st in enumerate(dg.steps):
        out(f"\nv{i} {st.label}: chi2_red {st.chi2_red:.3f} (band {st.band[0]:.3f}-"
               f"{st.band[1]:.3f}), RMS fitted {st.rms_fit * 1e6:.1f} um, held-out "
               f"{st.rms_heldout * 1e6:.1f} um")
        if st.candidates:
            out(text_table(["candidate", "status", "dBIC", "unique", "norm", "detail"],
                          [[c.label, c.status, f"{c.dbic:.1f}", f"{c.unique:.2f}",
                            f"{c.norm:.1f}", c.detail] for c in st.candidates]))
        if st.winner is not None:
            out(("ACCEPTED: " if st.accepted else "best, not accepted: ") + st.explanation)
    for n in dg.notes:
        out(f"note: {n}")
    if args.report:
        for p in write_history(args.report, dg):
            out(f"wrote {p}")
    if args.apply:
        write_robot(args.output, robot_with_effects(robot, arm, dg.final_effects))
        out(f"wrote {args.output}")
    return 0
