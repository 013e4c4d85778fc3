"""The columns of a kind of measurement file: :class:`Field` (one column: name, type,
quantity, canonical unit) and :class:`Schema` (the columns of one kind, in canonical order),
with the column groups every kind shares (joint angles, base-frame vectors).  Reading and
writing the cells by a schema: :mod:`~flexarm.validation.data.formats._table`.
"""

from __future__ import annotations

from dataclasses import dataclass
from fractions import Fraction

from ..measurements import DIRECTIONS
from ..units import QUANTITIES

__all__ = ["Field", "Schema", "joints", "vector"]


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
    group : str or None
        The columns of one array (``"q"`` for ``q1`` ... ``q6``, ``"f"`` for ``fx, fy,
        fz``): :meth:`Table.parse` fills them into one (n, k) array, also given under
        this name.
    """

    base: str
    type: str
    quantity: str | None = None
    unit: str | None = None
    required: bool = True
    group: str | None = None

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
    """``q1`` ... ``q6``: joint angles.

    Examples
    --------
    >>> [f.canonical for f in joints()][:2]
    ['q1_deg', 'q2_deg']
    """
    return tuple(Field(f"q{j}", "real", "angle", unit, group="q") for j in range(1, 7))


def vector(prefix: str, quantity: str, unit: str, required: bool = True) -> tuple[Field, ...]:
    """``<prefix>x``, ``<prefix>y``, ``<prefix>z``: a base-frame vector.

    Examples
    --------
    >>> [f.canonical for f in vector("d", "length", "mm")]
    ['dx_mm', 'dy_mm', 'dz_mm']
    """
    return tuple(Field(prefix + c, "real", quantity, unit, required, prefix or "xyz")
                 for c in DIRECTIONS)
