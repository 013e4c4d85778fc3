"""A KUKA KRL program (a ``.src`` with its ``.dat`` beside it) as a RAPID module in memory,
the program of ``lab --program``, ``compare --program``, ``history`` and ``compensate``.

:func:`~flexarm.robot.formats.krl_read.read_krl` reads the pair, the modules of the
folder it calls and the controller's ``$config.dat`` (the subset flexarm writes,
anything else one line naming the file and line); :func:`krl_module` writes what it read
as the RAPID module the rest of flexarm runs, one ``PROC`` per procedure of the program
(the main routine when it moves the arm itself, else each routine it calls, and the
routines nothing calls), so ``# procedure: NAME`` and ``--proc`` name KRL routines:

* calls: the called routine's moves are inlined at the call (another module's too,
  with a comment naming its file and line on the move); the system variables flow
  through the call as on the controller;

* ``PTP``, ``LIN``, ``CIRC`` become ``MoveJ`` (``MoveAbsJ`` to an ``E6AXIS``/``AXIS``),
  ``MoveL``, ``MoveC``; declared targets stay named robtargets, inline ones stay inline;
* speeds: ``$VEL.CP`` [m/s] is the TCP speed (``v<mm/s>``, ``\\V`` where RAPID has no
  such speeddata, ``$VEL_MA.CP`` is ``vmax``); a ``PTP`` runs at ``$VEL_AXIS`` [% of each
  axis], which RAPID cannot say: ``v100``, and the percentage in a comment on the move;
* zones: no approximation is ``fine``; ``C_DIS``, ``C_PTP``, ``C_VEL`` or ``C_ORI`` a zone
  of ``$APO.CDIS`` [mm] (``z1`` when the program sets none).  Neither speeds nor zones
  change the path flexarm samples (it passes through every target);
* the tool: ``$TOOL`` (a frame on the flange [mm], KUKA's A, B, C; ``BAS (#TOOL, n)``
  the controller's ``TOOL_DATA[n]`` and ``LOAD_DATA[n]``) becomes a ``tooldata``
  with the ``$LOAD`` payload, and the targets are read as that tool's TCP, as a RAPID
  program's targets are read as its tooldata (what ``compensate -o NAME.src`` writes);
  no ``$TOOL`` (or the null frame) is ``tool0``, the flange.  ``--tool robot`` or
  ``tool0`` override it as they do a RAPID program's tool;
* the base: ``$BASE`` (a frame [mm]; ``BAS (#BASE, n)`` the controller's
  ``BASE_DATA[n]``, 0 the null one) is applied, so
  every robtarget is in the robot base (``wobj0``; the robot root taken as the world).
  A named target moved to under two bases is refused;
* the configuration: the status and turn (``S``, ``T``) of a ``PTP`` target pick the
  branch of the closed-form IK whose shoulder, elbow, wrist and axis signs they give (a
  joint within ``conf_boundary`` of zero meets either sign), the nearest to the target
  before among several.  The controller reads them on ``PTP`` moves only: a ``LIN`` or
  ``CIRC`` target, and one without them, takes the branch nearest the target before (the
  first: nearest the zero angles).  The robtarget holds the ABB configuration of those
  angles.

Errors name the ``.src`` (or ``.dat``) and line, a called module's for its moves; the
motions carry their ``.src`` lines, so later messages (reach along the path, limits)
name them too (with the main ``.src``'s name: a RAPID motion holds a line, not a
file).  Without a robot (``compare``, ``history``: the programmed path only) every
configuration is 0.
"""

from __future__ import annotations

import re
from dataclasses import replace
from pathlib import Path

import numpy as np

from ....fe.errors import ConvergenceError, ReadError
from ....fe.typing import FloatArray, PathType
from ....robot.formats.krl import status_turn
from ....robot.formats.krl_read import KrlProgram, matrix_from_abc, read_krl
from ....robot.formats.rapid import RapidModule
from ....robot.ik import IKConfig, ik, ik_analytic, is_spherical_wrist_arm
from ....robot.ik_path import TOOL0, rapid_conf, tool_frame
from ....robot.quaternions import quat_from_matrix
from ...tolerances import tol
from .rapid_out import module_of_text

__all__ = ["krl_module"]

_KINDS = {"PTP": "MoveJ", "LIN": "MoveL", "CIRC": "MoveC"}
#: RAPID's predefined speeddata [mm/s] and zonedata (TCP radius [mm]; ``z0`` is 0.3 mm).
_SPEEDS = {5, 10, 20, 30, 40, 50, 60, 80, 100, 150, 200, 300, 400, 500, 600, 800, 1000,
           1500, 2000, 2500, 3000, 4000, 5000, 6000, 7000}
_ZONES = {1, 5, 10, 15, 20, 30, 40, 50, 60, 80, 100, 150, 200}
_RAPID_NAME = re.compile(r"[A-Za-z][A-Za-z0-9_]{0,31}\Z")
_UNUSED = 9e9


def _num(x: float) -> str:
    """Text of ``x`` that reads back to the same float (RAPID's ``9E+09``: unused)."""
    if float(x) >= _UNUSED:
        return "9E+09"
    s = repr(float(x) + 0.0)
    return s[:-2] if s.endswith(".0") else s


def _list(values) -> str:
    return "[" + ",".join(_num(v) for v in values) + "]"


def _frame(value, where: str, what: str) -> FloatArray:
    """(4, 4) frame [mm] of a KRL ``{X .., Y .., Z .., A .., B .., C ..}`` (or the null
    frame for ``$NULLFRAME`` and an unset variable)."""
    if value is None or value == "$NULLFRAME":
        return np.eye(4)
    if not isinstance(value, dict) or any(not isinstance(value.get(k), (int, float))
                                          for k in "XYZABC"):
        raise ReadError(f"{where}: {what} is not a frame {{X .., Y .., Z .., A .., B .., "
                        "C ..}} of numbers")
    T = np.eye(4)
    T[:3, :3] = matrix_from_abc([value["A"], value["B"], value["C"]])
    T[:3, 3] = [value["X"], value["Y"], value["Z"]]
    return T


def _speed(kind: str, s: dict, where: str) -> tuple[str, str]:
    """(RAPID speed argument, trailing comment) of a move under the settings ``s``."""
    if kind == "PTP":
        pct = s.get("$VEL_AXIS[1]")
        said = f"{pct:g} %" if isinstance(pct, (int, float)) else "not set"
        return "v100", f" ! PTP, $VEL_AXIS {said}"
    v = s.get("$VEL.CP")
    if v is None:
        return "v100", " ! no $VEL.CP"
    if v == "$VEL_MA.CP":
        return "vmax", ""
    if not isinstance(v, (int, float)) or not v > 0:
        raise ReadError(f"{where}: $VEL.CP = {v}: expected a speed > 0 [m/s]")
    mm_s = round(float(v) * 1e3, 9)
    return (f"v{int(mm_s)}" if mm_s in _SPEEDS else f"v100\\V:={_num(mm_s)}"), ""


def _zone(approx: str | None, s: dict, where: str) -> str:
    """RAPID zone argument: ``fine``, or the ``$APO.CDIS`` radius [mm]."""
    if approx is None:
        return "fine"
    r = s.get("$APO.CDIS")
    if r is None:
        return "z1"
    if not isinstance(r, (int, float)) or r < 0:
        raise ReadError(f"{where}: $APO.CDIS = {r}: expected a distance >= 0 [mm]")
    if r == 0.3:
        return "z0"
    return f"z{int(r)}" if r in _ZONES else f"z1\\Z:={_num(r)}"


def _tooldata(T: FloatArray, load) -> str:
    """The ``[robhold, tframe, tload]`` of a tool frame [mm] and a KRL ``$LOAD``."""
    tframe = f"[{_list(T[:3, 3])},{_list(quat_from_matrix(T[:3, :3]))}]"
    tload = "[0,[0,0,0],[1,0,0,0],0,0,0]"  # the program gives none: RAPID's "no load"
    if isinstance(load, dict) and isinstance(load.get("M"), (int, float)):
        cm = load.get("CM") if isinstance(load.get("CM"), dict) else {}
        J = load.get("J") if isinstance(load.get("J"), dict) else {}
        C = _frame({k: cm.get(k, 0.0) for k in "XYZABC"}, "", "$LOAD.CM")
        tload = (f"[{_num(load['M'])},{_list(C[:3, 3])},{_list(quat_from_matrix(C[:3, :3]))},"
                 f"{','.join(_num(J.get(k, 0.0)) for k in 'XYZ')}]")
    return f"[TRUE,{tframe},{tload}]"


def _turned(q: FloatArray, turn: int) -> FloatArray:
    """``q`` [rad] with each joint the turn of its sign in ``turn`` (bit ``j``: negative)."""
    q = (q + np.pi) % (2 * np.pi) - np.pi
    neg = (turn >> np.arange(len(q))) & 1
    eps = tol.conf_boundary
    return np.where((neg == 1) & (q > eps), q - 2 * np.pi,
                    np.where((neg == 0) & (q < -eps), q + 2 * np.pi, q))


def _has_status(ch, q: FloatArray, S: int, turn: int) -> bool:
    """``q`` has the status and turn ``S``, ``turn`` (bits of joints at zero are free)."""
    s, t = status_turn(np.degrees(q), rapid_conf(ch, q)[3])
    free_t = int(np.sum((np.abs(q) < tol.conf_boundary) << np.arange(len(q))))
    free_s = 4 if abs(q[4]) < tol.conf_boundary else 0
    return (int(s) | free_s) == (S | free_s) and (int(t) | free_t) == (turn | free_t)


def _joints(ch, T: FloatArray, st, near: FloatArray, robot) -> FloatArray | None:
    """Joint angles [rad] reaching ``T`` (4, 4) [m] with status and turn ``st`` (or the
    branch nearest ``near``); None when there are none within the limits."""
    lo, hi = robot.lower, robot.upper
    if st is None or not is_spherical_wrist_arm(ch):
        try:
            q = ik(ch, T, q_near=near, lower=lo, upper=hi)
        except (ValueError, ConvergenceError):
            return None
        return q if st is None or _has_status(ch, q, *st) else None
    best = None
    for c in IKConfig.all():
        q = ik_analytic(ch, T, c)
        if np.any(np.isnan(q)):
            continue
        q = _turned(q, st[1])
        if np.any(q < lo) or np.any(q > hi) or not _has_status(ch, q, *st):
            continue
        if best is None or np.sum((q - near) ** 2) < np.sum((best - near) ** 2):
            best = q
    return best


def _metres(T: FloatArray) -> FloatArray:
    """A (4, 4) frame [mm] in metres."""
    out = np.array(T, dtype=np.float64)
    out[:3, 3] *= 1e-3
    return out


class _Reader:
    """The moves of a :class:`KrlProgram` as RAPID lines, collecting targets and tools."""

    def __init__(self, prog: KrlProgram, src: Path):
        self.prog, self.src = prog, src
        self.data = {k.lower(): (k, t, v) for k, (t, v) in prog.data.items()}
        self.targets: dict[str, dict] = {}  # key -> name, frame [mm], S/T, tool, line
        self.joints: dict[str, str] = {}  # axis targets: name -> jointtarget literal
        self.tools: list[tuple[str, str]] = []  # name, tooldata

    def name(self, name: str, where: str) -> str:
        if not _RAPID_NAME.match(name):
            raise ReadError(f"{where}: '{name}' is not a RAPID name (a letter, then letters, "
                            "digits or _): rename it in the program")
        return name

    def tool(self, s: dict, where: str) -> tuple[str, FloatArray]:
        """(RAPID tool, frame on the flange [mm]) of the settings ``s``."""
        T = _frame(s.get("$TOOL"), where, "$TOOL")
        if np.array_equal(T, np.eye(4)):
            return "tool0", T
        text = _tooldata(T, s.get("$LOAD"))
        for name, known in self.tools:
            if known == text:
                return name, T
        taken = {*self.data, *(r.lower() for r in self.prog.routines)}
        name = f"krl_tool{len(self.tools) + 1}"
        while name.lower() in taken:
            name += "_"
        self.tools.append((name, text))
        return name, T

    def target(self, t, kind: str, base: FloatArray, tool: FloatArray, src: Path,
               line: int) -> tuple[str, bool]:
        """(RAPID argument: a name or an inline placeholder, is an axis target)."""
        where = f"{src}, line {line}"
        if isinstance(t, str):
            name, typ, value = self.data[t.lower()]
        else:
            name, typ, value = None, "E6AXIS" if "A1" in t else "E6POS", t
        if not isinstance(value, dict):
            raise ReadError(f"{where}: target '{t}' is a {typ}, not a position")
        if typ in ("E6AXIS", "AXIS"):
            if kind != "PTP":
                raise ReadError(f"{where}: {kind} to the axis target '{name or t}': only PTP "
                                "moves go to axis angles")
            literal = (f"[{_list(value.get(f'A{i}', 0.0) for i in range(1, 7))},"
                       f"{_list(value.get(f'E{i}') or _UNUSED for i in range(1, 7))}]")
            if name is None:
                return literal, True
            self.joints[self.name(name, where)] = literal
            return name, True
        P = base @ _frame({k: value.get(k) for k in "XYZABC"}, where, f"target '{name or t}'")
        key = name.lower() if name else f"@inline{len(self.targets)}@"
        seen = self.targets.get(key)
        if seen is not None and not np.array_equal(seen["frame"], P):  # same text, same floats
            raise ReadError(f"{where}: target '{name}' is moved to under another $BASE than "
                            f"on {Path(seen['file']).name}, line {seen['line']}: give each "
                            "base its own targets")
        # the controller reads S and T on PTP moves only (a LIN or CIRC keeps the branch)
        st = (value["S"], value["T"]) if kind == "PTP" and isinstance(value.get("S"), int) \
            and isinstance(value.get("T"), int) else None
        if seen is None:
            self.targets[key] = {"name": self.name(name, where) if name else None,
                                 "frame": P, "st": st, "tool": tool, "line": line,
                                 "file": src,
                                 "ext": [value.get(f"E{i}") or _UNUSED for i in range(1, 7)]}
        elif seen["st"] is None and st is not None:
            seen.update(st=st, line=line, file=src)
        return key if name is None else name, False

    def routine(self, routine: str) -> list[str]:
        lines = [f"    PROC {self.name(routine, str(self.src))}()"]
        for m in self.prog.routines[routine]:
            src = Path(m.file) if m.file else self.src
            where = f"{src}, line {m.line}"
            s = m.settings
            tool, T_tool = self.tool(s, where)
            base = _frame(s.get("$BASE"), where, "$BASE")
            speed, note = _speed(m.kind, s, where)
            zone = _zone(m.approx, s, where)
            args = [self.target(t, m.kind, base, T_tool, src, m.line) for t in m.targets]
            kind = "MoveAbsJ" if args[0][1] else _KINDS[m.kind]
            if src != self.src:  # inlined from a called module
                note += f" ! {src.name}, line {m.line}"
            lines.append(f"        {kind} {','.join(a for a, _j in args)},{speed},{zone},"
                         f"{tool}\\WObj:=wobj0;{note}")
        return [*lines, "    ENDPROC"]


def krl_module(path: PathType, robot=None, tool=None,
               config: PathType | None = None) -> tuple[str, RapidModule]:
    """(RAPID text, module) of a KRL ``.src`` and the ``.dat`` beside it (see the
    module's docstring).

    Parameters
    ----------
    path : path
        The ``.src``.
    robot : Robot or None
        Kinematics and joint limits (the configuration of every target from its status
        and turn); None: the path only (configurations 0, no reach check).
    tool : None, "tool0", "robot" or (4, 4) float
        What the targets are read as (default: the program's ``$TOOL``).
    config : path, optional
        The controller's ``$config.dat`` (``BAS (#TOOL, n)``, ``BAS (#BASE, n)``;
        default: the one beside the ``.src``, if any).

    Raises
    ------
    ReadError
        A missing ``.dat``, an undeclared target, a statement outside the subset, a
        routine found nowhere, a recursion, a tool or base with no table or entry, a
        target no joint angles reach with its status and turn (naming the file and line).

    Examples
    --------
    >>> import tempfile, pathlib
    >>> from flexarm.robot.demo_arm import load_demo_robot
    >>> from flexarm.robot.formats.krl import write_krl
    >>> from flexarm.robot.formats.rapid import read_rapid
    >>> from flexarm.studies.contact.loaded_circle import THESIS_RAPID
    >>> src = pathlib.Path(tempfile.mkdtemp()) / "thesis.src"
    >>> _ = write_krl(src, read_rapid(THESIS_RAPID), ["Path_30"])
    >>> text, module = krl_module(src, load_demo_robot())
    >>> [(m.kind, m.to_point.name, m.line) for m in module.procedures["Path_30"].motions]
    [('MoveJ', 'Target_70', 19), ('MoveC', 'Target_90', 21), ('MoveC', 'Target_110', 22)]
    """
    src = Path(path)
    prog = read_krl(src, config)
    reader = _Reader(prog, src)
    body = [line for r in prog.routines for line in reader.routine(r)]
    decls = [f"    PERS tooldata {n}:={text};" for n, text in reader.tools]
    decls += [f"    CONST jointtarget {n}:={text};" for n, text in reader.joints.items()]
    near = None if robot is None else np.zeros(robot.chain.n_joints)
    inline = {}
    for key, t in reader.targets.items():
        conf = np.zeros(4, dtype=int)
        if robot is not None:
            T_tool = tool_frame(robot.chain, tool) if tool is not None else \
                TOOL0 @ _metres(t["tool"])
            ch = replace(robot.chain, tool=T_tool)
            q = _joints(ch, _metres(t["frame"]), t["st"], near, robot)
            if q is None:
                x, y, z = t["frame"][:3, 3]
                which = "" if t["st"] is None else f" (with S {t['st'][0]} T {t['st'][1]})"
                raise ReadError(f"{t['file']}, line {t['line']}: target "
                                f"{t['name'] or '(inline)'} at "
                                f"({x:.1f}, {y:.1f}, {z:.1f}) mm is out of the arm's reach or "
                                f"needs a joint beyond its limits{which}")
            near, conf = q, rapid_conf(ch, q)
        literal = (f"[{_list(t['frame'][:3, 3])},{_list(quat_from_matrix(t['frame'][:3, :3]))},"
                   f"[{','.join(str(int(c)) for c in conf)}],{_list(t['ext'])}]")
        if t["name"] is None:
            inline[key] = literal
        else:
            decls.append(f"    CONST robtarget {t['name']}:={literal};")
    text = "\n".join([f"MODULE {prog.name}_krl",
                      f"    ! flexarm: {src.name} and {src.stem}.dat (KUKA KRL) as RAPID: "
                      "$TOOL as tooldata, $BASE applied (wobj0), S and T as configurations",
                      *[f"    ! flexarm: also read {Path(f).name}" for f in
                        [*prog.files[1:], *([prog.config] if prog.config else [])]],
                      *decls, *body, "ENDMODULE", ""])
    for k, v in inline.items():
        text = text.replace(k, v)
    module = module_of_text(text, "utf-8", str(src))
    # the motions carry the .src's lines: later messages (reach, limits) name them
    procs = {}
    for name, p in module.procedures.items():
        moves = prog.routines[next(r for r in prog.routines if r.lower() == name.lower())]
        motions = tuple(replace(mo, line=km.line) for mo, km in zip(p.motions, moves,
                                                                    strict=True))
        procs[name] = replace(p, motions=motions, line=moves[0].line if moves else p.line)
    return text, replace(module, procedures=procs)
