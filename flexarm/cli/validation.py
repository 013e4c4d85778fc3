"""Measurements: ``lab`` (virtual lab), ``compare``, ``diagnose``."""

from __future__ import annotations

import argparse

from ._common import (
    MESH_SIZE,
    add_krl_config_arg,
    add_measured_pose_args,
    add_robot_args,
    command,
    krl_config_from,
    out,
    say,
    wrote,
)
from ._numbers import band, count, effect, levels, number, numbers

#: The tracker noise of files without a sigma column [µm] (a bare number is µm).
_TRACKER_UM = number("length", "um", 0, 1e4, open_low=True)
#: A relative scatter [%] (a bare number is per cent).
_PERCENT = number("ratio", "%", 0, 100, open_low=True)
#: Load levels [N]: ``start:stop:step`` or a comma list.
LOADS = levels("force", "N", 0, 1e6)
#: Lab noise: a length with its unit, returned in metres.
_LAB_NOISE = number("length", "um", 0, 1e4, bare=False, result="m")


def _add_validation_common(p: argparse.ArgumentParser) -> None:
    add_robot_args(p, ("emodel", "cb", "guyan"), pose=False)
    p.add_argument("--flexible", action="store_true", help="build the flexible model (link "
                   "flexibility); the E-model then takes its masses from the same tet meshes")
    p.add_argument("--flex-mesh", type=MESH_SIZE, default=0.06,
                   help="tet size [m] of that coarse flexible model (default 0.06, cached)")
    p.add_argument("--flex-modes", type=count(0, 500), default=4,
                   help="Craig-Bampton modes per link of that flexible model (default 4)")


def _options(args):
    """The :class:`~flexarm.validation.models.ValidationOptions` of the shared options."""
    from ..validation.models import ValidationOptions

    return ValidationOptions(args.mass, args.flexible, args.flex_mesh, args.flex_modes,
                             args.model, args.mesh_size, args.modes, args.coupling)


# --- lab -------------------------------------------------------------------------------
def _add_lab(p: argparse.ArgumentParser) -> None:
    _add_validation_common(p)
    p.add_argument("--effect", action="append", default=[], type=effect,
                   help="hidden effect, e.g. backlash:j2=0.1mrad (repeatable; angles and "
                        "lengths with their unit)")
    p.add_argument("--noise", type=_LAB_NOISE, default="15um",
                   help="tracker noise with its unit, e.g. 15um (or 15µm)")
    p.add_argument("--poses", default="P1,P2,P3", help="named poses (P1,P2), or joint "
                   "angles [deg] of each pose separated by ';' (0,52,-19,12,-15,-11;...)")
    p.add_argument("--loads", type=LOADS, default="0:800:100",
                   help="load levels [N] start:stop:step or a comma list")
    p.add_argument("--dirs", default="x,y,z", help="load directions, e.g. x,y,z,-z")
    p.add_argument("--cycles", action="store_true", help="load then unload each series")
    p.add_argument("--seed", type=count(0, 2**32 - 1), default=0)
    p.add_argument("--ref-noise", type=_LAB_NOISE, default="0um",
                   help="extra error of each series' reference reading with its unit, e.g. "
                        "45um (tracker re-lock; stated in the sigma column)")
    p.add_argument("--modal", default=None, help="also write natural frequencies to this CSV")
    p.add_argument("--n-modes", type=count(1, 100), default=4, help="modes per pose in --modal")
    p.add_argument("--freq-noise", type=number("ratio", "%", 0, 100), default=0.5,
                   help="frequency noise [%%]")
    p.add_argument("--frf-band", type=band("frequency", "Hz", 0, 1e5, open_low=True),
                   default=None, help="band of the FRFs of a --modal universal "
                   "file [Hz], LO:HI (default: 0.25 Hz to 1.2x the highest mode kept), "
                   "e.g. 0.25:300 to reach the wrist modes")
    p.add_argument("--program", default=None, help="run this program (a RAPID module, a KUKA "
                   "KRL .src with its .dat, or a CSV of poses as compensate reads it) under "
                   "--force instead of static series, and write the measured tool path (path "
                   "CSV)")
    p.add_argument("--reference", default=None, help="with --program: the program the path is "
                   "measured against, e.g. the original of a compensated program (default: "
                   "the program)")
    p.add_argument("--orientation", type=numbers("ratio", "", -1.0, 1.0, n=4), default=None,
                   metavar="QW,QX,QY,QZ", help="with a --program CSV of positions only: the "
                   "tool orientation of every pose, a unit quaternion in the base frame")
    p.add_argument("--force", default=None, help="with --program: the process force, as "
                   "compensate takes it (ballbar:800N, tool:fz=300, base:..., forces.csv)")
    p.add_argument("--proc", action="append", default=None, help="with --program: procedure "
                   "to run (repeatable; default: every procedure; several write "
                   "OUTPUT_<procedure>.csv each)")
    p.add_argument("--pivot", type=numbers("length", "mm", -1e4, 1e4, n=3, result="m"),
                   default=None, help="with --program: ball-bar pivot x,y,z [mm] (default: "
                   "fitted to the reference's circles)")
    p.add_argument("--tool", default="program", choices=["program", "tool0", "robot"],
                   help="with --program: what the targets are read as, as compensate reads "
                        "them (the instructions' tool, the flange, the robot file's TCP)")
    p.add_argument("--step", type=number("length", "mm", 0, 1000, open_low=True), default=2.0,
                   help="with --program: reading step along the path [mm]")
    add_krl_config_arg(p)
    p.add_argument("-o", "--output", required=True,
                   help="static CSV to write (the path CSV with --program)")


def _run_program_lab(args) -> int:
    """``lab --program``: the measured path of a program under load."""
    from ..robot.effects import parse_effect
    from ..studies.compensation.lab.lab_run import lab_program
    from ._common import arm_spec_from, robot_from

    if args.force is None:
        raise ValueError("--program needs --force (e.g. ballbar:800N, tool:fz=300)")
    if args.modal is not None:
        raise ValueError("--modal goes with static series, not with --program")
    robot = robot_from(args)
    procs = None if args.proc is None else [n.strip() for p in args.proc for n in p.split(",")
                                            if n.strip()]
    lab = lab_program(args.program, robot,
                      [parse_effect(e, robot.chain.n_joints) for e in args.effect], args.force,
                      procs=procs, reference=args.reference, spec=arm_spec_from(args),
                      noise=args.noise, seed=args.seed, pivot=args.pivot,
                      tool=None if args.tool == "program" else args.tool, step_mm=args.step,
                      orientation=args.orientation,
                      krl_config=krl_config_from(args, args.program, args.reference),
                      progress=say)
    out(lab.text())
    wrote(lab.write(args.output))
    return 0


@command("lab", "virtual lab: static series (or a program's path under load, --program) "
         "from the model + hidden effects + tracker noise", _add_lab)
def _run_lab(args) -> int:
    from ..validation.lab.virtual_lab import run_lab

    if args.program is not None:
        return _run_program_lab(args)
    if args.orientation is not None:
        raise ValueError("--orientation goes with --program (a CSV of positions only)")
    krl_config_from(args)  # refused without a KRL --program
    lab = run_lab(args.robot, args.effect, _options(args), noise=args.noise, poses=args.poses,
                  loads=args.loads, dirs=args.dirs, cycles=args.cycles, seed=args.seed,
                  ref_noise=args.ref_noise, modal=args.modal is not None, n_modes=args.n_modes,
                  freq_noise_pct=args.freq_noise, progress=say,
                  frf_band=args.frf_band)
    out(lab.text(lab.write(args.output, args.modal)))
    return 0


# --- compare ---------------------------------------------------------------------------
def _add_compare(p: argparse.ArgumentParser) -> None:
    p.add_argument("data", help="measurements: a CSV (static, modal or FRF, recognised by "
                   "its columns) or a universal file (mode shapes or FRFs)")
    _add_validation_common(p)
    add_measured_pose_args(p, tcp_node=True)
    p.add_argument("--noise", type=_TRACKER_UM, default=15.0,
                   help="tracker noise [µm] (no sigma column)")
    p.add_argument("--freq-noise", type=_PERCENT, default=0.5, help="frequency noise [%%] (modal)")
    p.add_argument("-o", "--output", default=None, help="report folder (CSV, PNG)")
    p.add_argument("--program", default=None, help="a path CSV against this program's "
                   "programmed path (the original program: a RAPID module, a KRL .src "
                   "or a CSV of poses): RMS and peak deviation")
    p.add_argument("--proc", default=None, help="with --program: the procedure (default: the "
                   "one the file names in a '# procedure:' comment, else the one nearest to "
                   "the readings)")
    add_krl_config_arg(p)


@command("compare", "model predictions vs measurements (static series, modal data, FRFs): "
         "errors, chi2_red, MAC, plots; a measured path vs its program (--program)",
         _add_compare)
def _run_compare(args) -> int:
    from ..validation.workflow import compare

    if args.program is not None:
        from ..studies.compensation.lab.measured import compare_path

        out(compare_path(args.data, args.program, args.proc,
                         krl_config=krl_config_from(args, args.program)).text())
        return 0
    krl_config_from(args)  # refused without a KRL --program
    cmp = compare(args.data, args.robot, _options(args), noise_um=args.noise,
                  freq_noise_pct=args.freq_noise, progress=say, pose=args.pose,
                  response=args.response, tcp_node=args.tcp_node)
    out(cmp.text())
    if args.output:
        wrote(cmp.write(args.output))
    return 0


# --- diagnose --------------------------------------------------------------------------
def _add_diagnose(p: argparse.ArgumentParser) -> None:
    p.add_argument("data", help="static measurement CSV")
    _add_validation_common(p)
    p.add_argument("--noise", type=_TRACKER_UM, default=15.0,
                   help="tracker noise [µm] (no sigma column)")
    p.add_argument("--apply", action="store_true", help="write a robot TOML with the accepted "
                   "effects and fitted parameters (-o)")
    p.add_argument("-o", "--output", default=None, help="robot TOML for --apply")
    p.add_argument("--force", action="store_true", help="--apply even when the diagnosis "
                   "ends with an unexplained misfit (first line of the report)")
    p.add_argument("--report", default=None, help="folder for the history CSV/JSON/PNG")
    p.add_argument("--noise-model", default="shared", choices=["shared", "independent"],
                   help="shared reference reading (GLS, default) or independent rows (only "
                   "to show the shared-reference trap)")
    p.add_argument("--modal", default=None, help="measured natural frequencies (CSV or "
                   "universal file; they join the fits, paired with model modes in every "
                   "fit; add --flexible for the link-flexibility candidate)")
    p.add_argument("--freq-noise", type=_PERCENT, default=0.5, help="frequency noise [%%]")
    p.add_argument("--shape-noise", type=_PERCENT, default=2.0, help="scatter of a measured "
                   "shape entry [%% of the shape's largest entry] (--modal with shapes: "
                   "modes paired by MAC, shapes join the fits)")
    add_measured_pose_args(p)


@command("diagnose", "find which physical effect the model misses in static measurements",
         _add_diagnose)
def _run_diagnose(args) -> int:
    from ..validation.workflow import run_diagnosis

    if args.apply and not args.output:
        raise ValueError("--apply needs -o NEW_ROBOT.toml")
    run = run_diagnosis(args.data, args.robot, _options(args), noise_um=args.noise,
                        noise_model=args.noise_model, modal=args.modal,
                        freq_noise_pct=args.freq_noise, progress=say,
                        shape_noise_pct=args.shape_noise, pose=args.pose,
                        response=args.response)
    out(run.text())
    if args.report:
        wrote(run.write_history(args.report))
    if args.apply:
        wrote([run.write_robot(args.output, force=args.force)])
    return 0
