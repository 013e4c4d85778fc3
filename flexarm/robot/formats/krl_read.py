"""Read the KUKA KRL that :mod:`~flexarm.robot.formats.krl` writes: a ``.src``/``.dat`` pair.

The subset read is the one flexarm writes (and the plain expert-mode programs shaped like
it): in the ``.dat``, ``DECL TYPE name=value`` lines (``E6POS``, ``POS``, ``E6AXIS``,
``AXIS``, ``FRAME``, ``LOAD`` or a scalar); in the ``.src``, ``DEF name( )`` ... ``END``
routines holding system-variable assignments (``$VEL.CP = 0.02``, ``$VEL_AXIS[1] =
10``, ``$TOOL = {X ..}``, ``$LOAD = {M .., CM {..}, J {..}}``), ``BAS`` calls (speeds, the
null tool and base), calls of the routines the file defines and the moves ``PTP``,
``LIN`` and ``CIRC`` to declared or inline targets with an optional approximation
(``C_DIS``, ``C_PTP``, ``C_VEL``, ``C_ORI``).  ``;`` starts a comment, ``&`` lines are
editor headers.  Anything else is refused with one line naming the file and line: this
is a check of what flexarm wrote, not a KRL interpreter (no ``IF``, loops, inline forms
or expressions).

Aggregates are read by a loop over their braces with an explicit stack: no recursion,
however deep a file nests them.  Positions stay in mm and angles in degrees, as
written; :func:`matrix_from_abc` turns ``A, B, C`` into rotation matrices.
"""

from __future__ import annotations

import re
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from ...fe.errors import ReadError
from ...fe.typing import ArrayLike, FloatArray, PathType

__all__ = ["KrlMove", "KrlProgram", "read_krl", "matrix_from_abc", "read_status_turn"]

_MOVES = ("PTP", "LIN", "CIRC")
_APPROX = ("C_DIS", "C_PTP", "C_VEL", "C_ORI")
_TOKEN = re.compile(r"\s*(?:(?P<open>\{)|(?P<close>\})|(?P<comma>,)"
                    r"|(?P<bits>'B[01]+')|(?P<word>[^\s{},]+))")
_DECL = re.compile(r"DECL\s+(?:GLOBAL\s+)?(\w+)\s+([A-Za-z_$][\w$]*)\s*=\s*(.+)\Z", re.I)
_ASSIGN = re.compile(r"(\$[\w.]+)(?:\[(\d+)\])?\s*=\s*(.+)\Z")
_BAS = re.compile(r"BAS\s*\(\s*#(\w+)\s*(?:,\s*(.*?))?\s*\)", re.I)
_MOVE = re.compile(r"(PTP|LIN|CIRC)\s+(.+?)(?:\s+(C_DIS|C_PTP|C_VEL|C_ORI))?\Z", re.I)


def matrix_from_abc(abc_deg: ArrayLike) -> FloatArray:
    """Rotation matrices ``Rz(A) Ry(B) Rx(C)`` of KUKA angles ``[A, B, C]`` (..., 3) [deg].

    Examples
    --------
    >>> (matrix_from_abc([180.0, 0.0, 180.0]).round(12) + 0.0).tolist()  # tool down
    [[-1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, -1.0]]
    """
    a, b, c = np.moveaxis(np.radians(np.asarray(abc_deg, dtype=np.float64)), -1, 0)
    ca, sa, cb, sb, cc, sc = np.cos(a), np.sin(a), np.cos(b), np.sin(b), np.cos(c), np.sin(c)
    rows = [[ca * cb, ca * sb * sc - sa * cc, ca * sb * cc + sa * sc],
            [sa * cb, sa * sb * sc + ca * cc, sa * sb * cc - ca * sc],
            [-sb, cb * sc, cb * cc]]
    return np.stack([np.stack(r, axis=-1) for r in rows], axis=-2)


@dataclass(frozen=True)
class KrlMove:
    """One move of a routine.

    Attributes
    ----------
    kind : {"PTP", "LIN", "CIRC"}
    targets : tuple
        Each a declared name (str) or an inline aggregate (dict of components).
    approx : str or None
        ``C_DIS``, ``C_PTP`` ... or None (exact stop).
    settings : dict
        The system variables in force (``"$VEL.CP"``, ``"$APO.CDIS"``, ``"$TOOL"``,
        ``"$LOAD"``, ``"$VEL_AXIS[1]"`` ...), as read.
    line : int
        Line in the ``.src``.
    """

    kind: str
    targets: tuple
    approx: str | None
    settings: dict
    line: int


@dataclass(frozen=True, eq=False)
class KrlProgram:
    """A ``.src``/``.dat`` pair.

    Attributes
    ----------
    name : str
        The main routine (the file's stem).
    data : dict
        ``.dat`` declarations: name -> (type, value); aggregates as dicts of components
        (float, int, bit strings as int, nested dicts).
    routines : dict
        Routine name -> tuple of :class:`KrlMove`, in file order (the main routine
        too when it has moves of its own).
    calls : tuple of str
        The routines the main routine calls, in order.
    main_settings : dict
        The system variables the main routine sets before its calls.
    """

    name: str
    data: dict
    routines: dict
    calls: tuple[str, ...] = ()
    main_settings: dict = field(default_factory=dict)

    def pose(self, target) -> tuple[FloatArray, FloatArray]:
        """(position (3,) [mm], rotation (3, 3)) of a declared name or inline aggregate."""
        v = self.data[target][1] if isinstance(target, str) else target
        return (np.array([v["X"], v["Y"], v["Z"]], dtype=np.float64),
                matrix_from_abc([v["A"], v["B"], v["C"]]))


def _value(text: str, where: str) -> Any:
    """A number, a bit string, a name or a ``{KEY value, ...}`` aggregate (dict)."""
    stack: list[tuple[dict, str | None]] = []
    done, key, pos = None, None, 0
    text = text.strip()
    while pos < len(text):
        m = _TOKEN.match(text, pos)
        if m is None or not m.group(0).strip():
            break
        pos = m.end()
        if m.group("open"):
            stack.append(({}, key))
            key = None
        elif m.group("close") or m.group("comma"):
            if not stack or key is not None:
                raise ReadError(f"{where}: unbalanced or incomplete aggregate '{text}'")
            if m.group("close"):
                agg, key = stack.pop()
                if not stack:
                    done = agg
                else:
                    stack[-1][0][key] = agg
                    key = None
        elif not stack:
            done = _scalar(m.group(0).strip(), where) if done is None else \
                _fail(where, text)
        elif key is None:
            key = m.group(0).strip().upper()
        else:
            stack[-1][0][key] = _scalar(m.group(0).strip(), where)
            key = None
    if stack or done is None or text[pos:].strip():
        _fail(where, text)
    return done


def _fail(where: str, text: str):
    raise ReadError(f"{where}: cannot read the value '{text}'")


def _scalar(word: str, where: str) -> Any:
    if word.startswith("'B"):
        return int(word[2:-1], 2)
    if re.fullmatch(r"[+-]?\d+", word):
        return int(word)
    try:
        return float(word)
    except ValueError:
        if re.fullmatch(r"[#$A-Za-z_][\w$.#]*", word):
            return word  # a system variable or an enumeration value: kept as written
        raise ReadError(f"{where}: '{word}' is not a number, name or aggregate") from None


def _lines(path: Path) -> list[tuple[int, str]]:
    """(line number, statement) of a KRL file, comments and editor headers dropped."""
    try:
        text = path.read_text(encoding="utf-8")
    except (OSError, UnicodeDecodeError) as exc:
        raise ReadError(f"{path}: {getattr(exc, 'strerror', None) or exc}") from None
    out = []
    for i, line in enumerate(text.splitlines(), start=1):
        s = line.split(";", 1)[0].strip()
        if s and not s.startswith("&"):
            out.append((i, s))
    return out


def _bas(settings: dict, m: re.Match, where: str) -> None:
    """A ``BAS (#WHAT, value)`` call as the system variables it sets: speeds (``#VEL_PTP``
    [%], ``#VEL_CP`` [m/s]), the null tool or base (``#TOOL``/``#BASE`` 0); the motion
    defaults (``#INITMOV``) and accelerations do not change the path.  A tool or base of
    the controller's tables is not in the files: refused."""
    what = m.group(1).upper()
    value = None if m.group(2) is None else _value(m.group(2), where)
    if what in ("INITMOV", "ACC_CP", "ACC_PTP"):
        return
    if what in ("VEL_PTP", "VEL_CP") and isinstance(value, (int, float)):
        settings.update({f"$VEL_AXIS[{i}]": float(value) for i in range(1, 7)}
                        if what == "VEL_PTP" else {"$VEL.CP": float(value)})
    elif what in ("TOOL", "BASE") and value == 0:
        settings[f"${what}"] = "$NULLFRAME"
    else:
        raise ReadError(f"{where}: unsupported call '{m.group(0)}' (flexarm reads BAS "
                        "#INITMOV, #VEL_PTP, #VEL_CP and the null #TOOL/#BASE; set $TOOL "
                        "and $BASE as frames, the controller's tables are not in the files)")


def _read_dat(path: Path) -> dict:
    data = {}
    for i, s in _lines(path):
        if re.fullmatch(r"(DEFDAT\s+\w+(\s+PUBLIC)?|ENDDAT)", s, re.I):
            continue
        m = _DECL.match(s)
        if m is None:
            raise ReadError(f"{path}, line {i}: expected 'DECL TYPE name=value', got '{s}'")
        name = m.group(2)
        if name.lower() in {k.lower() for k in data}:
            raise ReadError(f"{path}, line {i}: '{name}' is declared twice")
        data[name] = (m.group(1).upper(), _value(m.group(3), f"{path}, line {i}"))
    return data


def _targets(text: str, where: str) -> tuple:
    """The move's targets: names, or inline aggregates split at the top-level commas."""
    parts, depth, start = [], 0, 0
    for k, ch in enumerate(text):
        depth += ch == "{"
        depth -= ch == "}"
        if ch == "," and depth == 0:
            parts.append(text[start:k])
            start = k + 1
    parts.append(text[start:])
    return tuple(_value(p, where) if p.strip().startswith("{") else p.strip() for p in parts)


def _read_src(path: Path, data: dict) -> tuple[dict, dict]:
    """(routine -> moves, main routine's settings and calls)."""
    routines: dict[str, list[KrlMove]] = {}
    heads: dict[str, dict] = {}
    current, settings = None, {}
    calls: list[tuple[int, str]] = []
    known = {k.lower() for k in data}
    for i, s in _lines(path):
        where = f"{path}, line {i}"
        head = re.fullmatch(r"(?:GLOBAL\s+)?DEF\s+(\w+)\s*\(\s*\)", s, re.I)
        if head:
            if current is not None:
                raise ReadError(f"{where}: DEF {head.group(1)} inside DEF {current} (missing "
                                "END)")
            current, settings = head.group(1), {"calls": []}
            routines[current], heads[current] = [], settings
            continue
        if current is None:
            raise ReadError(f"{where}: '{s}' outside a DEF ... END routine")
        if s.upper() == "END":
            current = None
            continue
        if (m := _ASSIGN.match(s)) is not None:
            var = m.group(1).upper() + (f"[{m.group(2)}]" if m.group(2) else "")
            settings[var] = _value(m.group(3), where)
        elif (m := _MOVE.match(s)) is not None:
            targets = _targets(m.group(2), where)
            for t in targets:
                if isinstance(t, str) and t.lower() not in known:
                    raise ReadError(f"{where}: target '{t}' is not declared in {path.stem}.dat")
            want = 2 if m.group(1).upper() == "CIRC" else 1
            if len(targets) != want:
                raise ReadError(f"{where}: {m.group(1).upper()} takes {want} target(s), got "
                                f"{len(targets)}")
            routines[current].append(KrlMove(m.group(1).upper(), targets, m.group(3),
                                             {k: v for k, v in settings.items()
                                              if k != "calls"}, i))
        elif (m := _BAS.fullmatch(s)) is not None:
            _bas(settings, m, where)
        elif (m := re.fullmatch(r"(\w+)\s*\(\s*\)", s)) is not None:
            settings["calls"].append(m.group(1))
            calls.append((i, m.group(1)))
        else:
            raise ReadError(f"{where}: unsupported KRL statement '{s}' (flexarm reads the "
                            "moves, assignments and calls it writes)")
    if current is not None:
        raise ReadError(f"{path}: DEF {current} has no END")
    defined = {k.lower() for k in routines}
    for i, name in calls:
        if name.lower() not in defined:
            raise ReadError(f"{path}, line {i}: {name}( ) is not a DEF of {path.name} "
                            "(flexarm reads one .src: the moves of other files are unknown)")
    return routines, heads


def read_krl(path: PathType) -> KrlProgram:
    """Read a ``.src`` and the ``.dat`` beside it.

    Raises
    ------
    ReadError
        A missing file or a statement outside the subset, naming the file and line.

    Examples
    --------
    >>> import tempfile, pathlib
    >>> from flexarm.robot.formats.krl import write_krl
    >>> from flexarm.robot.formats.rapid import read_rapid
    >>> from flexarm.studies.contact.loaded_circle import THESIS_RAPID
    >>> out = pathlib.Path(tempfile.mkdtemp()) / "thesis.src"
    >>> _ = write_krl(out, read_rapid(THESIS_RAPID), ["Path_30"])
    >>> prog = read_krl(out)
    >>> [m.kind for m in prog.routines["Path_30"]], prog.pose("Target_70")[0].tolist()
    (['PTP', 'CIRC', 'CIRC'], [1488.34, 47.78, 588.13])
    """
    path = Path(path)
    data = _read_dat(path.with_suffix(".dat"))
    routines, heads = _read_src(path, data)
    main = next((k for k in routines if k.lower() == path.stem.lower()), None)
    if main is None:
        raise ReadError(f"{path}: no main routine DEF {path.stem}( )")
    settings = {k: v for k, v in heads[main].items() if k != "calls"}
    # the main routine is a routine of its own only when it moves the arm itself
    return KrlProgram(main, data, {k: tuple(v) for k, v in routines.items()
                                   if k != main or v},
                      tuple(heads[main]["calls"]), settings)


_STATUS_DECL = re.compile(r"^\s*DECL\s+(?:E6POS|POS)\s+([A-Za-z_$][\w$]*)\s*=\s*\{([^}]*)\}",
                          re.IGNORECASE | re.MULTILINE)


def read_status_turn(path: PathType) -> dict[str, tuple[int, int]]:
    """Lower-case name -> ``(S, T)`` of every ``E6POS``/``POS`` declaration of a ``.dat``
    that gives them (a template: the configurations taught on the controller, whatever
    else the file declares).

    Examples
    --------
    >>> import tempfile, pathlib
    >>> p = pathlib.Path(tempfile.mkdtemp()) / "t.dat"
    >>> _ = p.write_text("DEFDAT t\\nDECL E6POS XP1={X 1,Y 2,Z 3,A 0,B 0,C 0,S 6,T 'B100011'}\\n")
    >>> read_status_turn(p)
    {'xp1': (6, 35)}
    """
    try:
        text = Path(path).read_text(encoding="utf-8", errors="replace")
    except OSError as exc:
        raise ReadError(f"{path}: {exc.strerror or exc}") from None
    out = {}
    for m in _STATUS_DECL.finditer(text):
        parts = dict(re.findall(r"\b([ST])\s+('B[01]+'|\d+)", m.group(2), re.IGNORECASE))
        parts = {k.upper(): int(v[2:-1], 2) if v.startswith("'") else int(v)
                 for k, v in parts.items()}
        if "S" in parts and "T" in parts:
            out[m.group(1).lower()] = (parts["S"], parts["T"])
    return out
