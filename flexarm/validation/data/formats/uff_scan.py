"""The block structure of a universal file, read from its bytes: what pyuff does not say.

pyuff finds datasets as pairs of ``    -1`` delimiter lines and silently drops a last
delimiter without its pair, so a file cut short loses its last dataset (and with it a
pose) without a word; and a number it cannot parse (``1.#QNAN``, ``nan(ind)``: NaN as
some Windows tools print it) fails the whole dataset with no line.  :func:`truncation`
and :func:`bad_number` find those in the same bytes, with pyuff's own rule for a
delimiter line.
"""

from __future__ import annotations

import re

__all__ = ["delimiters", "truncation", "bad_number"]

_TAG = b"    -1"
_PADDING = b" " * 74  # a delimiter padded with blanks to 80 columns
_MARK = re.compile(rb"flexarm pose=(\S+)")
#: Line (0-based, from the opening delimiter) where the data of an ASCII dataset starts:
#: delimiter, type, then the 58 set's 11 header records.
_DATA_START = {58: 13}


def delimiters(raw: bytes) -> list[int]:
    """Byte offsets of the delimiter lines, found as pyuff finds them."""
    out, i = [], raw.find(_TAG)
    while i != -1:
        end = i + len(_TAG)
        if end == len(raw) or raw[end] in (10, 13) or raw[end:end + len(_PADDING)] == _PADDING:
            out.append(i)
        i = raw.find(_TAG, i + 1)
    return out


def _line(raw: bytes, offset: int) -> int:
    return raw.count(b"\n", 0, offset) + 1


def _kind(block: bytes) -> str:
    lines = block.splitlines()
    return lines[1][:6].strip().decode("ascii", "replace") if len(lines) > 1 else "?"


def truncation(raw: bytes) -> str | None:
    """What is cut off at the end of a universal file (``None`` if nothing is).

    Examples
    --------
    >>> whole = b"    -1\\n    15\\n         1 0 0 1 0.0 0.0 0.0\\n    -1\\n"
    >>> truncation(whole) is None
    True
    >>> truncation(whole + b"    -1\\n    58\\nflexarm pose=P2 q_deg=0,0,0,0,0,0\\n  1.0")
    "the file ends inside dataset 2 (type 58, pose 'P2', from line 5): no closing '    -1' \
line, so the file is truncated there"
    """
    tags = delimiters(raw)
    if len(tags) % 2:
        start = tags[-1]
        block = raw[start:]
        mark = _MARK.search(block)
        pose = f", pose '{mark.group(1).decode('utf-8', 'replace')}'" if mark else ""
        return (f"the file ends inside dataset {len(tags) // 2 + 1} (type {_kind(block)}"
                f"{pose}, from line {_line(raw, start)}): no closing '    -1' line, so the "
                "file is truncated there")
    tail = raw[tags[-1] + len(_TAG):] if tags else b""
    if tail.strip() and tags:
        return (f"text after the last dataset's closing '    -1' (line "
                f"{_line(raw, tags[-1])}): the start of another dataset, cut off?")
    return None


def bad_number(raw: bytes, index: int) -> str | None:
    """Where dataset ``index`` (0-based) holds a data value that is not a number, as
    ``"line 30: '1.#QNAN' is not a number"``; ``None`` if none is found or the dataset
    is not an ASCII 58 set."""
    tags = delimiters(raw)
    if 2 * index + 1 >= len(tags):
        return None
    start, end = tags[2 * index], tags[2 * index + 1]
    lines = raw[start:end].splitlines()
    kind = _kind(raw[start:end])
    first = _DATA_START.get(int(kind)) if kind.isdigit() else None
    if first is None:
        return None
    for k, text in enumerate(lines[first:], start=first):
        for token in text.split():
            try:
                float(token)
            except ValueError:
                shown = token.decode("ascii", "replace")
                return f"line {_line(raw, start) + k}: {shown!r} is not a number"
    return None
