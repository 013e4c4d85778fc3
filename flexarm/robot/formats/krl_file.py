"""One module of a KUKA KRL program: a ``.src`` and its ``.dat``, statement by statement.

:func:`read_krl_file` reads the subset :mod:`~flexarm.robot.formats.krl_read` follows:
in the ``.dat``, ``DECL [GLOBAL] TYPE name=value`` lines; in the ``.src``, ``[GLOBAL] DEF
name( )`` ... ``END`` routines whose bodies are kept in order as

* ``("set", {variable: value}, line)``: system-variable assignments (``$VEL.CP = 0.02``,
  ``$TOOL = {X ..}``, ``$TOOL = TOOL_DATA[3]``) and ``BAS`` calls (speeds, tools and
  bases, the tables' entries taken from the controller's ``$config.dat``); a value None
  unsets the variable (a ``LOAD_DATA`` entry with KUKA's ``M -1``, "not given");
* ``("move", kind, targets, approximation, line)``: ``PTP``, ``LIN``, ``CIRC`` to declared
  names or inline aggregates, with ``C_DIS``, ``C_PTP``, ``C_VEL`` or ``C_ORI``;
* ``("call", name, line)``: a call of a routine without arguments.

Anything else is refused with one line naming the file and line (calls with arguments
and routines with parameters among them).
"""

from __future__ import annotations

import re
from dataclasses import dataclass
from pathlib import Path

from ...fe.errors import ReadError
from .krl_config import KrlConfig
from .krl_values import krl_statements, krl_value

__all__ = ["KrlFile", "read_krl_file"]

_DECL = re.compile(r"DECL\s+(GLOBAL\s+)?(\w+)\s+([A-Za-z_$][\w$]*)\s*=\s*(.+)\Z", re.I)
_ASSIGN = re.compile(r"(\$[\w.]+)(?:\[(\d+)\])?\s*=\s*(.+)\Z")
_TABLE = re.compile(r"(TOOL|BASE|LOAD)_DATA\s*\[\s*(\d+)\s*\]\Z", re.I)
_BAS = re.compile(r"BAS\s*\(\s*#(\w+)\s*(?:,\s*(.*?))?\s*\)", re.I)
_MOVE = re.compile(r"(PTP|LIN|CIRC)\s+(.+?)(?:\s+(C_DIS|C_PTP|C_VEL|C_ORI))?\Z", re.I)
_HEAD = re.compile(r"(GLOBAL\s+)?DEF\s+(\w+)\s*\((.*)\)\Z", re.I)
_CALL = re.compile(r"(\w+)\s*\((.*)\)\Z")


@dataclass(frozen=True)
class KrlFile:
    """One ``.src`` and its ``.dat``.

    Attributes
    ----------
    src : Path
    data : dict
        ``.dat`` declarations: name -> (type, value) (none without a ``.dat``).
    exported : frozenset of str
        Lower-case names the ``.dat`` declares ``GLOBAL``.
    routines : dict
        Lower-case name -> (name as written, is GLOBAL, line of the DEF, body): the body
        a tuple of ``("set" | "move" | "call", ...)`` items in order (module docstring).
    """

    src: Path
    data: dict
    exported: frozenset
    routines: dict

    def declared(self, name: str):
        """(name as declared, type, value) of a ``.dat`` name, or None."""
        return next(((k, t, v) for k, (t, v) in self.data.items()
                     if k.lower() == name.lower()), None)


def _read_dat(path: Path) -> tuple[dict, frozenset]:
    data, exported = {}, set()
    for i, s in krl_statements(path):
        if re.fullmatch(r"(DEFDAT\s+[\w$]+(\s+PUBLIC)?|ENDDAT)", s, re.I):
            continue
        m = _DECL.match(s)
        if m is None:
            raise ReadError(f"{path}, line {i}: expected 'DECL TYPE name=value', got '{s}'")
        name = m.group(3)
        if name.lower() in {k.lower() for k in data}:
            raise ReadError(f"{path}, line {i}: '{name}' is declared twice")
        data[name] = (m.group(2).upper(), krl_value(m.group(4), f"{path}, line {i}"))
        if m.group(1):
            exported.add(name.lower())
    return data, frozenset(exported)


def _table(config: KrlConfig | None, table: str, index: int, said: str, where: str,
           src: Path):
    """``TABLE_DATA[index]`` of the controller's ``$config.dat``, for the statement
    ``said`` on ``where``."""
    if config is None:
        raise ReadError(f"{where}: '{said}' takes {table}_DATA[{index}] from the "
                        f"controller's $config.dat (R1/System/$config.dat), which is not "
                        f"beside {src.name}: give that file (--krl-config PATH/$config.dat)")
    if table == "LOAD":  # KUKA's M -1: no payload given
        value = config.tables["LOAD"].get(index)
        return value if isinstance(value, dict) and isinstance(value.get("M"), (int, float)) \
            and value["M"] >= 0 else None
    return config.entry(table, index, where)


def _bas(m: re.Match, where: str, config: KrlConfig | None, src: Path) -> dict:
    """The system variables a ``BAS (#WHAT, value)`` call sets: speeds (``#VEL_PTP`` [%],
    ``#VEL_CP`` [m/s]), the tool (``$TOOL`` and ``$LOAD`` of the tables' entry n, the
    null frame for 0) or base; the motion defaults and accelerations do not change the
    path."""
    what = m.group(1).upper()
    value = None if m.group(2) is None else krl_value(m.group(2), where)
    if what in ("INITMOV", "ACC_CP", "ACC_PTP"):
        return {}
    if what in ("VEL_PTP", "VEL_CP") and isinstance(value, (int, float)):
        return {f"$VEL_AXIS[{i}]": float(value) for i in range(1, 7)} \
            if what == "VEL_PTP" else {"$VEL.CP": float(value)}
    if what in ("TOOL", "BASE") and isinstance(value, int) and value >= 0:
        if value == 0:
            return {f"${what}": "$NULLFRAME"}
        out = {f"${what}": _table(config, what, value, m.group(0), where, src)}
        if what == "TOOL":
            out["$LOAD"] = _table(config, "LOAD", value, m.group(0), where, src)
        return out
    raise ReadError(f"{where}: unsupported call '{m.group(0)}' (flexarm reads BAS "
                    "#INITMOV, #VEL_PTP, #VEL_CP and #TOOL/#BASE with a number)")


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
    return tuple(krl_value(p, where) if p.strip().startswith("{") else p.strip()
                 for p in parts)


def _statement(s: str, where: str, config: KrlConfig | None, src: Path) -> tuple:
    """The body item of one statement inside a routine."""
    if (m := _ASSIGN.match(s)) is not None:
        var = m.group(1).upper() + (f"[{m.group(2)}]" if m.group(2) else "")
        t = _TABLE.fullmatch(m.group(3).strip())
        value = krl_value(m.group(3), where) if t is None else \
            _table(config, t.group(1).upper(), int(t.group(2)), s, where, src)
        return ("set", {var: value})
    if (m := _MOVE.match(s)) is not None:
        targets = _targets(m.group(2), where)
        want = 2 if m.group(1).upper() == "CIRC" else 1
        if len(targets) != want:
            raise ReadError(f"{where}: {m.group(1).upper()} takes {want} target(s), got "
                            f"{len(targets)}")
        return ("move", m.group(1).upper(), targets, m.group(3))
    if (m := _BAS.fullmatch(s)) is not None:
        return ("set", _bas(m, where, config, src))
    if (m := _CALL.fullmatch(s)) is not None:
        if m.group(2).strip():
            raise ReadError(f"{where}: the call '{s}' passes arguments: flexarm follows "
                            "calls without arguments (IN/OUT parameters may change the "
                            "targets)")
        return ("call", m.group(1))
    raise ReadError(f"{where}: unsupported KRL statement '{s}' (flexarm reads moves, "
                    "assignments and calls)")


def read_krl_file(src: Path, config: KrlConfig | None = None,
                  dat_required: bool = True) -> KrlFile:
    """Read a ``.src`` and the ``.dat`` beside it (see the module's docstring).

    Parameters
    ----------
    src : Path
    config : KrlConfig or None
        The controller's tables (``BAS (#TOOL, n)`` with n > 0 is refused without).
    dat_required : bool
        A missing ``.dat`` is an error (else the module declares nothing).

    Raises
    ------
    ReadError
        A missing file or a statement outside the subset, naming the file and line.

    Examples
    --------
    >>> import tempfile, pathlib
    >>> d = pathlib.Path(tempfile.mkdtemp())
    >>> _ = (d / "sub.src").write_text("GLOBAL DEF sub( )\\n$VEL.CP = 0.1\\nLIN {X 1,Y 2,Z 3,"
    ...                                "A 0,B 0,C 0}\\nINI( )\\nEND\\nDEF ini( )\\nEND\\n")
    >>> f = read_krl_file(d / "sub.src", dat_required=False)
    >>> [item[0] for item in f.routines["sub"][3]], f.routines["sub"][1]
    (['set', 'move', 'call'], True)
    """
    dat = src.with_suffix(".dat")
    data, exported = _read_dat(dat) if dat_required or dat.is_file() else ({}, frozenset())
    routines: dict[str, tuple] = {}
    current, body = None, []
    for i, s in krl_statements(src):
        where = f"{src}, line {i}"
        head = _HEAD.fullmatch(s)
        if head:
            name = head.group(2)
            if current is not None:
                raise ReadError(f"{where}: DEF {name} inside DEF {current[0]} (missing END)")
            if head.group(3).strip():
                raise ReadError(f"{where}: DEF {name} takes parameters: flexarm follows "
                                "routines without IN/OUT parameters")
            if name.lower() in routines:
                raise ReadError(f"{where}: DEF {name} is defined twice in {src.name}")
            current, body = (name, bool(head.group(1)), i), []
            continue
        if current is None:
            raise ReadError(f"{where}: '{s}' outside a DEF ... END routine")
        if s.upper() == "END":
            routines[current[0].lower()] = (*current, tuple(body))
            current = None
            continue
        body.append((*_statement(s, where, config, src), i))
    if current is not None:
        raise ReadError(f"{src}: DEF {current[0]} has no END")
    return KrlFile(src, data, exported, routines)
