"""Lines of a measurement file to column texts: comments and blank lines dropped, fields
split at commas (quoted ones through the csv module), checked against the header's count.
Every error names the file and the line."""

from __future__ import annotations

import csv
import re
from pathlib import Path

from ....fe.errors import ReadError

__all__ = ["MeasurementFileError", "records", "fields", "column_texts"]


class MeasurementFileError(ReadError):
    """A measurement file is malformed; knows where.

    Attributes
    ----------
    path : str
        The file as given.
    line : int or None
        1-based line number in the file.
    column : str or None
        Column name as written in the header.
    """

    def __init__(self, message: str, path: str, line: int | None = None,
                 column: str | None = None):
        super().__init__(message)
        self.path, self.line, self.column = path, line, column


def records(path: Path, source: str) -> tuple[list[int], list[str]]:
    """Line numbers and stripped text of every non-comment, non-blank line."""
    try:
        text = path.read_text(encoding="utf-8-sig")
    except UnicodeDecodeError as exc:
        raise MeasurementFileError(f"{source}: not a UTF-8 text file ({exc.reason} at byte "
                                   f"{exc.start})", source) from None
    numbers, records, lines = [], [], text.splitlines()
    del text
    for number, line in enumerate(lines, start=1):
        stripped = line.strip()
        if stripped and not stripped.startswith("#"):
            numbers.append(number)
            records.append(stripped)
    return numbers, records


def fields(record: str, number: int, source: str) -> list[str]:
    """The stripped fields of one line (``"..."`` quotes a field holding a comma)."""
    if '"' not in record:  # what the csv module would do, without its cost
        return [f.strip() for f in record.split(",")]
    try:
        row = next(csv.reader([record], skipinitialspace=True, strict=True))
    except csv.Error as exc:
        raise MeasurementFileError(f"{source}, line {number}: malformed CSV ({exc})",
                                   source, number) from None
    return [f.strip() for f in row]


#: Lines split at a time (their fields exist as Python strings only chunk by chunk).
_CHUNK_ROWS = 65536
#: A comma with the blanks around it (never a line break: lines are joined by them).
_SEPARATOR = re.compile(r"[^\S\n]*,[^\S\n]*")


def column_texts(records: list[str], numbers: list[int], n: int, header_line: int,
                  source: str) -> tuple[str, ...]:
    """Each column's fields joined by newlines; a line with other than ``n`` fields raises.
    ``records`` is emptied as it goes."""
    def check(count: int, k: int) -> None:
        if count != n:
            hint = ("; decimal commas? write 1.5, not 1,5 (and quote a label holding a "
                    "comma)" if count > n else "")
            raise MeasurementFileError(
                f"{source}, line {numbers[k]}: {count} fields, expected {n} as in the header "
                f"(line {header_line}){hint}", source, numbers[k])

    parts: list[list[str]] = [[] for _ in range(n)]
    for start in range(0, len(records), _CHUNK_ROWS):
        chunk = records[start:start + _CHUNK_ROWS]
        block = "\n".join(chunk)
        if '"' in block:  # quoted fields: the csv module, line by line
            got = []
            for k, record in enumerate(chunk, start=start):
                row = fields(record, numbers[k], source)
                check(len(row), k)
                got += row
        else:  # split the whole chunk at once
            for k, record in enumerate(chunk, start=start):
                check(record.count(",") + 1, k)
            got = _SEPARATOR.sub(",", block).replace("\n", ",").split(",")
        for j in range(n):
            parts[j].append("\n".join(got[j::n]))
        records[start:start + len(chunk)] = [""] * len(chunk)  # done: free the line texts
    return tuple("\n".join(p) for p in parts)
