"""The words of KUKA KRL files: statements of a file, values and aggregates, KUKA angles.

:func:`krl_statements` gives the statements of a ``.src`` or ``.dat`` (``;`` starts a
comment, ``&`` lines are editor headers); :func:`krl_value` reads a number, a bit string,
a name or a ``{KEY value, ...}`` aggregate.  Aggregates are read by a loop over their
braces with an explicit stack: no recursion, however deep a file nests them.
:func:`matrix_from_abc` turns KUKA's ``A, B, C`` [deg] into rotation matrices.
"""

from __future__ import annotations

import re
from pathlib import Path
from typing import Any

import numpy as np

from ...fe.errors import ReadError
from ...fe.typing import ArrayLike, FloatArray

__all__ = ["krl_statements", "krl_value", "matrix_from_abc"]

_TOKEN = re.compile(r"\s*(?:(?P<open>\{)|(?P<close>\})|(?P<comma>,)"
                    r"|(?P<bits>'B[01]+')|(?P<word>[^\s{},]+))")


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


def krl_value(text: str, where: str) -> Any:
    """A number, a bit string (as int), a name or a ``{KEY value, ...}`` aggregate (dict,
    keys upper case) of KRL text; ``where`` (file and line) starts the error's message.

    Examples
    --------
    >>> krl_value("{X 1.5, CM {Z 60}, T 'B101'}", "t.dat, line 2")
    {'X': 1.5, 'CM': {'Z': 60}, 'T': 5}
    """
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


def krl_statements(path: Path) -> list[tuple[int, str]]:
    """(line number, statement) of a KRL file, comments and editor headers dropped.

    Raises
    ------
    ReadError
        The file cannot be read (naming it).
    """
    try:
        text = Path(path).read_text(encoding="utf-8")
    except (OSError, UnicodeDecodeError) as exc:
        raise ReadError(f"{path}: {getattr(exc, 'strerror', None) or exc}") from None
    out = []
    for i, line in enumerate(text.splitlines(), start=1):
        s = line.split(";", 1)[0].strip()
        if s and not s.startswith("&"):
            out.append((i, s))
    return out
