"""What every command shares: the registry, printing, progress and the robot options.

A command is an ``add_args(parser)`` function and a ``run(args) -> int`` function,
registered with :func:`command`.  ``run`` parses nothing itself: it turns ``args`` into
one call of an API function, then prints the returned result or hands it to an API
writer.  Every command that needs an arm takes the same robot options
(:func:`add_robot_args`) and gets its robot and arm from :func:`robot_from` and
:func:`arm_from`, so the defaults are the same everywhere.
"""

from __future__ import annotations

import argparse
import sys
import threading
import time
import warnings
from collections.abc import Callable, Iterable

from ._numbers import count, number

__all__ = ["COMMANDS", "command", "out", "say", "set_quiet", "wrote", "Progress",
           "add_robot_args",
           "add_flexible_args", "add_krl_config_arg", "krl_config_from",
           "robot_from", "arm_spec_from", "arm_from", "pose_from", "arm_at_pose", "floats", "ints",
           "names"]

#: ``--mesh-size`` and the like: a tet edge [m] (a bare number is metres).
MESH_SIZE = number("length", "m", 0, 2, open_low=True)
#: ``--max-displacement``: the largest displacement a drawn mode shape is scaled to [m].
DISPLACEMENT = number("length", "m", 0, 100, open_low=True)

#: name -> (help, add_args, run), in registration order
COMMANDS: dict[str, tuple[str, Callable, Callable]] = {}


def command(name: str, help: str, add_args: Callable[[argparse.ArgumentParser], None]):
    """Decorator registering ``run(args) -> int`` as command ``name``."""

    def register(run):
        COMMANDS[name] = (help, add_args, run)
        return run

    return register


def out(*parts) -> None:
    """One line of a command's result on stdout."""
    print(*parts)  # noqa: T201 - the CLI is where printing belongs


#: ``-q``: no progress lines (warnings and errors still go to stderr).
_QUIET = threading.Event()


def set_quiet(quiet: bool) -> None:
    """Silence (``True``) or restore :func:`say` and :class:`Progress`."""
    (_QUIET.set if quiet else _QUIET.clear)()


def say(text: str) -> None:
    """One progress line on stderr (nothing under ``-q``)."""
    if not _QUIET.is_set():
        print(text, file=sys.stderr, flush=True)  # noqa: T201


def wrote(paths: Iterable) -> None:
    """``wrote <path>`` for every written file."""
    for p in paths:
        out(f"wrote {p}")


class Progress:
    """Start/finish lines with elapsed time on stderr; on a terminal a ticking timer
    (tqdm's status line, redrawn in place).

    Carriage returns go to a terminal only: a log file gets plain lines, one per start,
    note and finish.  Nothing under ``-q``.
    """

    def __init__(self, what: str):
        self.what = what
        self._bar = None

    def _write(self, text: str) -> None:
        if not _QUIET.is_set():
            sys.stderr.write(text)
            sys.stderr.flush()

    def __enter__(self):
        self.t0 = time.perf_counter()
        self._stop = threading.Event()
        if sys.stderr.isatty() and not _QUIET.is_set():
            from tqdm import tqdm

            self._bar = tqdm(total=None, desc=self.what, file=sys.stderr, leave=False,
                             bar_format="{desc} ... {elapsed}", mininterval=1.0)
            threading.Thread(target=self._tick, daemon=True).start()
        else:
            self._write(f"{self.what} ...\n")
        return self

    def _tick(self) -> None:
        while not self._stop.wait(1.0):
            self._bar.refresh()

    def note(self, text: str) -> None:
        if self._bar is not None:
            self._bar.write(f"  {text}", file=sys.stderr)
        else:
            self._write(f"  {text}\n")

    def __exit__(self, exc_type, exc, tb):
        self._stop.set()
        if self._bar is not None:
            self._bar.close()
        status = "done" if exc_type is None else "failed"
        self._write(f"{self.what}: {status} in {time.perf_counter() - self.t0:.1f} s\n")
        return False


def add_robot_args(p: argparse.ArgumentParser, models=("emodel",), pose: bool = True,
                   flexible: bool = True) -> None:
    """The robot options every arm command shares: ``--robot``, ``--model``, ``--mass``,
    and for flexible models ``--mesh-size``, ``--modes``, ``--coupling``; ``--pose``."""
    from ..assembly.arm import MASS_METHODS

    p.add_argument("--robot", default=None,
                   help="robot TOML or URDF (default: the built-in IRB 4600-class demo arm)")
    p.add_argument("--model", default=models[0], choices=list(models),
                   help="arm model: emodel = rigid links + joint springs; guyan, cb = links "
                        "reduced to superelements")
    p.add_argument("--mass", default="surface", choices=list(MASS_METHODS),
                   help="E-model link mass properties from the CAD surfaces (default) or "
                        "from tet meshes")
    if flexible:
        add_flexible_args(p)
    if pose:
        p.add_argument("--pose", default=None,
                       help="named pose of the robot file (P1, P2, P3) or q1,...,q6 [deg] "
                            "(default: P1, else the robot's first named pose, else zeros)")


def add_measured_pose_args(p: argparse.ArgumentParser, tcp_node: bool = False) -> None:
    """What a universal file from another tool does not say: ``--pose`` (the pose it was
    measured at), ``--response`` (a general ordinate) and, for FRF comparisons,
    ``--tcp-node``."""
    p.add_argument("--pose", default=None,
                   help="pose a universal file without flexarm's pose mark was measured at: "
                        "a named pose of the robot file or q1,...,q6 [deg] (such a file is "
                        "refused without it, never read at zero angles)")
    p.add_argument("--response", default=None,
                   choices=["displacement", "velocity", "acceleration"],
                   help="what the FRFs' ordinate is when the file says 'general' or "
                        "'unknown' and its unit label does not tell")
    if tcp_node:
        p.add_argument("--tcp-node", type=count(1), default=None,
                       help="node whose driving-point FRFs are the TCP's (FRF files with "
                            "several nodes)")


def add_flexible_args(p: argparse.ArgumentParser) -> None:
    """``--mesh-size``, ``--modes``, ``--coupling`` of flexible links."""
    p.add_argument("--mesh-size", type=MESH_SIZE, default=None,
                   help="tet edge of flexible links [m], e.g. 0.03 or 30mm (default: the "
                        "robot's)")
    p.add_argument("--modes", type=count(0, 500), default=None,
                   help="Craig-Bampton modes per link (default: the robot's)")
    p.add_argument("--coupling", default="rbe2", choices=["rbe2", "rbe3"],
                   help="seat coupling of flexible links")


def add_krl_config_arg(p: argparse.ArgumentParser) -> None:
    """``--krl-config``: the controller's tables a KRL program's ``BAS (#TOOL, n)`` reads."""
    p.add_argument("--krl-config", default=None, metavar="PATH/$config.dat",
                   help="with a KRL .src: the controller's $config.dat (TOOL_DATA, "
                        "BASE_DATA, LOAD_DATA of BAS (#TOOL, n), BAS (#BASE, n); default: "
                        "a $config.dat beside the .src)")


def krl_config_from(args, *programs):
    """``--krl-config``, refused when none of ``programs`` is a KRL ``.src``."""
    from pathlib import Path

    if args.krl_config is not None and not any(
            p is not None and Path(p).suffix.lower() == ".src" for p in programs):
        raise ValueError("--krl-config goes with a KRL program (a .src)")
    return args.krl_config


def robot_from(args):
    """The robot of ``--robot`` (the demo arm when absent)."""
    from ..robot import load_robot

    return load_robot(args.robot)


def arm_spec_from(args, model: str | None = None):
    """The :class:`~flexarm.assembly.arm.ArmSpec` of the robot options (``model``
    overrides ``--model``)."""
    from ..assembly.arm import ArmSpec

    return ArmSpec(model or args.model, args.mass, getattr(args, "mesh_size", None),
                   getattr(args, "modes", None), getattr(args, "coupling", "rbe2"))


def arm_from(args, robot=None, model: str | None = None):
    """The :class:`~flexarm.assembly.arm.Arm` of the robot options (flexible links from
    the cache after the first run)."""
    from ..assembly.arm import build_arm

    robot = robot_from(args) if robot is None else robot
    return build_arm(robot, arm_spec_from(args, model), progress=say)


def pose_from(robot, args):
    """(n,) joint angles [rad] of ``--pose`` (default: ``P1``, else the robot's first named
    pose, else all zeros; ``args.pose`` is set to the name used)."""
    from ..robot import pose_from_string

    if args.pose is None:
        args.pose = "P1" if "P1" in robot.poses else next(iter(robot.poses), None)
        if args.pose is None:
            args.pose = ",".join("0" for _ in robot.joints)
    try:  # joint limits and angle counts are checked there; the option is named here
        q = pose_from_string(robot, args.pose)
    except ValueError as exc:
        raise ValueError(f"--pose: {exc}") from None
    from ..robot.collision import pose_note

    note = pose_note(robot, q)
    if note:  # the analysis still runs: a model can be asked about any pose
        warnings.warn(f"--pose {args.pose}: the robot cannot take this pose ({note})",
                      stacklevel=2)
    return q


def arm_at_pose(args):
    """``(arm, q)``: the arm of the robot options and the joint angles [rad] of ``--pose``.

    The pose is read and checked before the arm is built, so a bad ``--pose`` fails
    before any meshing; ``args.pose`` is set to the name used (:func:`pose_from`).
    """
    robot = robot_from(args)
    q = pose_from(robot, args)
    return arm_from(args, robot), q


def floats(text: str, what: str = "value") -> list[float]:
    """``"0.06,0.045"`` -> ``[0.06, 0.045]`` (finite numbers); a bad entry names ``what``.
    An option's values are better read by its type (:mod:`._numbers`)."""
    from ..fe.quantities import Quantity, parse_list

    return parse_list(text, Quantity("ratio"), what)


def ints(text: str, what: str = "value") -> list[int]:
    """``"0,5,10"`` -> ``[0, 5, 10]``; a bad entry names ``what``."""
    from ..fe.quantities import parse_count

    if not text.strip():
        raise ValueError(f"{what} '': expected comma-separated whole numbers")
    return [parse_count(s.strip(), what, -2**31, 2**31 - 1) for s in text.split(",")]


def names(text: str) -> list[str]:
    """``"P1, P2"`` -> ``["P1", "P2"]``."""
    return [s.strip() for s in text.split(",") if s.strip()]
