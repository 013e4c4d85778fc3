"""The CSV layer shared by every measurement kind: schemas, header, cells, errors.

A measurement file is UTF-8 text: one header row, then data rows.  Lines whose first
non-blank character is ``#`` are comments and blank lines are ignored, anywhere.
Fields are comma-separated (blanks after commas allowed, ``"..."`` quotes a label
holding a comma).  Every error names the file, the line and, where there is one,
the column as written in the header.
"""

from __future__ import annotations

import csv
import re
from dataclasses import dataclass
from fractions import Fraction
from pathlib import Path

import numpy as np

from ....fe.files import atomic_path
from ....fe.notebook import data_frame
from ....fe.typing import IntArray, PathType
from ..measurements import DIRECTIONS
from ..units import (
    QUANTITIES,
    accepted_units,
    format_values,
    parse_decimal_column,
    parse_values,
    split_column,
    unit_factor,
)
from ._lines import MeasurementFileError, column_texts, fields, records

__all__ = ["MeasurementFileError", "Field", "Schema", "Column", "Table", "read_table",
           "write_table", "table_frame", "label_problem", "joints", "vector"]

#: Largest magnitude [SI] a measured value of each quantity may have: beyond it the unit
#: or the export is wrong (1e300 mm, a force in mN read as N), and the analysis would
#: turn it into overflow.  Angles: two turns.
PLAUSIBLE = {"length": 100.0, "force": 1e7, "moment": 1e7, "angle": 4 * np.pi,
             "frequency": 1e6}
_INT = re.compile(r"[+-]?[0-9]+")
_REAL = re.compile(r"[+-]?(?:[0-9]+\.?[0-9]*|\.[0-9]+)(?:[eE][+-]?[0-9]+)?")


def label_problem(label: str) -> str | None:
    """Why ``label`` cannot be a series/pose label in a file, or ``None`` if it can."""
    if not label:
        return "empty value"
    if label.startswith("#") or "\n" in label or "\r" in label:
        return f"label {label!r} must not start with '#' or hold a line break"
    return None


@dataclass(frozen=True)
class Field:
    """One column of a schema.

    Attributes
    ----------
    base : str
        Name without unit suffix (``"dx"``, ``"series"``).
    type : str
        ``"label"``, ``"int"``, ``"real"`` or ``"direction"``.
    quantity : str or None
        Physical quantity (a key of ``QUANTITIES``): the column needs a unit suffix.
    unit : str or None
        Canonical unit, used when writing.
    required : bool
        Whether every file of the kind has this column.
    """

    base: str
    type: str
    quantity: str | None = None
    unit: str | None = None
    required: bool = True

    @property
    def canonical(self) -> str:
        """Column name as written by flexarm (``"dx_mm"``)."""
        return self.base if self.unit is None else f"{self.base}_{self.unit}"

    @property
    def factor(self) -> Fraction:
        """Exact SI size of the canonical unit (1 for unitless columns)."""
        return Fraction(1) if self.quantity is None else QUANTITIES[self.quantity][self.unit]


@dataclass(frozen=True)
class Schema:
    """The columns of one kind of measurement file, in canonical order."""

    kind: str
    fields: tuple[Field, ...]
    #: "a static file", for messages
    noun: str = ""

    def __post_init__(self) -> None:
        if not self.noun:
            object.__setattr__(self, "noun", f"a {self.kind} file")

    def field(self, base: str) -> Field:
        """The field called ``base``."""
        return next(f for f in self.fields if f.base == base)

    @property
    def required(self) -> list[str]:
        """Bases of the required columns."""
        return [f.base for f in self.fields if f.required]

    @property
    def vocabulary(self) -> dict[str, Field]:
        """Base name -> field."""
        return {f.base: f for f in self.fields}


def joints(unit: str = "deg") -> tuple[Field, ...]:
    """``q1`` ... ``q6``: joint angles."""
    return tuple(Field(f"q{j}", "real", "angle", unit) for j in range(1, 7))


def vector(prefix: str, quantity: str, unit: str, required: bool = True) -> tuple[Field, ...]:
    """``<prefix>x``, ``<prefix>y``, ``<prefix>z``: a base-frame vector."""
    return tuple(Field(prefix + c, "real", quantity, unit, required) for c in DIRECTIONS)


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
    cells : tuple of str
        Stripped fields of the data rows, one string per header column with its cells
        joined by newlines (which no cell holds): a million rows as Python strings
        would take gigabytes.
    lines : (n,) int
        Line number of each data row.
    """

    source: str
    header_line: int
    names: tuple[str, ...]
    columns: dict[str, Column]
    unknown: tuple[str, ...]
    cells: tuple[str, ...]
    lines: IntArray

    def error(self, row: int | None, base: str | None, message: str) -> MeasurementFileError:
        """Error at data row ``row`` (``None``: the header) and column ``base``."""
        line = self.header_line if row is None else int(self.lines[row])
        name = None if base is None else self.columns[base].name
        where = f"{self.source}, line {line}" + ("" if name is None else f", column '{name}'")
        return MeasurementFileError(f"{where}: {message}", self.source, line, name)

    def text(self, row: int, base: str) -> str:
        """The cell of data row ``row`` in column ``base``, as written."""
        return self.cells[self.columns[base].index].split("\n")[row]  # error paths only

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
        ``float64`` reals in SI.  The first bad cell in file order raises.
        """
        self.require(schema, guessed)
        values, problems = {}, []
        for field in schema.fields:
            if field.base in self.columns:
                values[field.base], problem = self._convert(field)
                if problem is not None:
                    problems.append((problem[0], self.columns[field.base].index, field.base,
                                     problem[1]))
        if problems:
            row, _, base, message = min(problems)
            raise self.error(row, base, message)
        return values

    def _convert(self, field: Field) -> tuple[np.ndarray, tuple[int, str] | None]:
        j = self.columns[field.base].index
        texts = self.cells[j].split("\n")
        factor = self.columns[field.base].factor
        values = parse_decimal_column(texts, factor) if field.type == "real" else None
        for i, t in enumerate(texts if values is None else ()):
            problem = _cell_problem(field.type, t)
            if problem is not None:
                return np.zeros(0), (i, problem)
        if field.type == "real":
            values = parse_values(texts, self.columns[field.base].factor) if values is None \
                else values
            bound = PLAUSIBLE.get(field.quantity)
            big = np.flatnonzero(np.abs(values) > bound) if bound is not None else ()
            if len(big):
                i, column = int(big[0]), self.columns[field.base]
                limit, unit = bound / float(column.factor), split_column(column.name)[1]
                return values, (i, f"{texts[i]} is not a plausible {field.quantity} (more "
                                   f"than {limit:.4g} {unit}): is the unit in the header "
                                   f"right?")
            return values, None
        if field.type == "int":
            return np.array([int(t) for t in texts], dtype=np.int64), None
        if field.type == "direction":
            return np.array([t.lower() for t in texts], dtype=np.str_), None
        return np.array(texts, dtype=np.str_), None


def _cell_problem(kind: str, text: str) -> str | None:
    if not text:
        return "empty value"
    if kind == "real" and not _REAL.fullmatch(text):
        try:
            number = float(text)
        except ValueError:
            number = 0.0
        return f"{text!r} is not a {'finite ' if not np.isfinite(number) else ''}number"
    if kind == "int" and not _INT.fullmatch(text):
        return f"{text!r} is not an integer"
    if kind == "direction" and text.lower() not in DIRECTIONS:
        return f"{text!r} is not a direction (x, y or z)"
    if kind == "label":
        return label_problem(text)
    return None


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
    numbers, lines = records(path, source)
    if not lines:
        raise MeasurementFileError(f"{source}: no header row (the file is empty or only "
                                   "holds comments)", source)
    header_line, names = numbers[0], fields(lines[0], numbers[0], source)
    separator = next((c for c in ";\t" if len(names) == 1 and c in names[0]), None)
    if separator is not None:
        raise MeasurementFileError(
            f"{source}, line {header_line}: the fields are separated by {separator!r}; "
            f"flexarm reads comma-separated files with '.' decimals (export as CSV with ',' "
            f"separators)", source, header_line)
    numbers_found = [n for n in names if _REAL.fullmatch(n)]
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
    del lines[0], numbers[0]
    cells = column_texts(lines, numbers, len(names), header_line, source)
    return Table(source, header_line, tuple(names), columns, unknown, cells,
                 np.array(numbers, dtype=np.int64))


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
