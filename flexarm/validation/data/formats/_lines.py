"""The line-by-line reader of measurement files: comments and blank lines dropped, fields
split at commas (quoted ones through the csv module).  Every error names the file and the
line.  Files the byte scan of :mod:`._cells` reads are only split here for their header."""

from __future__ import annotations

import csv
from pathlib import Path

from ....fe.errors import ReadError

__all__ = ["MeasurementFileError", "records", "fields"]


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
