"""A CSV of tool poses as a program, and :func:`read_program`, the one reader of a program
file for ``compensate``, ``lab --program``, ``compare --program`` and ``history``.

Those commands take, besides a RAPID module and a KUKA KRL ``.src`` with its ``.dat``
(:mod:`.krl_in`), a CSV of poses in the base frame (``wobj0``), one target a row:

* positions ``x_mm, y_mm, z_mm`` (any length unit the measurement files accept:
  ``x_m``, ``x_in`` ...), required;
* the orientation, either a unit quaternion ``qw, qx, qy, qz`` (RAPID's ``q1..q4``, what
  ``compensate -o poses.csv`` writes) or fixed-axis angles ``rx_deg, ry_deg, rz_deg``
  (``_rad`` too): turns about the base's x, then y, then z axis, ``R = Rz(rz) Ry(ry)
  Rx(rx)`` (FANUC's W, P, R; KUKA's C, B, A); or none, and then one orientation for
  every row (``--orientation qw,qx,qy,qz``);
* optionally ``target`` (RAPID names), ``step`` (names ``p<step>``) and ``f_N`` (read
  past): the path CSV ``lab --program`` and ``circle --measured`` use
  (``step, x_mm, y_mm, z_mm, f_N``) is such a file.

:func:`read_program` turns it into a RAPID module in memory: one procedure named after
the file (or as a leading ``# procedure: NAME`` comment names it, what ``lab --program``
and ``compensate -o NAME.csv`` write), a ``MoveJ`` to the first pose and ``MoveL``
through the others (a CSV gives no speeds or zones: ``v100`` and ``z1``, ``fine`` at both
ends, and the module says so in a comment), each pose a named robtarget whose
configuration is the one the arm has there on the branch of the first pose (the branch
nearest the zero angles), or, where that branch cannot reach a pose, the one nearest the
pose before.  Poses are read as
``tool0`` unless ``tool`` says otherwise.  Errors name the CSV file and line; the
motions carry the CSV lines of their targets, so later messages name them too.  Without a
robot (``compare``, ``history``: the programmed path only) no configuration is solved (all
``0``), nothing is checked for reach, and a file of positions only keeps the base frame's
orientation.
"""

from __future__ import annotations

import re
from dataclasses import replace
from pathlib import Path

import numpy as np

from ....fe.errors import ConvergenceError
from ....fe.typing import PathType
from ....robot.formats.krl_read import matrix_from_abc
from ....robot.formats.rapid import RapidModule, read_rapid
from ....robot.ik import ik
from ....robot.ik_path import rapid_conf, target_frames, tool_frame
from ....robot.quaternions import quat_from_matrix
from ....robot.tolerances import tol as robot_tol
from ....validation.data.formats._table import Field, Schema, read_table, vector
from ...tolerances import tol
from ..solve.ik_batch import newton_ik
from .krl_in import krl_module
from .rapid_out import module_of_text, read_module_text

__all__ = ["is_poses_csv", "read_program", "poses_module", "named_procedure"]

_QUAT = ("qw", "qx", "qy", "qz")
_SCHEMA = Schema("poses", (
    Field("target", "label", required=False),
    Field("step", "int", required=False),
    *vector("", "length", "mm"),
    Field("f", "real", "force", "N", required=False),
    *(Field(c, "real", required=False, group="quat") for c in _QUAT),
    *vector("r", "angle", "deg", required=False),
), "a CSV of tool poses")
_RAPID_NAME = re.compile(r"[A-Za-z][A-Za-z0-9_]{0,31}\Z")
_UNUSED = "[9E+09,9E+09,9E+09,9E+09,9E+09,9E+09]"
#: Orientation of a pose read for its path only (no robot, no orientation given).
_BASE_FRAME = (1.0, 0.0, 0.0, 0.0)


def is_poses_csv(program: PathType) -> bool:
    """True when ``program`` names a CSV (read as poses), not a RAPID module.

    Examples
    --------
    >>> is_poses_csv("path.CSV"), is_poses_csv("prog.mod")
    (True, False)
    """
    return Path(program).suffix.lower() == ".csv"


def named_procedure(path: PathType) -> str | None:
    """The procedure a CSV names in a leading ``# procedure: NAME`` comment.

    Examples
    --------
    >>> import tempfile, os
    >>> p = os.path.join(tempfile.mkdtemp(), "m.csv")
    >>> _ = open(p, "w").write("# lab\\n# procedure: Path_30\\nstep,x_mm,y_mm,z_mm,f_N\\n")
    >>> named_procedure(p)
    'Path_30'
    """
    try:
        with open(path, encoding="utf-8", errors="replace") as fh:
            for line in fh:
                text = line.strip()
                if text and not text.startswith("#"):
                    return None  # the header: the comments are over
                m = re.fullmatch(r"#\s*procedure:\s*(\w+)", text)
                if m:
                    return m.group(1)
    except OSError:
        return None  # the reader of the file says what is wrong with it
    return None


def _num(x: float) -> str:
    """The shortest text of ``x`` rounded to 1e-9 (of a mm: the CSV's decimals, not the
    binary noise of its conversion to metres and back)."""
    s = repr(round(float(x), 9) + 0.0)
    return s[:-2] if s.endswith(".0") else s


def _orientations(table, v: dict, n: int, orientation) -> np.ndarray:
    """(n, 4) quaternions of the rows, from the file's columns or ``orientation``."""
    has = {g: any(c in table.columns for c in cols)
           for g, cols in (("quat", _QUAT), ("r", ("rx", "ry", "rz")))}
    for g, cols in (("quat", "qw, qx, qy, qz"), ("r", "rx, ry, rz")):
        if has[g] and g not in v:
            raise table.error(None, None, f"give all of {cols} or none of them")
    if has["quat"] and has["r"]:
        raise table.error(None, None, "give the orientation once: a quaternion (qw, qx, qy, "
                                      "qz) or angles (rx, ry, rz), not both")
    if has["quat"]:
        Q = np.array(v["quat"], dtype=np.float64)
        bad = np.flatnonzero(np.abs(np.linalg.norm(Q, axis=1) - 1.0) > robot_tol.quaternion_norm)
        if len(bad):
            raise table.error(int(bad[0]), "qw", "qw, qx, qy, qz is not a unit quaternion "
                                                 f"(|q| = {np.linalg.norm(Q[bad[0]]):.6g})")
        return Q
    if has["r"]:
        angles = np.degrees(np.column_stack([v["rz"], v["ry"], v["rx"]]))
        return np.round(quat_from_matrix(matrix_from_abc(angles)), 12)
    if orientation is None:
        raise ValueError(f"{table.source}: positions only (x, y, z): give the tool orientation "
                         "(--orientation qw,qx,qy,qz), or qw, qx, qy, qz or rx, ry, rz columns")
    q = np.asarray(orientation, dtype=np.float64).reshape(-1)
    if q.shape != (4,) or abs(np.linalg.norm(q) - 1.0) > robot_tol.quaternion_norm:
        raise ValueError(f"--orientation {','.join(f'{x:g}' for x in q)}: expected a unit "
                         "quaternion qw,qx,qy,qz")
    return np.tile(q, (n, 1))


def _names(table, v: dict, n: int) -> list[str]:
    if "target" in v:
        names = [str(s) for s in v["target"]]
        seen: dict[str, int] = {}
        for i, name in enumerate(names):
            if not _RAPID_NAME.match(name):
                raise table.error(i, "target", f"'{name}' is not a RAPID name (a letter, then "
                                               "letters, digits or _, 32 at most)")
            if name.lower() in seen:
                raise table.error(i, "target", f"target '{name}' is listed twice")
            seen[name.lower()] = i
        return names
    steps = v.get("step")
    if steps is not None and steps.min() >= 0 and len(np.unique(steps)) == n:
        return [f"p{int(s)}" for s in steps]
    return [f"p{k + 1}" for k in range(n)]


def _angles(ch, T: np.ndarray, robot, table, names, P) -> np.ndarray:
    """(n, 6) joint angles [rad] of the poses ``T``: all at once by Newton from the first
    pose's branch (the one nearest the zero angles), and one by one from the pose before
    where that fails (out of reach, past a limit, another arm configuration)."""
    def solve(i, near):
        try:
            return ik(ch, T[i], q_near=near, lower=robot.lower, upper=robot.upper)
        except (ValueError, ConvergenceError):
            x, y, z = P[i]
            raise table.error(i, None, f"target {names[i]} at ({x:.1f}, {y:.1f}, {z:.1f}) "
                                       "mm is out of the arm's reach or needs a joint beyond "
                                       "its limits") from None

    q0 = solve(0, np.zeros(ch.n_joints))
    Q, err = newton_ik(ch, T, np.tile(q0, (len(T), 1)))
    cfx = rapid_conf(ch, Q)[:, 3]
    redo = (err > tol.ik_pose_error) | np.any(Q < robot.lower, axis=1) \
        | np.any(Q > robot.upper, axis=1) | (cfx != cfx[0])
    redo[0] = False
    Q[0] = q0
    for i in np.flatnonzero(redo):  # in order: the pose before is final
        Q[i] = solve(i, Q[i - 1])
    return Q


def _procedure_name(path: Path, names: list[str]) -> str:
    """The procedure the file names (:func:`named_procedure`), else its stem, as a RAPID
    (and KRL) name apart from every target's."""
    named = named_procedure(path)
    name = re.sub(r"\W", "_", named if named and _RAPID_NAME.match(named) else path.stem)[:24]
    name = name if re.match(r"[A-Za-z]", name) else f"P_{name}"[:24]
    taken = {t.lower() for t in names}
    return name if name.lower() not in taken else f"{name[:19]}_path"


def poses_module(path: PathType, robot=None, tool=None,
                 orientation=None) -> tuple[str, RapidModule]:
    """(RAPID text, module) of a CSV of poses (see the module's docstring).

    Parameters
    ----------
    path : path
        The CSV.
    robot : Robot or None
        Kinematics and joint limits (the configuration of every pose); None: the path
        only (configurations 0, no reach check, positions only in the base orientation).
    tool : None, "tool0", "robot" or (4, 4) float
        What the poses are read as (default ``tool0``, the flange).
    orientation : (4,) float, optional
        Quaternion ``[w, x, y, z]`` of every pose when the file gives positions only.

    Raises
    ------
    ReadError
        A bad header, column or value (naming the file, line and column).
    ValueError
        No orientation, a pose out of reach (naming the file and line).

    Examples
    --------
    >>> import tempfile, pathlib
    >>> from flexarm.robot.demo_arm import load_demo_robot
    >>> p = pathlib.Path(tempfile.mkdtemp()) / "cut.csv"
    >>> _ = p.write_text("x_mm,y_mm,z_mm\\n1100,-150,500\\n1400,-150,500\\n")
    >>> text, module = poses_module(p, load_demo_robot(), orientation=[0, 0, 1, 0])
    >>> [(m.kind, m.targets[0].name, m.line) for m in module.procedures["cut"].motions]
    [('MoveJ', 'p1', 2), ('MoveL', 'p2', 3)]
    """
    path = Path(path)
    table = read_table(path, _SCHEMA.vocabulary)
    v = table.parse(_SCHEMA)
    n = len(table.lines)
    P = np.array(v["xyz"], dtype=np.float64) * 1e3
    if robot is None and orientation is None:
        orientation = _BASE_FRAME  # the path alone does not need it
    Q = _orientations(table, v, n, orientation)
    names = _names(table, v, n)
    proc = _procedure_name(path, names)
    if robot is None:
        conf = np.zeros((n, 4), dtype=int)
    else:
        ch = replace(robot.chain, tool=tool_frame(robot.chain,
                                                  "tool0" if tool is None else tool))
        conf = rapid_conf(ch, _angles(ch, target_frames(P, Q), robot, table, names, P))
    what = "the robot file's TCP" if tool == "robot" else "tool0 (the flange)"
    what += "" if robot is not None else ", for the path only (no configurations)"
    lines = [f"MODULE {proc}_poses",
             f"    ! flexarm: the {n} poses of {path.name} read as {what}; the CSV gives no "
             "speeds or zones: v100 and z1 (fine at both ends)"]
    lines += [f"    CONST robtarget {t}:=[[{','.join(_num(x) for x in p)}],"
              f"[{','.join(_num(x) for x in qq)}],[{','.join(str(int(c)) for c in cf)}],"
              f"{_UNUSED}];" for t, p, qq, cf in zip(names, P, Q, conf, strict=True)]
    lines.append(f"    PROC {proc}()")
    for k, t in enumerate(names):
        kind, zone = ("MoveJ", "fine") if k == 0 else ("MoveL", "fine" if k == n - 1 else "z1")
        lines.append(f"        {kind} {t},v100,{zone},tool0\\WObj:=wobj0;")
    text = "\n".join([*lines, "    ENDPROC", "ENDMODULE", ""])
    module = module_of_text(text, "utf-8", str(path))
    # the motions carry the CSV's lines: later messages (reach, limits) name them
    p = module.procedures[proc]
    moves = tuple(replace(m, line=int(table.lines[k])) for k, m in enumerate(p.motions))
    procs = {proc: replace(p, motions=moves, line=int(table.lines[0]))}
    return text, replace(module, procedures=procs)


def read_program(program: PathType, robot=None, tool=None, orientation=None,
                 krl_config: PathType | None = None) -> tuple[str, str, RapidModule]:
    """(text, encoding, module) of a program: a RAPID module as written, a CSV of poses
    (``.csv``) as one (:func:`poses_module`), or a KUKA KRL ``.src`` with its ``.dat`` as
    one (:func:`~.krl_in.krl_module`).

    Parameters
    ----------
    program : path
        The RAPID module, the CSV of poses or the KRL ``.src``.
    robot : Robot or None
        The arm the CSV's poses and the KRL targets are solved on (their
        configurations); None: the programmed path only (``compare``, ``history``).
    tool : None, "tool0", "robot" or (4, 4) float
        What a CSV's poses are read as (default ``tool0``); a KRL program's targets
        (default: its ``$TOOL``).
    orientation : (4,) float, optional
        Quaternion ``[w, x, y, z]`` of every pose of a CSV of positions only.
    krl_config : path, optional
        A KRL program's controller tables, ``$config.dat`` (default: the one beside the
        ``.src``, if any); not read for other programs.

    Raises
    ------
    ReadError
        A bad file (naming the file, line and column).
    ValueError
        ``orientation`` with a RAPID module, a pose out of reach.

    Examples
    --------
    >>> from flexarm.robot.demo_arm import load_demo_robot
    >>> from flexarm.studies.contact.loaded_circle import THESIS_RAPID
    >>> text, encoding, module = read_program(THESIS_RAPID, load_demo_robot())
    >>> encoding, module.name
    ('utf-8', 'Module1')
    """
    if is_poses_csv(program):
        text, module = poses_module(program, robot, tool, orientation)
        return text, "utf-8", module
    name, suffix = Path(program).name, Path(program).suffix.lower()
    if orientation is not None:
        raise ValueError(f"--orientation goes with a CSV of positions, not with the program "
                         f"{name} (its targets give it)")
    if suffix == ".src":  # KUKA KRL, the .dat read beside it
        text, module = krl_module(program, robot, tool, krl_config)
        return text, "utf-8", module
    if suffix == ".dat":
        raise ValueError(f"{name}: give the KRL program's .src (its .dat is read beside it)")
    text, encoding = read_module_text(program)
    return text, encoding, read_rapid(program)
