"""The controller's tables a KUKA KRL program refers to: ``$config.dat``.

``BAS (#TOOL, n)``, ``BAS (#BASE, n)``, ``$TOOL = TOOL_DATA[n]`` and the like take the
tool, base and payload from tables that live on the controller (``R1/System/$config.dat``),
not in the program's files.  :func:`read_krl_config` reads from that file what a path
needs:

* ``TOOL_DATA[n]={X .., Y .., Z .., A .., B .., C ..}`` (a tool frame on the flange,
  [mm] and KUKA's angles [deg]), ``BASE_DATA[n]={...}`` (a base frame in the robot's
  world [mm], [deg]) and ``LOAD_DATA[n]={M .., CM {..}, J {..}}`` (payload [kg], [mm],
  [kg m²]; ``M -1`` is KUKA's "not given");
* position declarations ``DECL [GLOBAL] E6AXIS|AXIS|E6POS|POS|FRAME name={...}`` (such as
  ``XHOME``): the file's declarations are global, every module of the program sees them.

Everything else in the file (signals, options, names, the tables' ``DECL``) is the
controller's business and is passed over.  A table entry or a position it cannot read
is one line naming the file and line.  :func:`find_krl_config` looks for the file beside
a program.
"""

from __future__ import annotations

import re
from dataclasses import dataclass, field
from pathlib import Path

from ...fe.errors import ReadError
from ...fe.typing import PathType
from .krl_values import krl_statements, krl_value

__all__ = ["KrlConfig", "read_krl_config", "find_krl_config", "CONFIG_NAMES"]

#: The names the controller's configuration file goes by beside a program (lower case).
CONFIG_NAMES = ("$config.dat", "config.dat")
_ENTRY = re.compile(r"(TOOL|BASE|LOAD)_DATA\s*\[\s*(\d+)\s*\]\s*=\s*(\{.*)\Z", re.I)
_POSITION = re.compile(r"DECL\s+(?:GLOBAL\s+)?(E6POS|POS|E6AXIS|AXIS|FRAME)\s+"
                       r"([A-Za-z_$][\w$]*)\s*=\s*(\{.*)\Z", re.I)


@dataclass(frozen=True)
class KrlConfig:
    """What a path needs of a controller's ``$config.dat``.

    Attributes
    ----------
    path : Path
        The file read.
    tables : dict
        ``"TOOL"``, ``"BASE"``, ``"LOAD"`` -> {index: aggregate (dict of components, [mm],
        [deg], [kg])}.
    positions : dict
        Declared name -> (type, aggregate): positions every module sees.
    """

    path: Path
    tables: dict = field(default_factory=lambda: {"TOOL": {}, "BASE": {}, "LOAD": {}})
    positions: dict = field(default_factory=dict)

    def entry(self, table: str, index: int, where: str) -> dict:
        """``TABLE_DATA[index]`` (``table`` one of ``TOOL``, ``BASE``, ``LOAD``).

        Raises
        ------
        ReadError
            No such entry: one line starting with ``where`` (the program's file and
            line) and naming this file.
        """
        value = self.tables[table.upper()].get(index)
        if value is None:
            raise ReadError(f"{where}: {table.upper()}_DATA[{index}] is not in {self.path} "
                            "(the controller's table has no such entry)")
        return value


def read_krl_config(path: PathType) -> KrlConfig:
    """Read the tool, base and payload tables and the positions of a ``$config.dat``.

    Raises
    ------
    ReadError
        A missing file, an entry or position that is not an aggregate, an index given
        twice (naming the file and line).

    Examples
    --------
    >>> import tempfile, pathlib
    >>> p = pathlib.Path(tempfile.mkdtemp()) / "$config.dat"
    >>> _ = p.write_text("DEFDAT $CONFIG\\nDECL INT GRIPPER=0\\nDECL FRAME TOOL_DATA[16]\\n"
    ...                  "TOOL_DATA[3]={X 0.0,Y 0.0,Z 150.0,A 0.0,B 0.0,C 0.0}\\nENDDAT\\n")
    >>> read_krl_config(p).tables["TOOL"][3]["Z"]
    150.0
    """
    path = Path(path)
    tables: dict[str, dict[int, dict]] = {"TOOL": {}, "BASE": {}, "LOAD": {}}
    positions: dict[str, tuple[str, dict]] = {}
    for i, s in krl_statements(path):
        where = f"{path}, line {i}"
        if (m := _ENTRY.match(s)) is not None:
            table, index = m.group(1).upper(), int(m.group(2))
            if index in tables[table]:
                raise ReadError(f"{where}: {table}_DATA[{index}] is given twice")
            tables[table][index] = _aggregate(m.group(3), where)
        elif (m := _POSITION.match(s)) is not None:
            positions[m.group(2)] = (m.group(1).upper(), _aggregate(m.group(3), where))
    return KrlConfig(path, tables, positions)


def _aggregate(text: str, where: str) -> dict:
    value = krl_value(text, where)
    if not isinstance(value, dict):
        raise ReadError(f"{where}: '{text}' is not an aggregate {{..}}")
    return value


def find_krl_config(folder: PathType) -> Path | None:
    """The controller's configuration file beside a program (``$config.dat``, else
    ``config.dat``, in any letter case), or None.

    Examples
    --------
    >>> import tempfile, pathlib
    >>> d = pathlib.Path(tempfile.mkdtemp())
    >>> find_krl_config(d) is None
    True
    >>> _ = (d / "$CONFIG.DAT").write_text("DEFDAT $CONFIG\\nENDDAT\\n")
    >>> find_krl_config(d).name
    '$CONFIG.DAT'
    """
    try:
        found = {p.name.lower(): p for p in Path(folder).iterdir() if p.is_file()}
    except OSError:
        return None
    return next((found[n] for n in CONFIG_NAMES if n in found), None)
