"""Write a compensated RAPID module: the user's text with only the robtargets changed.

:func:`~flexarm.robot.formats.rapid.write_rapid` writes a module from its data and
drops the comments.  A compensated program must stay the user's program: every
procedure, instruction, speed, zone, configuration, comment and blank line as written,
only the position and orientation of the compensated robtargets replaced, and a header
comment after the ``MODULE`` line naming the model and the force.  So the source text
is edited in place: :func:`robtarget_spans` finds where each module-level robtarget's
``[x,y,z]`` and ``[q1,q2,q3,q4]`` are written (outside comments and strings), and
:func:`rewrite_targets` replaces exactly those characters.

Positions are written to 1e-6 mm and quaternions to 1e-10; the values in the file are
the offsets a reader sees (:func:`written_pose` gives them back exactly).
"""

from __future__ import annotations

import re
import tempfile
from collections.abc import Mapping, Sequence
from dataclasses import replace
from pathlib import Path

import numpy as np

from ....fe.files import atomic_path
from ....fe.typing import ArrayLike, FloatArray, PathType
from ....robot.formats.rapid import RapidModule, read_rapid

__all__ = ["robtarget_spans", "rewrite_targets", "written_pose", "read_module_text",
           "write_module_text", "module_of_text",
           "POS_DECIMALS", "QUAT_DECIMALS"]

#: Decimals of written positions [mm] (1 nm) and quaternion components.
POS_DECIMALS, QUAT_DECIMALS = 6, 10

_SCAN = re.compile(
    r"(?P<comment>![^\n]*)|(?P<str>\"(?:[^\"\n]|\"\")*\")"
    r"|(?P<decl>\brobtarget\s+(?P<name>[A-Za-z_]\w*)\s*:=\s*)"
    r"|(?P<module>\bMODULE\b[^\n]*)",
    re.IGNORECASE,
)


def _close(text: str, start: int) -> int:
    """Index just after the bracket matching ``text[start] == '['``."""
    depth = 0
    for i in range(start, len(text)):
        c = text[i]
        depth += c == "["
        depth -= c == "]"
        if depth == 0:
            return i + 1
    raise ValueError("unbalanced '[' in a robtarget literal")


def robtarget_spans(text: str) -> dict[str, tuple[tuple[int, int], tuple[int, int]]]:
    """Lower-case name -> character spans of the ``[x,y,z]`` and ``[q1..q4]`` aggregates
    of every robtarget declared with a literal value (``Offs`` and expressions are not).

    Examples
    --------
    >>> t = 'MODULE M\\n  ! robtarget c:=[[0,0,0]]\\n  CONST robtarget p1:=[[1,2,3],[1,0,0,0],' \\
    ...     '[0,0,0,0],[9E+09,9E+09,9E+09,9E+09,9E+09,9E+09]];\\nENDMODULE\\n'
    >>> (a, b), (c, d) = robtarget_spans(t)["p1"]
    >>> t[a:b], t[c:d]
    ('[1,2,3]', '[1,0,0,0]')
    """
    out = {}
    for m in _SCAN.finditer(text):
        if m.group("decl") is None:
            continue
        i = m.end()
        if i >= len(text) or text[i] != "[":
            continue  # a robtarget given by an expression: not ours to edit
        outer_end = _close(text, i)
        j = text.index("[", i + 1)
        pos = (j, _close(text, j))
        k = text.index("[", pos[1])
        quat = (k, _close(text, k))
        if quat[1] > outer_end:
            continue
        out[m.group("name").lower()] = (pos, quat)
    return out


def _number(x: float, decimals: int) -> str:
    """Fixed-point text of ``x`` rounded to ``decimals`` (reads back to ``round(x)``)."""
    v = round(float(x), decimals)
    s = f"{v:.{decimals}f}".rstrip("0").rstrip(".")
    return "0" if s in ("-0", "") else s


def written_pose(pos_mm: ArrayLike, quat: ArrayLike) -> tuple[FloatArray, FloatArray]:
    """The position [mm] and quaternion exactly as :func:`rewrite_targets` writes them.

    Examples
    --------
    >>> written_pose([1.23456789, 0, -2], [1, 0, 0, 0])[0].tolist()
    [1.234568, 0.0, -2.0]
    """
    p = np.array([float(_number(x, POS_DECIMALS)) for x in np.asarray(pos_mm, float)])
    q = np.array([float(_number(x, QUAT_DECIMALS)) for x in np.asarray(quat, float)])
    return p, q


def _header_at(text: str) -> tuple[int, str]:
    """(index after the ``MODULE`` line, indentation of the line after it)."""
    for m in _SCAN.finditer(text):
        if m.group("module") is not None:
            end = text.find("\n", m.start())
            end = len(text) if end < 0 else end + 1
            nxt = re.match(r"[ \t]*", text[end:])
            return end, (nxt.group(0) if nxt and nxt.group(0) else "    ")
    raise ValueError("no MODULE line in the RAPID text")


def rewrite_targets(text: str, new: Mapping[str, tuple[ArrayLike, ArrayLike]],
                    header: Sequence[str] = ()) -> str:
    """``text`` with the robtargets ``new`` (name -> (pos_mm (3,), quat (4,))) rewritten
    and ``header`` lines added as ``!`` comments after the ``MODULE`` line.

    Everything else (instructions, configurations, external axes, comments, blank
    lines, line breaks) is kept character for character.

    Raises
    ------
    ValueError
        A name that is not a robtarget declared with a literal in ``text``.

    Examples
    --------
    >>> t = 'MODULE M\\n    CONST robtarget p1:=[[1,2,3],[1,0,0,0],[0,0,0,0],' \\
    ...     '[9E+09,9E+09,9E+09,9E+09,9E+09,9E+09]];\\nENDMODULE\\n'
    >>> print(rewrite_targets(t, {"P1": ([1.5, 2, 3], [1, 0, 0, 0])}, ["shifted"]), end="")
    MODULE M
        ! shifted
        CONST robtarget p1:=[[1.5,2,3],[1,0,0,0],[0,0,0,0],[9E+09,9E+09,9E+09,9E+09,9E+09,9E+09]];
    ENDMODULE
    """
    spans = robtarget_spans(text)
    edits = []
    for name, (pos, quat) in new.items():
        if name.lower() not in spans:
            raise ValueError(f"robtarget '{name}' is not declared with a literal value in the "
                             "module (only named robtargets can be compensated)")
        (a, b), (c, d) = spans[name.lower()]
        edits.append((a, b, "[" + ",".join(_number(x, POS_DECIMALS) for x in pos) + "]"))
        edits.append((c, d, "[" + ",".join(_number(x, QUAT_DECIMALS) for x in quat) + "]"))
    if header:
        at, indent = _header_at(text)
        edits.append((at, at, "".join(f"{indent}! {h}\n" for h in header)))
    for a, b, s in sorted(edits, key=lambda e: e[0], reverse=True):
        text = text[:a] + s + text[b:]
    return text


def read_module_text(path: PathType) -> tuple[str, str]:
    """(text, encoding) of a RAPID file: UTF-8, else Latin-1 (as the reader decodes it).

    Examples
    --------
    >>> import tempfile, os
    >>> p = os.path.join(tempfile.mkdtemp(), "m.mod")
    >>> write_module_text(p, "MODULE M ! Größe\\nENDMODULE\\n", "latin-1").name
    'm.mod'
    >>> read_module_text(p)[1]
    'latin-1'
    """
    raw = Path(path).read_bytes()
    try:
        return raw.decode("utf-8"), "utf-8"
    except UnicodeDecodeError:
        return raw.decode("latin-1"), "latin-1"


def write_module_text(path: PathType, text: str, encoding: str = "utf-8") -> Path:
    """Write RAPID ``text`` to ``path`` atomically (nothing half-written); returns the path."""
    path = Path(path)
    with atomic_path(path) as tmp:
        Path(tmp).write_bytes(text.encode(encoding))
    return path


def module_of_text(text: str, encoding: str = "utf-8", name: str = "module.mod") -> RapidModule:
    """The :class:`~flexarm.robot.formats.rapid.RapidModule` of RAPID ``text``, with
    ``path`` = ``name`` (the file it came from, for messages).

    Examples
    --------
    >>> module_of_text("MODULE M\\nENDMODULE\\n").name
    'M'
    """
    with tempfile.TemporaryDirectory() as tmp:
        path = Path(tmp) / Path(name).name
        path.write_bytes(text.encode(encoding))
        return replace(read_rapid(path), path=str(name))
