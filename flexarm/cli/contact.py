"""Contact applications: ``circle`` (loaded circle test), ``chatter``, ``chatter-map``."""

from __future__ import annotations

import argparse
import os

import numpy as np

from ._common import add_robot_args, arm_from, command, out, pose_from, robot_from


def _add_circle(p: argparse.ArgumentParser) -> None:
    p.add_argument("--robot", default=None,
                   help="robot TOML (with an optional [nonlinear] table) or URDF (default: demo)")
    p.add_argument("--model", default="emodel", choices=["emodel", "cb", "guyan"],
                   help="rigid links (E-model) or flexible links (Craig-Bampton, Guyan)")
    p.add_argument("--compare-models", action="store_true",
                   help="overlay the E-model and the flexible model (cb unless --model guyan)")
    p.add_argument("--mesh-size", type=float, default=None, help="flexible links: tet edge [m]")
    p.add_argument("--modes", type=int, default=None, help="CB modes per link (robot default)")
    p.add_argument("--effect", action="append", default=[],
                   help="extra joint effect, e.g. backlash:j3=0.2mrad (repeatable)")
    p.add_argument("--mass", default="surface", choices=["tets", "surface"],
                   help="E-model mass properties from CAD surfaces (default) or tet meshes")
    p.add_argument("-o", "--output", default=None, help="folder for PNG/CSV output")
    p.add_argument("--rapid", default=None, help="RAPID module (default: the thesis's appendix B)")
    p.add_argument("--proc", default="Path_30", help="procedure name")
    p.add_argument("--loads", default="0,200,400,800", help="bar forces [N], comma-separated")
    p.add_argument("--pull", action="store_true", help="the bar pulls (default: pushes)")
    p.add_argument("--pivot", default=None, help="bar pivot x,y,z [mm] (default: fitted)")
    p.add_argument("--tool", default="tool0", choices=["tool0", "robot"],
                   help="load point: flange (tool0, as programmed) or the robot's TCP")
    p.add_argument("--step", type=float, default=2.0, help="path sampling step [mm]")
    p.add_argument("--measured", default=None,
                   help="measured circle to overlay: path CSV or static-schema CSV")


def _circle_robot(args):
    """Robot and its effects: TOML [nonlinear] table plus ``--effect`` options."""
    from ..robot.effects import parse_effect

    robot = robot_from(args)
    effects = list(robot.effects)
    return robot, effects + [parse_effect(e, robot.chain.n_joints) for e in args.effect]


@command("circle", "loaded circle test (LDBB): deviation, polar plot, Z along the path",
         _add_circle)
def _run_circle(args) -> int:
    from importlib.resources import files

    from ..assembly.effects import apply_effects
    from ..robot.formats.rapid import read_rapid
    from ..studies.contact import measured_deviation, predict_circle, rapid_circle
    from ..studies.contact.circle_data import static_circle_readings, write_circle_csv
    from ..studies.contact.circle_models import circle_arm, nonlinear_solver
    from ..studies.contact.plots import plot_circle_polar, plot_circle_top, plot_circle_z

    robot, effects = _circle_robot(args)
    mod = read_rapid(args.rapid or files("flexarm") / "data" / "rapid" / "ldbb_thesis.mod")
    if args.proc not in mod.procedures:
        raise ValueError(f"no procedure {args.proc} (module has {sorted(mod.procedures)})")
    pivot = None if args.pivot is None else np.array(args.pivot.split(","), float) * 1e-3
    setup = rapid_circle(robot, mod, args.proc, pivot, args.tool, args.step)
    loads = np.array(args.loads.split(","), dtype=float)
    out(f"{args.proc}: {len(setup.points)} samples, load point {args.tool}, pivot "
           f"{np.round(setup.pivot * 1e3, 3).tolist()} mm, bar {setup.bar_length.mean() * 1e3:.3f}"
           f" mm, circle R {setup.radius * 1e3:.3f} mm; conf met at "
           f"{int(setup.ik.is_conf_met.sum())}/{len(setup.ik.is_conf_met)} targets")
    for note in setup.ik.notes:
        out(f"  note: {note}")
    names = [args.model]
    if args.compare_models:
        names = ["emodel", "guyan" if args.model == "guyan" else "cb"]
    ang = np.degrees(setup.angles)
    runs = []
    for name in names:
        arm = circle_arm(robot, name, args.mass, args.mesh_size, args.modes)
        arm, laws = apply_effects(arm, effects)
        pred = predict_circle(arm, setup, loads, args.pull, nonlinear_solver(laws))
        label = {"emodel": "E-model", "cb": "CB", "guyan": "Guyan"}[name]
        runs.append((label, pred))
        out(f"{label} ({pred.method}{', laws on joints ' if laws else ''}"
               f"{','.join(str(j + 1) for j in sorted(laws))}):")
        for F, b, z in zip(loads, pred.bar, pred.normal, strict=True):
            k = int(np.argmax(np.abs(b)))
            out(f"  {F:6.0f} N: max |bar| {np.abs(b).max() * 1e3:.4f} mm at {ang[k]:7.1f} deg,"
                   f" max |normal| {np.abs(z).max() * 1e3:.4f} mm")
    meas = None
    if args.measured:
        from ..validation import read_measurements

        data = read_measurements(args.measured)
        if hasattr(data, "points"):
            meas = measured_deviation(setup, data.points, data.force)
        elif hasattr(data, "disp"):
            meas = measured_deviation(setup, *static_circle_readings(setup, robot.chain, data))
        else:
            raise ValueError("--measured: give a path CSV (step, x_mm, y_mm, z_mm, f_N) or a "
                             "static CSV (series, step, q1_deg.., fx_N.., dx_mm..)")
        out(f"measured: {len(meas[0])} readings at {np.unique(meas[3]).tolist()} N, max |bar| "
               f"{np.abs(meas[1]).max() * 1e3:.4f} mm")
    if args.output:
        os.makedirs(args.output, exist_ok=True)
        csv = os.path.join(args.output, f"circle_{args.proc}.csv")
        write_circle_csv(csv, runs)
        out(f"wrote {csv}")
        (label, pred), rest = runs[0], runs[1:]
        kw = {"label": label if rest else "", "compare": rest}
        folder = args.output
        for path in (plot_circle_top(pred, os.path.join(folder, "circle_top.png"), **kw),
                     plot_circle_polar(pred, os.path.join(folder, "circle_polar.png"), meas, **kw),
                     plot_circle_z(pred, os.path.join(folder, "circle_z.png"), meas, **kw)):
            out(f"wrote {path}")
    return 0


def _add_chatter(p: argparse.ArgumentParser) -> None:
    add_robot_args(p)
    p.add_argument("--kc", type=float, default=2e6, help="process stiffness K_c*b [N/m]")
    p.add_argument("--dir", type=float, default=30.0, help="force angle from the normal [deg]")
    p.add_argument("--normal", type=float, default=None,
                   help="surface-normal angle from e1 in the plane [deg] (default: worst case)")
    p.add_argument("--cnc-stiffness", type=float, default=5e7, help="CNC stiffness [N/m]")
    p.add_argument("--duration", type=float, default=2.0, help="simulated time [s]")
    p.add_argument("-o", "--output", default=None, help="folder for the PNGs")


@command("chatter", "mode-coupling chatter at a pose (2-DOF, closed form + simulation) vs a CNC",
         _add_chatter)
def _run_chatter(args) -> int:
    from ..studies.contact import analyse, cnc_model, critical_kcb, plane_model, simulate
    from ..studies.contact.chatter import process_vectors
    from ..studies.contact.chatter_map import worst_normal
    from ..studies.contact.plots import plot_chatter_orbit, plot_chatter_time

    arm_ = arm_from(args)
    robot, arm = arm_.robot, arm_.model
    q = pose_from(robot, args)
    pm = plane_model(arm, q)
    normal = args.normal
    if normal is None:
        normal = float(worst_normal(pm.M, pm.C, pm.K, args.dir)[1])
    cnc = cnc_model(args.cnc_stiffness, float(np.trace(pm.M)) / 2, axes=pm.axes)
    n, f = process_vectors(normal, args.dir)
    out(f"plane e1={np.round(pm.axes[0], 3).tolist()} e2={np.round(pm.axes[1], 3).tolist()}; "
           f"normal {normal:.1f} deg, force {args.dir:.1f} deg from it, K_c b {args.kc:.3g} N/m")
    runs, stable = [], []
    for model in (pm, cnc):
        res = analyse(model, args.kc, args.dir, normal)
        lim = float(critical_kcb(model.M, model.C, model.K, n, f))
        ks = np.linalg.eigvalsh(model.K)
        out(f"{model.name:5s}: K principal {ks[0]:.3g}/{ks[1]:.3g} N/m, M diag "
               f"{np.diag(model.M).round(1).tolist()} kg, growth {res.growth_rate:+.3f} 1/s, "
               f"limit K_c b {lim:.3g} N/m -> {'stable' if res.is_stable else 'UNSTABLE'}")
        t, x = simulate(model.M, model.C, res.K_total, 1e-5 * n, args.duration)
        stable.append(res.is_stable)
        runs.append((f"{model.name}: {'stable' if res.is_stable else 'chatter'}, growth "
                     f"{res.growth_rate:+.2f} 1/s", t, x))
    verdict = "; ".join(f"{m.name} {'stable' if ok else 'CHATTERS (mode coupling)'}"
                        for m, ok in zip((pm, cnc), stable, strict=True))
    out(f"verdict: {verdict}")
    if args.output:
        os.makedirs(args.output, exist_ok=True)
        out(f"wrote {plot_chatter_time(runs, os.path.join(args.output, 'chatter_time.png'))}")
        out(f"wrote {plot_chatter_orbit(runs, os.path.join(args.output, 'chatter_orbit.png'))}")
    return 0


def _add_chatter_map(p: argparse.ArgumentParser) -> None:
    add_robot_args(p)
    p.add_argument("--dir", type=float, default=30.0, help="force angle from the normal [deg]")
    p.add_argument("--normal", type=float, default=None,
                   help="surface-normal angle in the plane [deg] (default: worst case)")
    p.add_argument("--n", type=int, default=25, help="grid points per joint")
    p.add_argument("-o", "--output", default=None, help="folder for the CSV and PNG")


@command("chatter-map", "limit K_c*b (mode coupling) over joints 2 and 3 (CSV, PNG)",
         _add_chatter_map)
def _run_chatter_map(args) -> int:
    from ..studies.contact import chatter_map, recommendation
    from ..studies.contact.plots import plot_chatter_map

    arm_ = arm_from(args)
    robot, arm = arm_.robot, arm_.model
    q = pose_from(robot, args)
    lo, hi = robot.lower, robot.upper
    cm = chatter_map(arm, q, np.linspace(lo[1], hi[1], args.n), np.linspace(lo[2], hi[2], args.n),
                     args.dir, args.normal, lower=lo, upper=hi)
    for b2, b3, k in cm.best(3):
        out(f"best: q2={b2:7.1f} deg q3={b3:7.1f} deg limit K_c b={k:.3g} N/m")
    out(recommendation(cm))
    if args.output:
        os.makedirs(args.output, exist_ok=True)
        G2, G3 = np.meshgrid(np.degrees(cm.q2), np.degrees(cm.q3), indexing="ij")
        csv = os.path.join(args.output, "chatter_map.csv")
        np.savetxt(csv, np.column_stack([G2.ravel(), G3.ravel(), cm.kcb.ravel(),
                                         cm.normal_deg.ravel(), cm.k_weak.ravel()]),
                   delimiter=",", header="q2_deg,q3_deg,kcb_limit_N/m,normal_deg,k_weak_N/m",
                   comments="", fmt="%.9g")
        out(f"wrote {csv}")
        out(f"wrote {plot_chatter_map(cm, os.path.join(args.output, 'chatter_map.png'))}")
    return 0
