"""ABB RAPID modules: robtargets and Move instructions (``read(path)``, ``write(path, module)``).

A small reader for the part of RAPID that describes a robot path: ``MODULE`` /
``ENDMODULE``, ``!`` comments, ``CONST``/``PERS``/``VAR`` data declarations
(``robtarget`` and ``jointtarget`` are checked and turned into dataclasses; ``num``
values can be used in expressions; ``tooldata``, ``wobjdata``, ``speeddata``,
``zonedata`` and any other type are kept as plain nested tuples) and ``PROC`` routines
made of ``MoveL``, ``MoveJ``, ``MoveC`` and ``MoveAbsJ``.  Targets may be written
inline or with ``Offs(p, dx, dy, dz)`` and ``RelTool(p, dx, dy, dz [\\Rx] [\\Ry] [\\Rz])``.
``FUNC`` and ``TRAP`` routines are skipped.  Any other instruction raises
:class:`~flexarm.fe.errors.ReadError` naming the file and line.

Frames and units follow RAPID: positions are in mm in the work-object frame given by
the instruction's ``\\WObj`` (``wobj0`` = robot base frame when the robot is not
mounted elsewhere); quaternions are ``[q1, q2, q3, q4] = [w, x, y, z]`` (scalar first);
joint targets are in degrees.  RAPID is case-insensitive: names are looked up
without regard to case and kept as written.
"""

from __future__ import annotations

import logging
import re
from collections.abc import Mapping
from dataclasses import dataclass, field
from pathlib import Path
from types import MappingProxyType
from typing import Any

import numpy as np

from ...fe.errors import ReadError
from ...fe.files import atomic_path
from ...fe.tolerances import tol
from ...fe.typing import ArrayLike, FloatArray, IntArray, PathType

__all__ = [
    "RobTarget",
    "JointTarget",
    "Declaration",
    "Motion",
    "Procedure",
    "RapidModule",
    "SUPPORTED_INSTRUCTIONS",
    "EXTAX_UNUSED",
    "read_rapid",
    "write_rapid",
    "quadrant",
    "decode_cfx",
    "read",
    "write",
]

logger = logging.getLogger(__name__)

#: RAPID's value for an external axis that is not in use.
EXTAX_UNUSED = 9e9
#: Instructions this reader turns into :class:`Motion` objects.
SUPPORTED_INSTRUCTIONS = ("MoveL", "MoveJ", "MoveC", "MoveAbsJ")
#: Largest accepted | |q| - 1 | of a robtarget orientation (RAPID rejects unnormalised ones).


#: Positional arguments and allowed optional arguments (with the positional argument
#: each optional one follows, -1 = before the first) of every supported instruction.
_SIGNATURES: dict[str, tuple[tuple[str, ...], dict[str, int]]] = {
    "MoveL": (("ToPoint", "Speed", "Zone", "Tool"),
              {"Conc": -1, "ID": 0, "V": 1, "T": 1, "Z": 2, "Inpos": 2, "WObj": 3, "Corr": 3,
               "TLoad": 3}),
    "MoveJ": (("ToPoint", "Speed", "Zone", "Tool"),
              {"Conc": -1, "ID": 0, "V": 1, "T": 1, "Z": 2, "Inpos": 2, "WObj": 3, "TLoad": 3}),
    "MoveC": (("CirPoint", "ToPoint", "Speed", "Zone", "Tool"),
              {"Conc": -1, "ID": 1, "V": 2, "T": 2, "Z": 3, "Inpos": 3, "WObj": 4, "Corr": 4,
               "TLoad": 4}),
    "MoveAbsJ": (("ToJointPos", "Speed", "Zone", "Tool"),
                 {"Conc": -1, "ID": 0, "NoEOffs": 0, "V": 1, "T": 1, "Z": 2, "Inpos": 2,
                  "WObj": 3, "TLoad": 3}),
}
_N_TARGETS = {"MoveL": 1, "MoveJ": 1, "MoveC": 2, "MoveAbsJ": 1}
_FUNCTIONS = ("Offs", "RelTool")
_ROBTARGET_FORM = "[[x,y,z],[q1,q2,q3,q4],[cf1,cf4,cf6,cfx],[eax_a,...,eax_f]]"
_JOINTTARGET_FORM = "[[rax_1,...,rax_6],[eax_a,...,eax_f]]"


def _frozen(a: ArrayLike, dtype) -> np.ndarray:
    arr = np.array(a, dtype=dtype)
    arr.setflags(write=False)
    return arr


@dataclass(frozen=True, eq=False)
class RobTarget:
    """A RAPID ``robtarget``: a TCP pose with configuration and external axes.

    Parameters
    ----------
    name : str
        Data name as written in the module (or the expression text for inline targets).
    pos_mm : (3,) float
        TCP position [mm] in the work-object frame.
    quat : (4,) float
        Tool orientation in the work-object frame, ``[w, x, y, z]`` (RAPID ``q1..q4``),
        exactly as written (not renormalised).
    conf : (4,) int
        Configuration ``[cf1, cf4, cf6, cfx]``: quadrants of axes 1, 4 and 6 and the
        arm-configuration number (see :mod:`flexarm.assembly.paths` for its meaning).
    extax : (6,) float
        External axes a–f [mm or deg]; :data:`EXTAX_UNUSED` (9E9) when not used.

    Examples
    --------
    >>> p = RobTarget("p", [1000, 0, 500], [1, 0, 0, 0], [0, 0, 0, 1], [9e9] * 6)
    >>> p.pos_mm.tolist(), p.conf.tolist(), bool(p.is_extax_used.any())
    ([1000.0, 0.0, 500.0], [0, 0, 0, 1], False)
    """

    name: str
    pos_mm: FloatArray
    quat: FloatArray
    conf: IntArray
    extax: FloatArray

    def __post_init__(self) -> None:
        for attr, shape, dtype in (("pos_mm", (3,), np.float64), ("quat", (4,), np.float64),
                                   ("conf", (4,), np.int64), ("extax", (6,), np.float64)):
            arr = _frozen(getattr(self, attr), dtype)
            if arr.shape != shape:
                raise ValueError(f"RobTarget.{attr} must have shape {shape}, got {arr.shape}")
            object.__setattr__(self, attr, arr)

    @property
    def is_extax_used(self) -> np.ndarray:
        """(6,) bool: external axes with a value (not 9E9)."""
        return self.extax < EXTAX_UNUSED * (1 - 1e-6)

    def renamed(self, name: str) -> RobTarget:
        """The same target under another name."""
        return RobTarget(name, self.pos_mm, self.quat, self.conf, self.extax)


@dataclass(frozen=True, eq=False)
class JointTarget:
    """A RAPID ``jointtarget``: robot axes [deg] and external axes.

    Parameters
    ----------
    name : str
    joints_deg : (6,) float
        Robot axes 1–6 [deg].
    extax : (6,) float
        External axes a–f; 9E9 when not used.
    """

    name: str
    joints_deg: FloatArray
    extax: FloatArray

    def __post_init__(self) -> None:
        for attr in ("joints_deg", "extax"):
            arr = _frozen(getattr(self, attr), np.float64)
            if arr.shape != (6,):
                raise ValueError(f"JointTarget.{attr} must have shape (6,), got {arr.shape}")
            object.__setattr__(self, attr, arr)


@dataclass(frozen=True)
class Declaration:
    """Any other data declaration (``tooldata``, ``wobjdata``, ``speeddata``, ``num``, ...).

    ``value`` is the literal as nested tuples of float, bool and str (``None`` when the
    declaration has no initial value).
    """

    storage: str
    type: str
    name: str
    value: Any
    line: int


Target = RobTarget | JointTarget


@dataclass(frozen=True)
class Motion:
    """One Move instruction.

    Parameters
    ----------
    kind : {"MoveL", "MoveJ", "MoveC", "MoveAbsJ"}
    targets : tuple of RobTarget or JointTarget
        ``(ToPoint,)``, or ``(CirPoint, ToPoint)`` for ``MoveC``, or ``(ToJointPos,)``.
    speed, zone, tool : str
        The arguments as written (``"v10"``, ``"fine"``, ``"tool0"``).
    wobj : str or None
        ``\\WObj`` argument (``None``: ``wobj0``, the robot base frame).
    options : tuple of (str, str or None)
        The other optional arguments, e.g. ``(("Conc", None),)``.
    line : int
        Line of the instruction in the file (1-based).
    """

    kind: str
    targets: tuple[Target, ...]
    speed: str
    zone: str
    tool: str
    wobj: str | None
    options: tuple[tuple[str, str | None], ...]
    line: int

    @property
    def to_point(self) -> Target:
        """The destination (``ToPoint`` or ``ToJointPos``)."""
        return self.targets[-1]

    @property
    def cir_point(self) -> RobTarget | None:
        """The circle point of a ``MoveC`` (``None`` otherwise)."""
        return self.targets[0] if self.kind == "MoveC" else None

    @property
    def is_fine(self) -> bool:
        """True if the motion stops at its destination (zone ``fine``)."""
        return self.zone.lower() == "fine"


@dataclass(frozen=True)
class Procedure:
    """A ``PROC`` routine: its name, motions in program order and first line."""

    name: str
    motions: tuple[Motion, ...]
    line: int


@dataclass(frozen=True, eq=False)
class RapidModule:
    """A parsed RAPID module.

    Parameters
    ----------
    name : str
    targets : mapping of str to RobTarget
        Module-level robtargets in file order.
    procedures : mapping of str to Procedure
        In file order.
    joint_targets : mapping of str to JointTarget
    data : mapping of str to Declaration
        Every other module-level declaration.
    path : str
        File it was read from ("" if built in memory).
    """

    name: str
    targets: Mapping[str, RobTarget]
    procedures: Mapping[str, Procedure]
    joint_targets: Mapping[str, JointTarget] = field(default_factory=dict)
    data: Mapping[str, Declaration] = field(default_factory=dict)
    path: str = ""

    def __post_init__(self) -> None:
        for attr in ("targets", "procedures", "joint_targets", "data"):
            object.__setattr__(self, attr, MappingProxyType(dict(getattr(self, attr))))

    def procedure(self, name: str) -> Procedure:
        """Procedure by name (case-insensitive); ``KeyError`` lists the known ones."""
        for key, proc in self.procedures.items():
            if key.lower() == name.lower():
                return proc
        raise KeyError(f"no procedure '{name}' in module {self.name} "
                       f"(known: {', '.join(self.procedures)})")


def quadrant(angle_deg: ArrayLike) -> IntArray:
    """RAPID configuration quadrant of a rotating axis: ``floor(angle / 90 deg)``.

    ``0`` for [0, 90) deg, ``1`` for [90, 180), ``-1`` for [-90, 0), ``-2`` for
    [-180, -90), and so on beyond one turn.  ``cf1``, ``cf4`` and ``cf6`` are the quadrants
    of axes 1, 4 and 6.  (Exactly at a boundary the controller accepts either side.)

    Examples
    --------
    >>> quadrant([0.0, 45.0, 90.0, -10.0, -135.0, 200.0]).tolist()
    [0, 0, 1, -1, -2, 2]
    """
    return np.floor(np.asarray(angle_deg, dtype=np.float64) / 90.0).astype(np.int64)


def decode_cfx(cfx: int) -> dict[str, bool]:
    """Meaning of ``cfx`` (0..7) for ABB 6-axis serial arms such as the IRB 4600.

    Bit 2 set: wrist centre *behind* axis 1; bit 1 set: wrist centre *behind* the lower
    arm (the line through axes 2 and 3); bit 0 set: axis 5 angle *negative*.

    Returns
    -------
    dict
        ``wrist_in_front_of_axis1``, ``wrist_in_front_of_lower_arm``, ``axis5_positive``.

    Examples
    --------
    >>> decode_cfx(1)
    {'wrist_in_front_of_axis1': True, 'wrist_in_front_of_lower_arm': True, 'axis5_positive': False}
    """
    if int(cfx) != cfx or not 0 <= cfx <= 7:
        raise ValueError(f"cfx must be an integer in 0..7, got {cfx}")
    cfx = int(cfx)
    return {"wrist_in_front_of_axis1": not cfx & 4, "wrist_in_front_of_lower_arm": not cfx & 2,
            "axis5_positive": not cfx & 1}


# ----------------------------------------------------------------------------- tokens

@dataclass(frozen=True)
class _Tok:
    kind: str  # "name", "num", "str", "op", "eof"
    text: str
    line: int


_TOKEN_RE = re.compile(
    r"(?P<ws>[ \t\r\f\v]+)|(?P<nl>\n)|(?P<comment>![^\n]*)"
    r"|(?P<str>\"(?:[^\"\n]|\"\")*\")"
    r"|(?P<num>(?:\d+\.?\d*|\.\d+)(?:[eE][+-]?\d+)?)"
    r"|(?P<name>[A-Za-z_][A-Za-z0-9_]*)"
    r"|(?P<op>:=|<>|<=|>=|[\[\](){},;:\\+\-*/=<>])"
)
_HEADER_RE = re.compile(r"\s*%%%.*?%%%", re.DOTALL)  # old "%%% VERSION:1 ... %%%" header


def _tokenize(text: str, file: str) -> list[_Tok]:
    toks: list[_Tok] = []
    line = 1
    pos = 0
    header = _HEADER_RE.match(text)
    if header:
        line += header.group(0).count("\n")
        pos = header.end()
    while pos < len(text):
        m = _TOKEN_RE.match(text, pos)
        if m is None:
            raise ReadError(f"{file}, line {line}: unexpected character {text[pos]!r}")
        kind = m.lastgroup
        if kind == "nl":
            line += 1
        elif kind in ("str", "num", "name", "op"):
            toks.append(_Tok(kind, m.group(0), line))
        pos = m.end()
    toks.append(_Tok("eof", "", toks[-1].line if toks else line))  # errors at end of text
    return toks


# ----------------------------------------------------------------------------- parser

class _Parser:
    """Recursive descent over the token list; ``scope`` maps lower-case names to values."""

    def __init__(self, toks: list[_Tok], file: str, scope: dict[str, Any], ignore: set[str]):
        self.toks = toks
        self.i = 0
        self.file = file
        self.scope = scope
        self.ignore = ignore

    # -- helpers
    def peek(self, k: int = 0) -> _Tok:
        return self.toks[min(self.i + k, len(self.toks) - 1)]

    def next(self) -> _Tok:
        tok = self.peek()
        self.i = min(self.i + 1, len(self.toks) - 1)
        return tok

    def error(self, msg: str, line: int | None = None) -> ReadError:
        return ReadError(f"{self.file}, line {self.peek().line if line is None else line}: {msg}")

    def is_kw(self, *words: str, k: int = 0) -> bool:
        tok = self.peek(k)
        return tok.kind == "name" and tok.text.upper() in words

    def expect(self, text: str, what: str = "") -> _Tok:
        tok = self.next()
        if tok.text.upper() != text.upper() or tok.kind not in ("op", "name"):
            got = tok.text or "end of file"
            raise self.error(f"expected '{text}'{what}, got '{got}'", tok.line)
        return tok

    def name(self, what: str) -> _Tok:
        tok = self.next()
        if tok.kind != "name":
            raise self.error(f"expected {what}, got '{tok.text or 'end of file'}'", tok.line)
        return tok

    # -- module
    def module(self) -> RapidModule:
        self.expect("MODULE")
        mod_name = self.name("a module name").text
        if self.peek().text == "(":  # MODULE m(SYSMODULE, NOVIEW)
            while self.next().text != ")":
                if self.peek().kind == "eof":
                    raise self.error("unclosed module attribute list")
        targets: dict[str, RobTarget] = {}
        joint_targets: dict[str, JointTarget] = {}
        data: dict[str, Declaration] = {}
        procs: dict[str, Procedure] = {}
        while True:
            tok = self.peek()
            if tok.kind == "eof":
                raise self.error(f"missing ENDMODULE for MODULE {mod_name}")
            word = tok.text.upper() if tok.kind == "name" else ""
            if word == "ENDMODULE":
                self.next()
                if self.peek().kind != "eof":
                    raise self.error(f"unexpected '{self.peek().text}' after ENDMODULE")
                break
            if word in ("LOCAL", "TASK"):
                self.next()
                continue
            if word in ("CONST", "PERS", "VAR"):
                decl = self.declaration()
                key = decl.name.lower()
                if key in self.scope:
                    raise self.error(f"'{decl.name}' is declared twice", decl.line)
                self.scope[key] = decl.value
                if isinstance(decl.value, RobTarget):
                    targets[decl.name] = decl.value
                elif isinstance(decl.value, JointTarget):
                    joint_targets[decl.name] = decl.value
                else:
                    data[decl.name] = decl
            elif word == "PROC":
                proc = self.procedure()
                if proc.name.lower() in {p.lower() for p in procs}:
                    raise self.error(f"PROC '{proc.name}' is defined twice", proc.line)
                procs[proc.name] = proc
            elif word in ("FUNC", "TRAP"):
                self.skip_routine(word)
            else:
                raise self.error(f"unexpected '{tok.text}' at module level (expected a data "
                                 "declaration, PROC or ENDMODULE)")
        return RapidModule(mod_name, targets, procs, joint_targets, data, self.file)

    def skip_routine(self, word: str) -> None:
        start = self.next()
        end = "END" + word
        while not self.is_kw(end):
            if self.peek().kind == "eof":
                raise self.error(f"missing {end} for the {word} on line {start.line}", start.line)
            self.next()
        self.next()
        logger.info("%s, line %d: skipped a %s routine", self.file, start.line, word)

    # -- declarations
    def declaration(self) -> Declaration:
        storage = self.next()
        type_name = self.name("a data type").text
        name_tok = self.name("a data name")
        if self.peek().text == "{":
            raise self.error(f"array declarations are not supported ('{name_tok.text}')")
        value: Any = None
        if self.peek().text == ":=":
            self.next()
            value = self.expression()
        tok = self.next()
        if tok.text != ";":
            raise self.error(f"expected ';' after the declaration of '{name_tok.text}', "
                             f"got '{tok.text or 'end of file'}'", tok.line)
        kind = type_name.lower()
        if value is None and storage.text.upper() != "CONST":
            pass  # VAR/PERS without an initial value: kept as a Declaration, error on use
        elif value is None and kind not in ("robtarget", "jointtarget"):
            raise self.error(f"CONST '{name_tok.text}' has no value", name_tok.line)
        elif kind == "robtarget":
            value = self.robtarget(name_tok.text, value, name_tok.line)
        elif kind == "jointtarget":
            value = self.jointtarget(name_tok.text, value, name_tok.line)
        elif kind == "num" and value is not None and not isinstance(value, float):
            raise self.error(f"num '{name_tok.text}' must be a number", name_tok.line)
        elif isinstance(value, (RobTarget, JointTarget)):
            raise self.error(f"'{name_tok.text}' of type {type_name} cannot hold a target",
                             name_tok.line)
        else:
            value = _tuples(value)
        return Declaration(storage.text.upper(), type_name, name_tok.text, value, name_tok.line)

    def robtarget(self, name: str, value: Any, line: int) -> RobTarget:
        if isinstance(value, RobTarget):
            return value.renamed(name)
        if value is None:
            raise self.error(f"robtarget '{name}' has no value (expected := {_ROBTARGET_FORM})",
                             line)
        shape = _shape(value)
        if shape != [3, 4, 4, 6] or not _all_numbers(value):
            raise self.error(f"malformed robtarget '{name}': expected {_ROBTARGET_FORM}, "
                             f"got {_describe(value)}", line)
        pos, quat, conf, extax = (np.asarray(v, dtype=np.float64) for v in value)
        if np.any(conf != np.round(conf)):
            raise self.error(f"malformed robtarget '{name}': configuration data "
                             f"{_fmt_list(conf)} must be integers", line)
        norm = float(np.linalg.norm(quat))
        if abs(norm - 1.0) > tol.quaternion_norm:
            raise self.error(f"malformed robtarget '{name}': orientation {_fmt_list(quat)} is not "
                             f"a unit quaternion (|q| = {norm:.6g})", line)
        return RobTarget(name, pos, quat, conf.astype(np.int64), extax)

    def jointtarget(self, name: str, value: Any, line: int) -> JointTarget:
        if isinstance(value, JointTarget):
            return JointTarget(name, value.joints_deg, value.extax)
        if value is None or _shape(value) != [6, 6] or not _all_numbers(value):
            raise self.error(f"malformed jointtarget '{name}': expected {_JOINTTARGET_FORM}, "
                             f"got {_describe(value)}", line)
        return JointTarget(name, value[0], value[1])

    # -- expressions: numbers, strings, TRUE/FALSE, aggregates, data names, Offs, RelTool
    def expression(self) -> Any:
        value = self.term()
        while self.peek().text in ("+", "-"):
            op = self.next()
            value = self.arith(op, value, self.term())
        return value

    def term(self) -> Any:
        value = self.factor()
        while self.peek().text in ("*", "/"):
            op = self.next()
            value = self.arith(op, value, self.factor())
        return value

    def arith(self, op: _Tok, a: Any, b: Any) -> float:
        if not (isinstance(a, float) and isinstance(b, float)):
            raise self.error(f"'{op.text}' is only supported between numbers", op.line)
        if op.text == "+":
            return a + b
        if op.text == "-":
            return a - b
        if op.text == "*":
            return a * b
        if b == 0.0:
            raise self.error("division by zero", op.line)
        return a / b

    def factor(self) -> Any:
        tok = self.next()
        if tok.text in ("-", "+") and tok.kind == "op":
            value = self.factor()
            if not isinstance(value, float):
                raise self.error(f"unary '{tok.text}' needs a number", tok.line)
            return -value if tok.text == "-" else value
        if tok.kind == "num":
            return float(tok.text)
        if tok.kind == "str":
            return tok.text[1:-1].replace('""', '"')
        if tok.text == "(":
            value = self.expression()
            self.expect(")")
            return value
        if tok.text == "[":
            items = [self.expression()]
            while self.peek().text == ",":
                self.next()
                items.append(self.expression())
            self.expect("]", " to close the aggregate")
            return items
        if tok.kind == "name":
            upper = tok.text.upper()
            if upper in ("TRUE", "FALSE"):
                return upper == "TRUE"
            if self.peek().text == "(":
                return self.call(tok)
            key = tok.text.lower()
            if key not in self.scope:
                raise self.error(f"unknown data '{tok.text}'", tok.line)
            if self.scope[key] is None:
                raise self.error(f"'{tok.text}' is declared without a value", tok.line)
            return self.scope[key]
        raise self.error(f"unexpected '{tok.text or 'end of file'}' in an expression", tok.line)

    def call(self, func: _Tok) -> RobTarget:
        names = {f.lower(): f for f in _FUNCTIONS}
        if func.text.lower() not in names:
            raise self.error(f"unsupported function '{func.text}' "
                             f"(supported: {', '.join(_FUNCTIONS)})", func.line)
        fname = names[func.text.lower()]
        self.expect("(")
        start = self.i
        args = [self.expression()]
        opts: dict[str, float] = {}
        while self.peek().text in (",", "\\"):
            if self.next().text == "\\":
                opt = self.name("an optional argument name").text
                self.expect(":=")
                opts[opt.lower()] = self.expression()
            else:
                args.append(self.expression())
        text = " ".join(t.text for t in self.toks[start:self.i])
        self.expect(")", f" to close {fname}(")
        if (len(args) != 4 or not isinstance(args[0], RobTarget)
                or not all(isinstance(a, float) for a in args[1:])):
            raise self.error(f"{fname} expects (robtarget, dx, dy, dz)", func.line)
        allowed = {"rx", "ry", "rz"} if fname == "RelTool" else set()
        bad = sorted(set(opts) - allowed)
        if bad or not all(isinstance(v, float) for v in opts.values()):
            raise self.error(f"unsupported optional argument '\\{bad[0] if bad else ''}' "
                             f"of {fname}", func.line)
        p: RobTarget = args[0]
        d = np.array(args[1:], dtype=np.float64)
        if fname == "Offs":
            return RobTarget(f"Offs({text})", p.pos_mm + d, p.quat, p.conf, p.extax)
        from ..paths import quat_from_intrinsic_xyz, quat_multiply, quat_to_matrix

        pos = p.pos_mm + quat_to_matrix(p.quat) @ d
        turn = quat_from_intrinsic_xyz([opts.get(a, 0.0) for a in ("rx", "ry", "rz")])
        return RobTarget(f"RelTool({text})", pos, quat_multiply(p.quat, turn), p.conf, p.extax)

    # -- procedures
    def procedure(self) -> Procedure:
        start = self.expect("PROC")
        name = self.name("a procedure name").text
        self.expect("(", f" after PROC {name}")
        if self.peek().text != ")":
            raise self.error(f"PROC {name}: procedures with parameters are not supported")
        self.expect(")")
        outer = self.scope
        self.scope = dict(outer)  # routine data shadow module data
        motions: list[Motion] = []
        local: set[str] = set()
        while True:
            tok = self.peek()
            if tok.kind == "eof" or self.is_kw("ENDMODULE", "PROC"):
                raise self.error(f"missing ENDPROC for PROC {name} (line {start.line})")
            word = tok.text.upper() if tok.kind == "name" else ""
            if word == "ENDPROC":
                self.next()
                break
            if word in ("CONST", "PERS", "VAR"):
                decl = self.declaration()
                if decl.name.lower() in local:
                    raise self.error(f"'{decl.name}' is declared twice", decl.line)
                local.add(decl.name.lower())
                self.scope[decl.name.lower()] = decl.value
                continue
            motions.append(self.instruction())
            if motions[-1] is None:
                motions.pop()
        self.scope = outer
        return Procedure(name, tuple(motions), start.line)

    def instruction(self) -> Motion | None:
        tok = self.next()
        if tok.kind != "name":
            raise self.error(f"unexpected '{tok.text}' (expected an instruction)", tok.line)
        if self.peek().text == ":=":
            raise self.error(f"unsupported statement: assignment to '{tok.text}' (supported "
                             f"instructions: {', '.join(SUPPORTED_INSTRUCTIONS)})", tok.line)
        kinds = {k.lower(): k for k in SUPPORTED_INSTRUCTIONS}
        if tok.text.lower() in self.ignore:
            while self.next().text != ";":
                if self.peek().kind == "eof":
                    raise self.error(f"missing ';' after {tok.text}", tok.line)
            logger.info("%s, line %d: ignored %s", self.file, tok.line, tok.text)
            return None
        if tok.text.lower() not in kinds:
            raise self.error(f"unsupported instruction '{tok.text}' "
                             f"(supported: {', '.join(SUPPORTED_INSTRUCTIONS)})", tok.line)
        return self.motion(kinds[tok.text.lower()], tok.line)

    def arguments(self, instr: str, line: int) -> tuple[list[list[_Tok]], list[tuple]]:
        """Split ``arg, arg \\Opt:=x, ...;`` into positional token runs and optional args."""
        positional: list[list[_Tok]] = []
        optional: list[tuple[str, list[_Tok] | None, int]] = []
        while True:
            tok = self.peek()
            if tok.text == ";":
                self.next()
                return positional, optional
            if tok.kind == "eof" or self.is_kw("ENDPROC", "ENDMODULE"):
                raise self.error(f"missing ';' at the end of {instr}", line)
            if tok.text == "\\":
                self.next()
                opt = self.name("an optional argument name after '\\'").text
                value = None
                if self.peek().text == ":=":
                    self.next()
                    value = self.run()
                optional.append((opt, value, len(positional) - 1))
            else:
                run = self.run()
                if not run:
                    raise self.error(f"empty argument in {instr}", line)
                _check_commas(self, run)
                positional.append(run)
            if self.peek().text == ",":
                self.next()

    def run(self) -> list[_Tok]:
        """Tokens of one argument: up to ',', '\\' or ';' outside brackets."""
        out: list[_Tok] = []
        depth = 0
        while True:
            tok = self.peek()
            if tok.kind == "eof" or (depth == 0 and tok.text in (",", "\\", ";")):
                return out
            if depth == 0 and self.is_kw("ENDPROC", "ENDMODULE"):
                return out
            depth += tok.text in ("[", "(") and tok.kind == "op"
            depth -= tok.text in ("]", ")") and tok.kind == "op"
            out.append(self.next())

    def evaluate(self, run: list[_Tok]) -> Any:
        sub = _Parser(run + [_Tok("eof", "", run[-1].line)], self.file, self.scope, self.ignore)
        value = sub.expression()
        if sub.peek().kind != "eof":
            raise self.error(f"unexpected '{sub.peek().text}' in an argument", sub.peek().line)
        return value

    def motion(self, kind: str, line: int) -> Motion:
        names, allowed = _SIGNATURES[kind]
        positional, optional = self.arguments(kind, line)
        if len(positional) != len(names):
            raise self.error(f"{kind} expects {len(names)} arguments ({', '.join(names)}), "
                             f"got {len(positional)}", line)
        allowed_l = {k.lower(): k for k in allowed}
        wobj = None
        options: list[tuple[str, str | None]] = []
        for opt, value, _after in optional:
            if opt.lower() not in allowed_l:
                raise self.error(f"unknown optional argument '\\{opt}' for {kind} "
                                 f"(allowed: {', '.join(allowed)})", line)
            text = None if value is None else "".join(t.text for t in value)
            if opt.lower() == "wobj":
                wobj = text
            else:
                options.append((allowed_l[opt.lower()], text))
        targets: list[Target] = []
        for k in range(_N_TARGETS[kind]):
            run = positional[k]
            value = self.evaluate(run)
            text = "".join(t.text for t in run)
            if kind == "MoveAbsJ":
                if isinstance(value, list):
                    value = self.jointtarget(text, value, run[0].line)
                if not isinstance(value, JointTarget):
                    raise self.error(f"{kind}: {names[k]} '{text}' is not a jointtarget", line)
            else:
                if isinstance(value, list):
                    value = self.robtarget(text, value, run[0].line)
                if not isinstance(value, RobTarget):
                    raise self.error(f"{kind}: {names[k]} '{text}' is not a robtarget", line)
            targets.append(value)
        speed, zone, tool = ("".join(t.text for t in run) for run in positional[-3:])
        return Motion(kind, tuple(targets), speed, zone, tool, wobj, tuple(options), line)


def _check_commas(parser: _Parser, run: list[_Tok]) -> None:
    """Two operands side by side at bracket depth 0 mean a missing comma."""
    depth = 0
    for prev, tok in zip(run, run[1:], strict=False):
        depth += prev.text in ("[", "(") and prev.kind == "op"
        depth -= prev.text in ("]", ")") and prev.kind == "op"
        ends = prev.kind in ("name", "num", "str") or (prev.kind == "op" and prev.text in "])")
        starts = tok.kind in ("name", "num", "str") or (tok.kind == "op" and tok.text == "[")
        if depth == 0 and ends and starts:
            raise parser.error(f"expected ',' between '{prev.text}' and '{tok.text}'", tok.line)


def _tuples(value: Any) -> Any:
    return tuple(_tuples(v) for v in value) if isinstance(value, list) else value


def _shape(value: Any) -> list[int] | None:
    if not isinstance(value, list) or not all(isinstance(v, list) for v in value):
        return None
    return [len(v) for v in value]


def _all_numbers(value: list) -> bool:
    return all(isinstance(x, float) for v in value for x in v)


def _fmt_list(a: np.ndarray) -> str:
    return "[" + ",".join(_num(x) for x in a) + "]"


def _describe(value: Any) -> str:
    if value is None:
        return "no value"
    if isinstance(value, list):
        return "[" + ",".join(_describe(v) if isinstance(v, list) else
                              (_num(v) if isinstance(v, float) else repr(v)) for v in value) + "]"
    return repr(value)


def _num(x: float) -> str:
    """RAPID literal of a number that reads back to the same float."""
    x = float(x)
    if x == EXTAX_UNUSED:
        return "9E+09"
    if x.is_integer() and abs(x) < 1e15:
        return str(int(x))
    return repr(x)


# ----------------------------------------------------------------------------- public API

def read_rapid(path: PathType, ignore: tuple[str, ...] = ()) -> RapidModule:
    """Read a RAPID module (``.mod``/``.modx``/``.prg``).

    Parameters
    ----------
    path : str or path-like
        The module file (UTF-8 or Latin-1 text).
    ignore : tuple of str, optional
        Instruction names to skip silently (logged), e.g. ``("ConfL", "SingArea")``.
        Every other instruction outside :data:`SUPPORTED_INSTRUCTIONS` is an error.

    Returns
    -------
    RapidModule
        Robtargets, joint targets, other data and procedures.  Positions in mm in the
        work-object frame; quaternions ``[w, x, y, z]``.

    Raises
    ------
    ReadError
        Naming the file and line: syntax errors, malformed robtargets (wrong shape,
        non-integer configuration, non-unit quaternion), unknown data, unsupported
        instructions, functions or array declarations.

    Examples
    --------
    >>> from importlib.resources import files
    >>> mod = read_rapid(files("flexarm") / "data" / "rapid" / "ldbb_thesis.mod")
    >>> len(mod.targets), list(mod.procedures)[:3]
    (24, ['main', 'Path_10', 'Path_20'])
    >>> mod.procedure("path_30").motions[1].kind
    'MoveC'
    """
    path = Path(path)
    logger.info("reading RAPID module %s", path)
    try:
        raw = path.read_bytes()
    except OSError as exc:
        raise ReadError(f"{path}: cannot read the file ({exc.strerror})") from exc
    try:
        text = raw.decode("utf-8")
    except UnicodeDecodeError:
        text = raw.decode("latin-1")
    toks = _tokenize(text, str(path))
    ignored = {name.lower() for name in ignore}
    parser = _Parser(toks, str(path), {}, ignored)
    if not parser.is_kw("MODULE"):
        raise parser.error(f"expected 'MODULE', got '{parser.peek().text or 'end of file'}'")
    module = parser.module()
    logger.info("read RAPID module %s: %d robtargets, %d procedures", module.name,
                len(module.targets), len(module.procedures))
    return module


def _literal(value: Any) -> str:
    if isinstance(value, bool):
        return "TRUE" if value else "FALSE"
    if isinstance(value, float):
        return _num(value)
    if isinstance(value, str):
        return '"' + value.replace('"', '""') + '"'
    return "[" + ",".join(_literal(v) for v in value) + "]"


def _target_literal(t: Target) -> str:
    if isinstance(t, JointTarget):
        return _literal([list(t.joints_deg), list(t.extax)])
    return _literal([list(t.pos_mm), list(t.quat), [float(c) for c in t.conf], list(t.extax)])


def _motion_text(m: Motion, named: Mapping[str, Target]) -> str:
    names, allowed = _SIGNATURES[m.kind]
    slots: list[list[str]] = [[] for _ in range(len(names) + 1)]  # slot 0: before the first
    opts = list(m.options) + ([("WObj", m.wobj)] if m.wobj is not None else [])
    for opt, value in opts:
        slots[allowed[opt] + 1].append("\\" + opt + ("" if value is None else ":=" + value))
    args = [t.name if named.get(t.name.lower()) is t else _target_literal(t) for t in m.targets]
    args += [m.speed, m.zone, m.tool]
    head = m.kind + ("".join(slots[0]) + "," if slots[0] else "") + " "
    return head + ",".join(a + "".join(slots[k + 1]) for k, a in enumerate(args)) + ";"


def write_rapid(path: PathType, module: RapidModule) -> None:
    """Write a module as RAPID text (one statement per line, values round-trip exactly).

    Targets that are module data are referenced by name; inline ones are written as
    literals.  Comments of the source file are not kept.

    Examples
    --------
    >>> import tempfile, os
    >>> p = RobTarget("p1", [1000, 0, 500], [1, 0, 0, 0], [0, 0, 0, 1], [9e9] * 6)
    >>> m = Motion("MoveL", (p,), "v100", "fine", "tool0", None, (), 0)
    >>> mod = RapidModule("M", {"p1": p}, {"main": Procedure("main", (m,), 0)})
    >>> out = os.path.join(tempfile.mkdtemp(), "m.mod")
    >>> write_rapid(out, mod)
    >>> read_rapid(out).procedures["main"].motions[0].to_point.pos_mm.tolist()
    [1000.0, 0.0, 500.0]
    """
    named: dict[str, Target] = {}
    lines = [f"MODULE {module.name}"]
    for name, decl in module.data.items():
        value = "" if decl.value is None else " := " + _literal(decl.value)
        lines.append(f"    {decl.storage} {decl.type} {name}{value};")
    for kind, table in (("robtarget", module.targets), ("jointtarget", module.joint_targets)):
        for name, t in table.items():
            named[name.lower()] = t
            lines.append(f"    CONST {kind} {name}:={_target_literal(t)};")
    for name, proc in module.procedures.items():
        lines.append(f"    PROC {name}()")
        lines += ["        " + _motion_text(m, named) for m in proc.motions]
        lines.append("    ENDPROC")
    lines.append("ENDMODULE")
    with atomic_path(path) as tmp:
        Path(tmp).write_text("\n".join(lines) + "\n", encoding="utf-8")


read = read_rapid
write = write_rapid
