"""The CSV layer shared by every measurement kind: header, cells, errors (the schemas:
:mod:`~flexarm.validation.data.formats._schema`).

A measurement file is UTF-8 text: one header row, then data rows.  Lines whose first
non-blank character is ``#`` are comments and blank lines are ignored, anywhere.
Fields are comma-separated (blanks after commas allowed, ``"..."`` quotes a label
holding a comma).  Every error names the file, the line and, where there is one,
the column as written in the header.
"""

from __future__ import annotations

import csv
from dataclasses import dataclass
from fractions import Fraction
from pathlib import Path

import numpy as np

from ....fe.files import atomic_path
from ....fe.notebook import data_frame
from ....fe.typing import IntArray, PathType
from ..decimals import INTEGER, REAL, integers, reals
from ..measurements import DIRECTIONS
from ..units import accepted_units, format_values, split_column, unit_factor
from ._cells import Cells, file_lines
from ._lines import MeasurementFileError
from ._schema import Field, Schema, joints, vector

# the schemas' names are part of this module's interface too (the kinds import them here)
__all__ = ["MeasurementFileError", "Field", "Schema", "Column", "Table", "read_table",
           "write_table", "table_frame", "label_problem", "joints", "vector"]

#: Largest magnitude [SI] a measured value of each quantity may have: beyond it the unit
#: or the export is wrong (1e300 mm, a force in mN read as N), and the analysis would
#: turn it into overflow.  Angles: two turns.
PLAUSIBLE = {"length": 100.0, "force": 1e7, "moment": 1e7, "angle": 4 * np.pi,
             "frequency": 1e6}
#: Rows converted at a time (the work arrays stay a few MB).
_ROWS = 1 << 16


def label_problem(label: str) -> str | None:
    """Why ``label`` cannot be a series/pose label in a file, or ``None`` if it can."""
    if not label:
        return "empty value"
    if label.startswith("#") or "\n" in label or "\r" in label:
        return f"label {label!r} must not start with '#' or hold a line break"
    return None


@dataclass(frozen=True)
class Column:
    """A header entry: its name as written, position and exact unit size."""

    name: str
    index: int
    factor: Fraction


@dataclass(frozen=True)
class Table:
    """The raw cells of a measurement file, with where each came from.

    Attributes
    ----------
    source : str
        File name used in messages.
    header_line : int
        Line number of the header.
    names : tuple of str
        Column names as written in the header.
    columns : dict
        Known base name -> :class:`Column`.
    unknown : tuple of str
        Header names that no measurement kind knows.
    cells : Cells
        The fields of the data rows (a byte buffer and the bounds of each field: a
        million rows as Python strings would take gigabytes).
    lines : (n,) int
        Line number of each data row.
    """

    source: str
    header_line: int
    names: tuple[str, ...]
    columns: dict[str, Column]
    unknown: tuple[str, ...]
    cells: Cells
    lines: IntArray

    def error(self, row: int | None, base: str | None, message: str) -> MeasurementFileError:
        """Error at data row ``row`` (``None``: the header) and column ``base``."""
        line = self.header_line if row is None else int(self.lines[row])
        name = None if base is None else self.columns[base].name
        where = f"{self.source}, line {line}" + ("" if name is None else f", column '{name}'")
        return MeasurementFileError(f"{where}: {message}", self.source, line, name)

    def text(self, row: int, base: str) -> str:
        """The cell of data row ``row`` in column ``base``, as written."""
        return self.cells.text(row, self.columns[base].index)

    def require(self, schema: Schema, guessed: bool = False) -> None:
        """Raise unless the header has all required and only known columns of ``schema``."""
        missing = [schema.field(b).canonical for b in schema.required if b not in self.columns]
        if missing:
            how = " (kind guessed from the other columns)" if guessed else ""
            plural = "s" if len(missing) > 1 else ""
            raise self.error(None, None, f"missing required column{plural} "
                             f"{', '.join(repr(m) for m in missing)} for {schema.noun}{how}")
        known = {c.name for b, c in self.columns.items() if b in schema.vocabulary}
        extra = sorted(set(self.unknown) | (set(self.names) - known), key=self.names.index)
        if extra:
            names = ", ".join(f.canonical for f in schema.fields)
            where = f"{self.source}, line {self.header_line}, column '{extra[0]}'"
            raise MeasurementFileError(
                f"{where}: unknown column for {schema.noun} (known: {names})",
                self.source, self.header_line, extra[0])

    def parse(self, schema: Schema, guessed: bool = False) -> dict[str, np.ndarray]:
        """Check the header against ``schema`` and convert every present column.

        Returns base -> (n,) array: ``str`` labels and directions, ``int64`` integers,
        ``float64`` reals in SI; and group -> (n, k) array for each group of columns all
        present (``"q"``: the joint angles; the columns are views of it).  The arrays are
        read-only.  The first bad cell in file order raises.
        """
        self.require(schema, guessed)
        n = len(self.lines)
        values, problems = {}, []
        members: dict[str, list[Field]] = {}
        for field in schema.fields:
            if field.group is not None:
                members.setdefault(field.group, []).append(field)
        for group, fields_ in members.items():
            if all(f.base in self.columns for f in fields_):
                values[group] = np.zeros((n, len(fields_)))
        for field in schema.fields:
            if field.base not in self.columns:
                continue
            out = None
            if field.group in values:
                out = values[field.group][:, members[field.group].index(field)]
            values[field.base], problem = self._convert(field, out)
            if problem is not None:
                problems.append((problem[0], self.columns[field.base].index, field.base,
                                 problem[1]))
        if problems:
            row, _, base, message = min(problems)
            raise self.error(row, base, message)
        for v in values.values():
            v.setflags(write=False)
        return values

    def _convert(self, field: Field, out: np.ndarray | None = None
                 ) -> tuple[np.ndarray, tuple[int, str] | None]:
        j = self.columns[field.base].index
        if field.type in ("label", "direction"):
            texts = self.cells.strings(j)
            wrong = _string_problems(field.type, texts)
            if wrong.size:
                return texts, (int(wrong[0]), _cell_problem(field.type, str(texts[wrong[0]])))
            return (np.char.lower(texts) if field.type == "direction" else texts), None
        n = len(self.lines)
        if out is None:
            out = np.zeros(n, np.int64 if field.type == "int" else np.float64)
        factor = self.columns[field.base].factor
        for a in range(0, n, _ROWS):  # a block of rows at a time: small work arrays
            starts, ends = self.cells.column(j, a, a + _ROWS)
            if field.type == "int":
                out[a:a + _ROWS], bad = integers(self.cells.buf, starts, ends)
            else:
                out[a:a + _ROWS], bad = reals(self.cells.buf, starts, ends, factor)
            if bad.any():
                i = a + int(np.argmax(bad))
                return out, (i, _cell_problem(field.type, self.text(i, field.base)))
        bound = PLAUSIBLE.get(field.quantity)
        big = np.flatnonzero(np.abs(out) > bound) if bound is not None else ()
        if len(big):
            i, column = int(big[0]), self.columns[field.base]
            limit, unit = bound / float(column.factor), split_column(column.name)[1]
            return out, (i, f"{self.text(i, field.base)} is not a plausible {field.quantity}"
                            f" (more than {limit:.4g} {unit}): is the unit in the header "
                            "right?")
        return out, None


def _string_problems(kind: str, texts: np.ndarray) -> np.ndarray:
    """Rows whose label (or direction) cell is wrong, vectorised over the code points."""
    codes = texts.view(np.uint32).reshape(len(texts), -1)
    first = codes[:, 0]
    if kind == "direction":
        wrong = (codes[:, 1:] != 0).any(axis=1) | ~np.isin(first | 32, [ord(c) for c in DIRECTIONS])
    else:
        wrong = (first == 0) | (first == ord("#")) | np.isin(codes, [10, 13]).any(axis=1)
    return np.flatnonzero(wrong)


def _cell_problem(kind: str, text: str) -> str:
    if not text:
        return "empty value"
    if kind == "real" and not REAL.fullmatch(text):
        try:
            number = float(text)
        except ValueError:
            number = 0.0
        return f"{text!r} is not a {'finite ' if not np.isfinite(number) else ''}number"
    if kind == "int":
        return (f"{text!r} is not an integer" if not INTEGER.fullmatch(text) else
                f"{text} does not fit in a 64-bit integer")
    if kind == "direction" and text.lower() not in DIRECTIONS:
        return f"{text!r} is not a direction (x, y or z)"
    return label_problem(text) or f"{text!r} cannot be read"


def _header(names: list[str], line: int, source: str, vocabulary: dict[str, Field]):
    columns, unknown, seen = {}, [], {}

    def fail(name, message):
        return MeasurementFileError(f"{source}, line {line}, column '{name}': {message}",
                                    source, line, name)

    for index, name in enumerate(names):
        if not name:
            raise MeasurementFileError(f"{source}, line {line}: column {index + 1} has no name",
                                       source, line)
        base, suffix = name.lower(), None
        if base not in vocabulary or vocabulary[base].quantity is not None:
            base, suffix = split_column(name)
            base = base.lower()
        field = vocabulary.get(base)
        key = base if field is not None else name.lower()
        if key in seen:
            raise fail(name, f"duplicate column (already given as '{seen[key]}')")
        seen[key] = name
        if field is None or (field.quantity is None and suffix is not None):
            unknown.append(name)
            continue
        factor = Fraction(1)
        if field.quantity is not None:
            units = ", ".join(accepted_units(field.quantity))
            if suffix is None:
                raise fail(name, f"missing unit suffix (a {field.quantity}: {units}, "
                                 f"e.g. '{field.canonical}')")
            found = unit_factor(field.quantity, suffix)
            if found is None:
                raise fail(name, f"unknown unit '{suffix}' for a {field.quantity} "
                                 f"(accepted: {units})")
            factor = found[1]
        columns[base] = Column(name, index, factor)
    return columns, tuple(unknown)


def read_table(path: PathType, vocabulary: dict[str, Field]) -> Table:
    """Read the header and the data rows of a measurement file.

    Parameters
    ----------
    path : path-like
        The CSV file.
    vocabulary : dict
        Base name -> :class:`Field` of every column the caller knows; others are
        kept in ``Table.unknown``.

    Raises
    ------
    MeasurementFileError
        Empty file, bad header (unnamed, duplicate, unknown unit), a row with the
        wrong number of fields, or no data rows.
    """
    path = Path(path)
    source = str(path)
    lines = file_lines(path, source)
    if not len(lines):
        raise MeasurementFileError(f"{source}: no header row (the file is empty or only "
                                   "holds comments)", source)
    header_line, names = int(lines.numbers[0]), lines.header()
    separator = next((c for c in ";\t" if len(names) == 1 and c in names[0]), None)
    if separator is not None:
        raise MeasurementFileError(
            f"{source}, line {header_line}: the fields are separated by {separator!r}; "
            f"flexarm reads comma-separated files with '.' decimals (export as CSV with ',' "
            f"separators)", source, header_line)
    numbers_found = [n for n in names if REAL.fullmatch(n)]
    if numbers_found:  # a data row where the header belongs: say so, not "duplicate 0"
        shown = ", ".join(numbers_found[:3]) + (", ..." if len(numbers_found) > 3 else "")
        raise MeasurementFileError(
            f"{source}, line {header_line}: no header row: the first row that is not a "
            f"comment holds numbers ({shown}) where the column names belong; add the "
            "header line (e.g. 'series, step, q1_deg, ...' for static series; see "
            "flexarm.validation for every kind)", source, header_line)
    columns, unknown = _header(names, header_line, source, vocabulary)
    if len(lines) == 1:
        raise MeasurementFileError(f"{source}, line {header_line}: no data rows after the "
                                   "header", source, header_line)
    cells = lines.cells(len(names), header_line)
    return Table(source, header_line, tuple(names), columns, unknown, cells, lines.numbers[1:])


def write_table(path: PathType, schema: Schema, values: dict[str, np.ndarray],
                comments=()) -> Path:
    """Write ``values`` (base -> (n,) array in SI) as a ``schema`` file, atomically.

    Columns come in schema order with canonical units; optional columns appear when
    present in ``values``.  ``comments`` become ``#`` lines after the title line.
    """
    present = [f for f in schema.fields if values.get(f.base) is not None]
    texts = []
    for f in present:
        v = values[f.base]
        texts.append(format_values(v, f.factor) if f.type == "real" else [str(x) for x in v])
    lines = [f"# flexarm {schema.kind} measurements (see flexarm.validation for the schema)"]
    lines += [f"# {c}".rstrip() for comment in comments for c in str(comment).splitlines()]
    with atomic_path(path) as tmp:
        with open(tmp, "w", encoding="utf-8", newline="") as out:
            out.write("\n".join(lines) + "\n")
            writer = csv.writer(out, lineterminator="\n")
            writer.writerow([f.canonical for f in present])
            writer.writerows(zip(*texts, strict=True))
    return Path(path)


def table_frame(schema: Schema, values: dict[str, np.ndarray]):
    """``pandas.DataFrame`` of ``values`` (base -> (n,) array in SI) with the columns
    :func:`write_table` writes: schema order, canonical names and units (``dx_mm``)."""
    present = [f for f in schema.fields if values.get(f.base) is not None]
    columns = {}
    for f in present:
        v = np.asarray(values[f.base])
        columns[f.canonical] = v * float(1 / f.factor) if f.type == "real" else v
    return data_frame(columns)
