"""Read a KUKA KRL program: the ``.src`` flexarm writes (:mod:`~flexarm.robot.formats.krl`)
or a plain expert-mode one shaped like it, its ``.dat``, the modules it calls and the
controller's tables.

The statements of each file are the subset :func:`~.krl_file.read_krl_file` reads
(declarations, routines of assignments, ``BAS`` calls, moves and calls without
arguments; anything else one line naming the file and line): this is a check of what a
program moves, not a KRL interpreter (no ``IF``, loops, inline forms or expressions).
What :func:`read_krl` adds is the program:

* calls are followed as the controller runs them: a routine of the same ``.src``, else
  the module of that name in the folder (``my_sub( )`` runs ``DEF my_sub( )`` of
  ``my_sub.src``), else the one ``GLOBAL DEF`` of that name in another ``.src`` of the
  folder.  The called routine's moves are inlined at the call, in call order, each
  keeping the file and line it comes from; the system variables flow through calls
  (a routine sees its caller's ``$TOOL`` and what it sets stays set).  A routine found
  nowhere, a local ``DEF`` of another module, or a recursion is one line naming the
  ``.src`` and line of the call;
* the procedures (what ``--proc`` names): the main routine when it moves the arm itself
  (its calls inlined), else each routine it calls, each starting from the main
  routine's settings at the call; and every routine of the main ``.src`` nothing calls;
* names: a target is the calling module's ``.dat`` declaration, else a ``DECL GLOBAL``
  of another ``.dat`` read, else a position of ``$config.dat`` (``XHOME``).  Another
  module's name that the main ``.dat`` already gives to another point is renamed
  ``<module>_<name>``;
* the tables: ``BAS (#TOOL, n)``, ``BAS (#BASE, n)``, ``$TOOL = TOOL_DATA[n]`` ... read
  the controller's ``$config.dat`` (given, else found beside the ``.src``,
  :mod:`~.krl_config`).

Positions stay in mm and angles in degrees, as written;
:func:`~.krl_values.matrix_from_abc` turns ``A, B, C`` into rotation matrices.
"""

from __future__ import annotations

import re
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from ...fe.errors import ReadError
from ...fe.typing import FloatArray, PathType
from .krl_config import KrlConfig, find_krl_config, read_krl_config
from .krl_file import KrlFile, read_krl_file
from .krl_values import matrix_from_abc

__all__ = ["KrlMove", "KrlProgram", "read_krl", "matrix_from_abc", "read_status_turn"]


@dataclass(frozen=True)
class KrlMove:
    """One move of a routine.

    Attributes
    ----------
    kind : {"PTP", "LIN", "CIRC"}
    targets : tuple
        Each a name of :attr:`KrlProgram.data` (str) or an inline aggregate (dict of
        components).
    approx : str or None
        ``C_DIS``, ``C_PTP`` ... or None (exact stop).
    settings : dict
        The system variables in force (``"$VEL.CP"``, ``"$APO.CDIS"``, ``"$TOOL"``,
        ``"$LOAD"``, ``"$VEL_AXIS[1]"`` ...), as read.
    line : int
        Line in its ``.src``.
    file : str
        Its ``.src`` (a called module's for an inlined move).
    """

    kind: str
    targets: tuple
    approx: str | None
    settings: dict
    line: int
    file: str = ""


@dataclass(frozen=True, eq=False)
class KrlProgram:
    """A KRL program: its procedures' moves, calls inlined.

    Attributes
    ----------
    name : str
        The main routine (the file's stem).
    data : dict
        Declarations: name -> (type, value); aggregates as dicts of components (float,
        int, bit strings as int, nested dicts).  The main ``.dat``'s, then those the
        called modules' moves use (renamed where the name is taken).
    routines : dict
        Procedure -> tuple of :class:`KrlMove`, in execution order.
    calls : tuple of str
        The routines the main routine calls, in order.
    main_settings : dict
        The system variables the main routine sets.
    files : tuple of str
        The ``.src`` files read, the main one first.
    config : str or None
        The controller's ``$config.dat`` read.
    """

    name: str
    data: dict
    routines: dict
    calls: tuple[str, ...] = ()
    main_settings: dict = field(default_factory=dict)
    files: tuple[str, ...] = ()
    config: str | None = None

    def pose(self, target) -> tuple[FloatArray, FloatArray]:
        """(position (3,) [mm], rotation (3, 3)) of a declared name or inline aggregate."""
        v = self.data[target][1] if isinstance(target, str) else target
        return (np.array([v["X"], v["Y"], v["Z"]], dtype=np.float64),
                matrix_from_abc([v["A"], v["B"], v["C"]]))


def _settled(state: dict) -> dict:
    """The variables set (None: unset)."""
    return {k: v for k, v in state.items() if v is not None}


class _Folder:
    """The modules of the program's folder, read as calls reach them."""

    def __init__(self, main: KrlFile, config: KrlConfig | None):
        self.main, self.config = main, config
        self.files = {main.src: main}
        self._sources: dict[str, Path] | None = None

    def sources(self) -> dict[str, Path]:
        """Lower-case stem -> ``.src`` of the folder."""
        if self._sources is None:
            self._sources = {p.stem.lower(): p for p in sorted(self.main.src.parent.iterdir())
                             if p.suffix.lower() == ".src" and p.is_file()}
        return self._sources

    def load(self, src: Path) -> KrlFile:
        if src not in self.files:
            self.files[src] = read_krl_file(src, self.config, dat_required=False)
        return self.files[src]

    def _defining(self, name: str, caller: Path) -> tuple[list[Path], list[Path]]:
        """(``.src`` with a ``GLOBAL DEF name``, with a local ``DEF name``) of the folder."""
        glob = re.compile(rf"^[ \t]*GLOBAL[ \t]+DEF[ \t]+{re.escape(name)}[ \t]*\(", re.I | re.M)
        local = re.compile(rf"^[ \t]*DEF[ \t]+{re.escape(name)}[ \t]*\(", re.I | re.M)
        hits: tuple[list[Path], list[Path]] = ([], [])
        for p in self.sources().values():
            if p == caller:
                continue
            try:
                text = p.read_text(encoding="utf-8", errors="replace")
            except OSError:
                continue
            if glob.search(text):
                hits[0].append(p)
            elif local.search(text):
                hits[1].append(p)
        return hits

    def resolve(self, caller: KrlFile, name: str, where: str) -> tuple[KrlFile, str]:
        """(module, lower-case routine) a call of ``name`` in ``caller`` runs."""
        key = name.lower()
        if key in caller.routines:
            return caller, key
        src = self.sources().get(key)
        if src is not None and src != caller.src:
            module = self.load(src)
            if key not in module.routines:
                raise ReadError(f"{where}: {name}( ): {src.name} has no DEF {name}( )")
            return module, key
        glob, local = self._defining(name, caller.src)
        if len(glob) > 1:
            raise ReadError(f"{where}: {name}( ) is a GLOBAL DEF of both {glob[0].name} and "
                            f"{glob[1].name}: keep one")
        if glob:
            return self.load(glob[0]), key
        if local:
            raise ReadError(f"{where}: {name}( ) is a local DEF of {local[0].name}, which the "
                            f"controller does not call from {caller.src.name}: make it a "
                            "GLOBAL DEF")
        raise ReadError(f"{where}: {name}( ) is not a DEF of {caller.src.name}, nor a module "
                        f"{name}.src or a GLOBAL DEF in its folder {caller.src.parent}")


class _Reader:
    """Follows the calls of a program and inlines them (see the module's docstring)."""

    def __init__(self, main: KrlFile, config: KrlConfig | None):
        self.folder = _Folder(main, config)
        self.config = config
        self.data = dict(main.data)
        self.renamed: dict[tuple[Path, str], str] = {}
        self.calls: dict[tuple[Path, int], tuple[KrlFile, str]] = {}
        self._follow()

    def _follow(self) -> None:
        """Read every module a routine of the main ``.src`` reaches (the calls resolved)."""
        main = self.folder.main
        todo, seen = [(main, k) for k in main.routines], {(main.src, k) for k in main.routines}
        while todo:
            module, key = todo.pop()
            for item in module.routines[key][3]:
                if item[0] != "call":
                    continue
                where = f"{module.src}, line {item[-1]}"
                called = self.folder.resolve(module, item[1], where)
                self.calls[module.src, item[-1]] = called
                if (called[0].src, called[1]) not in seen:
                    seen.add((called[0].src, called[1]))
                    todo.append(called)

    def name(self, module: KrlFile, target: str, where: str) -> str:
        """The :attr:`KrlProgram.data` name of a target named in ``module``."""
        found, origin = module.declared(target), module.src
        if found is None:
            for other in self.folder.files.values():
                if target.lower() in other.exported:
                    found, origin = other.declared(target), other.src
                    break
        if found is None and self.config is not None:
            found = next(((k, t, v) for k, (t, v) in self.config.positions.items()
                          if k.lower() == target.lower()), None)
            origin = self.config.path
        if found is None:
            raise ReadError(f"{where}: target '{target}' is not declared in "
                            f"{module.src.stem}.dat (nor GLOBAL in another .dat of the "
                            "program or in the controller's $config.dat)")
        name, typ, value = found
        if origin == self.folder.main.src:
            return name
        key = (origin, name.lower())
        if key not in self.renamed:
            taken = {k.lower(): k for k in self.data}
            new = taken.get(name.lower(), name)
            if new.lower() in taken and self.data[new] != (typ, value):
                stem = re.sub(r"\W", "", origin.stem) or "module"
                base = new = f"{stem}_{name}"
                n = 2
                while new.lower() in taken:
                    new, n = f"{base}_{n}", n + 1
            self.data[new] = (typ, value)
            self.renamed[key] = new
        return self.renamed[key]

    def run(self, module: KrlFile, key: str, state: dict,
            via: tuple[tuple[Path, str], ...] = ()) -> list[KrlMove]:
        """The moves of a routine with its calls inlined; ``state`` (the system variables)
        is updated as the controller would.  A loop over an explicit stack of frames."""
        moves: list[KrlMove] = []
        frames = [(module, iter(module.routines[key][3]))]
        active = [*via, (module.src, key)]
        while frames:
            current, items = frames[-1]
            item = next(items, None)
            if item is None:
                frames.pop()
                active.pop()
            elif item[0] == "set":
                state.update(item[1])
            elif item[0] == "move":
                where = f"{current.src}, line {item[-1]}"
                targets = tuple(self.name(current, t, where) if isinstance(t, str) else t
                                for t in item[2])
                moves.append(KrlMove(item[1], targets, item[3], _settled(state), item[-1],
                                     str(current.src)))
            else:
                called, ck = self.calls[current.src, item[-1]]
                self.check_loop(active, (called.src, ck), current, item)
                frames.append((called, iter(called.routines[ck][3])))
                active.append((called.src, ck))
        return moves

    def check_loop(self, active, entry, current: KrlFile, item) -> None:
        if entry in active:
            names = [f"{Path(s).name}:{k}" for s, k in active[active.index(entry):]]
            raise ReadError(f"{current.src}, line {item[-1]}: {item[1]}( ) is called again "
                            f"while it runs ({' -> '.join([*names, names[0]])}): a "
                            "recursion, which flexarm does not follow")


def read_krl(path: PathType, config: PathType | None = None) -> KrlProgram:
    """Read a ``.src``, the ``.dat`` beside it and the modules it calls.

    Parameters
    ----------
    path : path
        The main ``.src``.
    config : path, optional
        The controller's ``$config.dat`` (tool, base and payload tables; default: a
        ``$config.dat`` or ``config.dat`` beside the ``.src``, if any).

    Raises
    ------
    ReadError
        A missing file, a statement outside the subset, a routine found nowhere, a
        recursion, a table entry missing (naming the file and line).

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
    found = find_krl_config(path.parent) if config is None else Path(config)
    table = None if found is None else read_krl_config(found)
    main = read_krl_file(path, table)
    key = path.stem.lower()
    if key not in main.routines:
        raise ReadError(f"{path}: no main routine DEF {path.stem}( )")
    name, _glob, line, body = main.routines[key]
    reader = _Reader(main, table)
    own: dict = {}
    routines: dict[str, list[KrlMove]] = {}
    calls = []
    if any(item[0] == "move" for item in body):
        routines[name] = reader.run(main, key, {})
    for item in body:
        if item[0] == "set":
            own.update(item[1])
        elif item[0] == "call":
            calls.append(item[1])
            module, ck = reader.calls[path, item[-1]]
            reader.check_loop([(path, key)], (module.src, ck), main, item)
            proc = module.routines[ck][0]
            if name not in routines and proc not in routines:
                routines[proc] = reader.run(module, ck, dict(own), ((path, key),))
    called = {(m.src, k) for m, k in reader.calls.values()}
    for k, (proc, *_rest) in main.routines.items():
        if k != key and (path, k) not in called:  # nothing calls it: a procedure of its own
            routines[proc] = reader.run(main, k, dict(own))
    return KrlProgram(name, reader.data, {k: tuple(v) for k, v in routines.items()},
                      tuple(calls), _settled(own),
                      tuple(str(p) for p in reader.folder.files),
                      None if found is None else str(found))


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
