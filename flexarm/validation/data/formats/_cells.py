"""The data rows of a measurement file as one byte buffer and the bounds of every field.

A million rows as Python strings would take gigabytes and seconds, so a file is read
as bytes and split with numpy: line breaks, comment and blank lines, commas and the
blanks around them.  Cell ``(i, j)`` is ``buf[bounds[i, j] + 1 : bounds[i, j + 1]]``
with its blanks stripped (:meth:`Cells.column`); the columns are then converted in
bulk (:mod:`flexarm.validation.data.decimals`).

Files the byte scan cannot split exactly as the line-by-line reader would (quoted
fields, data rows that are not ASCII, line breaks other than ``\\n`` and ``\\r\\n``,
control characters that Python counts as blanks or line breaks) go through that reader
(:func:`._lines.records`, :func:`._lines.fields`); their stripped fields then fill the
same structure.  Comments and the header may hold any UTF-8 text.
"""

from __future__ import annotations

import codecs
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ....fe.typing import IntArray
from ..decimals import cell_text
from ._lines import MeasurementFileError, fields, records

__all__ = ["Lines", "Cells", "file_lines"]

_BOM = codecs.BOM_UTF8
_NL, _COMMA, _HASH = 10, 44, 35
_BLANKS = (32, 9, 13)  # space, tab, the CR of a CRLF
#: Bytes that ``str.splitlines``/``str.strip`` treat as line breaks or blanks, and quotes:
#: a file holding one is read line by line.
_ODD = (b'"', b"\x00", b"\x0b", b"\x0c", b"\x1c", b"\x1d", b"\x1e", b"\x1f")
#: Bytes scanned at a time (the comparison arrays stay small).
_BLOCK = 1 << 24
#: Lines split into fields at a time.
_ROWS = 1 << 16


def _positions(buf: np.ndarray, test, start: int = 0, stop: int | None = None) -> IntArray:
    """Indices ``i`` in ``[start, stop)`` where ``test(buf[i])``, block by block."""
    stop = len(buf) if stop is None else stop
    found = [a + np.flatnonzero(test(buf[a:min(a + _BLOCK, stop)]))
             for a in range(start, stop, _BLOCK)]
    return np.concatenate(found) if found else np.zeros(0, np.int64)


def _strip(buf: np.ndarray, starts: IntArray, ends: IntArray) -> tuple[IntArray, IntArray]:
    """``starts`` and ``ends`` moved past the blanks at both ends of each span."""
    starts, ends = starts.copy(), ends.copy()
    blank = np.zeros(256, bool)
    blank[list(_BLANKS)] = True
    todo = np.flatnonzero(starts < ends)
    while todo.size:  # one step per leading blank: a file has a few at most
        todo = todo[blank[buf[starts[todo]]]]
        starts[todo] += 1
        todo = todo[starts[todo] < ends[todo]]
    todo = np.flatnonzero(starts < ends)
    while todo.size:
        todo = todo[blank[buf[ends[todo] - 1]]]
        ends[todo] -= 1
        todo = todo[starts[todo] < ends[todo]]
    return starts, ends


@dataclass(frozen=True)
class Cells:
    """The fields of the data rows.

    Attributes
    ----------
    buf : (b,) uint8
        The bytes the fields are in.
    bounds : (n, n_columns + 1) int
        Field ``j`` of row ``i`` is ``buf[bounds[i, j] + 1 : bounds[i, j + 1]]``, blanks
        around it included.
    """

    buf: np.ndarray
    bounds: np.ndarray

    def column(self, j: int, start: int = 0, stop: int | None = None
               ) -> tuple[IntArray, IntArray]:
        """Starts and ends of column ``j``'s cells (of rows ``start:stop``), blanks
        stripped."""
        rows = self.bounds[start:stop]
        return _strip(self.buf, rows[:, j].astype(np.int64) + 1, rows[:, j + 1].astype(np.int64))

    def text(self, i: int, j: int) -> str:
        """Cell ``(i, j)`` as written (stripped)."""
        return cell_text(self.buf, self.bounds[i, j] + 1, self.bounds[i, j + 1]).strip()

    def strings(self, j: int) -> np.ndarray:
        """(n,) str: column ``j``'s cells."""
        starts, ends = self.column(j)
        width = int((ends - starts).max(initial=0))
        codes = np.zeros((len(starts), max(width, 1)), np.uint32)
        at = np.arange(width)
        for a in range(0, len(starts), _ROWS):  # a block of rows at a time: small work arrays
            s, e = starts[a:a + _ROWS, None], ends[a:a + _ROWS, None]
            block = self.buf[np.minimum(s + at, max(len(self.buf) - 1, 0))] if width else 0
            codes[a:a + _ROWS, :width] = np.where(s + at < e, block, 0)
        if np.all(codes < 128):  # ASCII: the code points are the bytes
            return codes.view(f"<U{codes.shape[1]}")[:, 0]
        return np.array([cell_text(self.buf, a, b) for a, b in zip(starts, ends, strict=True)],
                        dtype=np.str_)


@dataclass(frozen=True)
class Lines:
    """The non-blank, non-comment lines of a file (the header first), stripped.

    Attributes
    ----------
    source : str
        The file, for messages.
    numbers : (m,) int
        1-based line number of each.
    buf : (b,) uint8
        The bytes of the file (empty when ``texts`` holds the lines).
    starts, ends : (m,) int
        Each line is ``buf[starts[k]:ends[k]]``.
    texts : list of str, optional
        The lines as the line-by-line reader read them.
    """

    source: str
    numbers: IntArray
    buf: np.ndarray
    starts: IntArray
    ends: IntArray
    texts: list | None = None

    def __len__(self) -> int:
        return len(self.numbers)

    def text(self, k: int) -> str:
        """Line ``k`` as text."""
        if self.texts is not None:
            return self.texts[k]
        return cell_text(self.buf, self.starts[k], self.ends[k])

    def header(self) -> list[str]:
        """The stripped fields of the first line."""
        return fields(self.text(0), int(self.numbers[0]), self.source)

    def cells(self, n: int, header_line: int) -> Cells:
        """Lines 1... split into ``n`` fields each; a line with another count raises."""
        rows = len(self) - 1
        if self.texts is not None:
            return _joined_cells(self.texts[1:], self.numbers[1:], n, header_line, self.source)
        dtype = np.int32 if len(self.buf) < 2**31 - 1 else np.int64
        bounds = np.zeros((rows, n + 1), dtype=dtype)
        for a in range(1, rows + 1, _ROWS):
            b = min(a + _ROWS, rows + 1)
            starts, ends = self.starts[a:b], self.ends[a:b]
            commas = _positions(self.buf, lambda x: x == _COMMA, int(starts[0]), int(ends[-1]))
            line = np.searchsorted(starts, commas, side="right") - 1
            inside = commas < ends[line]  # not those of comment lines in between
            commas, counts = commas[inside], np.bincount(line[inside], minlength=b - a)
            wrong = np.flatnonzero(counts != n - 1)
            if wrong.size:
                _field_count_error(int(counts[wrong[0]]) + 1, n, int(self.numbers[a + wrong[0]]),
                                   header_line, self.source)
            block = bounds[a - 1:b - 1]
            block[:, 0] = starts - 1
            block[:, n] = ends
            block[:, 1:n] = commas.reshape(b - a, n - 1)
        return Cells(self.buf, bounds)


def _field_count_error(count: int, n: int, line: int, header_line: int, source: str):
    hint = ("; decimal commas? write 1.5, not 1,5 (and quote a label holding a comma)"
            if count > n else "")
    raise MeasurementFileError(f"{source}, line {line}: {count} fields, expected {n} as in "
                               f"the header (line {header_line}){hint}", source, line)


def _joined_cells(texts: list[str], numbers: IntArray, n: int, header_line: int,
                  source: str) -> Cells:
    """Cells of lines split one by one (``"..."`` quotes): the stripped fields joined by
    line breaks, which no field holds."""
    rows = []
    for text, line in zip(texts, numbers, strict=True):
        rows.append(fields(text, int(line), source))
        if len(rows[-1]) != n:
            _field_count_error(len(rows[-1]), n, int(line), header_line, source)
    buf = np.frombuffer("\n".join(f for row in rows for f in row).encode("utf-8"), np.uint8)
    breaks = np.r_[-1, _positions(buf, lambda x: x == _NL), len(buf)]
    at = np.arange(len(rows))[:, None] * n + np.arange(n + 1)
    return Cells(buf, breaks[at])


def _fast_lines(raw: bytes, source: str) -> Lines | None:
    """The lines of ``raw`` by the byte scan, or None when it needs the line reader."""
    if any(odd in raw for odd in _ODD) or raw.count(b"\r") != raw.count(b"\r\n"):
        return None
    buf = np.frombuffer(raw, np.uint8)
    breaks = _positions(buf, lambda x: x == _NL)
    starts, ends = _strip(buf, np.r_[0, breaks + 1], np.r_[breaks, len(buf)])
    keep = starts < ends
    keep[keep] = buf[starts[keep]] != _HASH
    numbers = np.flatnonzero(keep) + 1
    lines = Lines(source, numbers, buf, starts[keep], ends[keep])
    if not raw.isascii():  # only comments and the header may hold other text
        if not _utf8(raw):
            return None
        wide = _positions(buf, lambda x: x > 127)
        line = np.searchsorted(lines.starts, wide, side="right") - 1
        if np.any((line >= 1) & (wide < lines.ends[np.maximum(line, 0)])):
            return None
    return lines


def _utf8(raw: bytes) -> bool:
    decoder = codecs.getincrementaldecoder("utf-8")()
    try:
        for a in range(0, len(raw), _BLOCK):
            decoder.decode(raw[a:a + _BLOCK], final=a + _BLOCK >= len(raw))
    except UnicodeDecodeError:
        return False
    return True


def file_lines(path: Path, source: str) -> Lines:
    """The non-blank, non-comment lines of a measurement file."""
    raw = path.read_bytes()
    raw = raw[len(_BOM):] if raw.startswith(_BOM) else raw
    lines = _fast_lines(raw, source)
    if lines is not None:
        return lines
    del raw
    numbers, texts = records(path, source)
    none = np.zeros(len(numbers), np.int64)
    return Lines(source, np.array(numbers, dtype=np.int64), np.zeros(0, np.uint8), none, none,
                 texts)
