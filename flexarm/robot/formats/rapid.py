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

This module holds the public reader and writer; the work is split by concept into
:mod:`.rapid_data` (the dataclasses and configuration helpers), :mod:`.rapid_lexer`
(tokens), :mod:`.rapid_values` (expressions and target literals) and
:mod:`.rapid_parser` (module, routines and Move instructions).
"""

from __future__ import annotations

import logging
from collections.abc import Mapping
from pathlib import Path
from typing import Any

from ...fe.errors import ReadError
from ...fe.files import atomic_path
from ...fe.typing import PathType
from .rapid_data import (
    _SIGNATURES,
    EXTAX_UNUSED,
    SUPPORTED_INSTRUCTIONS,
    Declaration,
    JointTarget,
    Motion,
    Procedure,
    RapidModule,
    RobTarget,
    Target,
    decode_cfx,
    quadrant,
)
from .rapid_lexer import _tokenize
from .rapid_parser import _Parser
from .rapid_values import _num

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
