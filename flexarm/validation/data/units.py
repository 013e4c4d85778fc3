"""Unit suffixes of measurement columns and exact conversion to and from SI.

A physical column is named ``<base>_<unit>`` (``dx_mm``, ``fy_kN``, ``q2_deg``).  The
base fixes the quantity (length, force, ...); the suffix picks one of the accepted
units of that quantity.  Suffixes are matched case-insensitively, and ``µm``/``μm``
are accepted for ``um``.

Conversions are exact to one rounding: a decimal text ``"1.5"`` in mm becomes the
double nearest to 1.5e-3 (the same double as ``float("0.0015")``), and
:func:`format_values` writes the shortest text that reads back to the same double.
So reading a written file gives bit-identical arrays.  The degree factor is the
double ``math.pi / 180``, so ``"170"`` deg reads as exactly ``np.deg2rad(170)``.
The unit tables are those of every typed number, :mod:`flexarm.fe.quantities`.
"""

from __future__ import annotations

import math
from decimal import Context, Decimal
from fractions import Fraction

import numpy as np

from ...fe.quantities import QUANTITIES, Quantity, accepted_units, si_unit, unit_factor
from ...fe.typing import ArrayLike, FloatArray
from .decimals import reals

__all__ = [
    "QUANTITIES",
    "accepted_units",
    "unit_factor",
    "si_factor",
    "split_column",
    "parse_values",
    "parse_decimal_column",
    "format_values",
    "parse_quantity",
]

_DIGITS = 17  # significant digits that always identify a double


def si_factor(quantity: str, unit: str) -> float:
    """Size of one ``unit`` in SI, as a float (for display and rough work).

    Examples
    --------
    >>> si_factor("force", "kN")
    1000.0
    """
    found = unit_factor(quantity, unit)
    if found is None:
        raise ValueError(f"unknown {quantity} unit '{unit}' "
                         f"(accepted: {', '.join(accepted_units(quantity))})")
    return float(found[1])


def parse_quantity(text: str | float, quantity: str = "length", what: str | None = None
                   ) -> float:
    """SI value of a number with an optional unit suffix, ``"15um"`` -> ``1.5e-05``.

    The decimal is scaled exactly and rounded once, like a measurement column, so
    ``"15um"`` is the double nearest to 15e-6 (not ``15 * 1e-6``, one ulp below).

    Parameters
    ----------
    text : str or float
        ``"<number>[<unit>]"`` with a unit of ``quantity`` (case-insensitive, space
        allowed: ``"0.1 mrad"``); a bare number, or a float, is already SI.
    quantity : str
        A key of :data:`QUANTITIES`.
    what : str, optional
        Name of the value in error messages (default: ``quantity``).

    Examples
    --------
    >>> parse_quantity("15um"), parse_quantity("2kN", "force"), parse_quantity("0.02")
    (1.5e-05, 2000.0, 0.02)
    """
    if not isinstance(text, str):
        return float(text)
    return Quantity(quantity, si_unit(quantity)).parse(text, what or quantity)


def split_column(name: str) -> tuple[str, str | None]:
    """Split a column name at its first underscore into base and unit suffix.

    Examples
    --------
    >>> split_column("re_m_per_N")
    ('re', 'm_per_N')
    >>> split_column("series")
    ('series', None)
    """
    base, sep, unit = name.partition("_")
    return base, (unit if sep else None)


def parse_values(texts: list[str], factor: Fraction) -> FloatArray:
    """(n,) float: decimal ``texts`` in a unit of size ``factor`` [SI], one rounding.

    Parameters
    ----------
    texts : list of str, length n
        Plain decimal numbers (already checked, e.g. ``"-1.5e-3"``).
    factor : Fraction
        Size of the unit in SI (from :func:`unit_factor`).

    Examples
    --------
    >>> parse_values(["1.5", "-2"], Fraction(1, 1000)).tolist()
    [0.0015, -0.002]
    """
    if factor == 1:
        return np.array(texts, dtype=np.float64).reshape(len(texts))
    return np.array([float(Fraction(t) * factor) for t in texts], dtype=np.float64)


def format_values(values: ArrayLike, factor: Fraction) -> list[str]:
    """Shortest decimal texts of SI ``values`` in a unit of size ``factor``.

    ``parse_values(format_values(v, f), f)`` returns ``v`` bit for bit.

    Parameters
    ----------
    values : (n,) float
        Values in SI.
    factor : Fraction
        Size of the target unit in SI.

    Examples
    --------
    >>> format_values([0.0015, 1e-3 / 3], Fraction(1, 1000))
    ['1.5', '0.3333333333333333']
    """
    values = np.asarray(values, dtype=np.float64).ravel()
    if factor == 1:
        return [repr(float(v)) for v in values]
    return [_shortest(float(v), factor) for v in values]


def _shortest(value: float, factor: Fraction) -> str:
    exact = Fraction(value) / factor
    try:
        nearest = float(exact)
    except OverflowError:
        nearest = math.inf
    if math.isfinite(nearest):
        # reprs of the nearest doubles are short; keep the shortest that reads back exactly
        candidates = [nearest]
        for direction in (math.inf, -math.inf):
            y = nearest
            for _ in range(2):
                y = math.nextafter(y, direction)
                candidates.append(y)
        texts = [repr(y) for y in candidates if math.isfinite(y)]
        good = [t for t in texts if float(Fraction(t) * factor) == value]
        if good:
            return min(good, key=len)
    # The nearest 17-digit decimal lies inside the rounding interval of any double.
    dec = Context(prec=_DIGITS).divide(Decimal(exact.numerator), Decimal(exact.denominator))
    text = f"{dec:g}"
    assert float(Fraction(text) * factor) == value, (value, text)
    return text


def parse_decimal_column(texts: list[str], factor: Fraction) -> np.ndarray | None:
    """:func:`parse_values` of a column whose every cell is a plain finite decimal,
    vectorised (bit for bit the same values, :func:`~.decimals.reals`); None when a cell
    is not (then the cells are checked one by one for the message).

    Examples
    --------
    >>> parse_decimal_column(["1.5", "-2e1"], Fraction(1, 1000)).tolist()
    [0.0015, -0.02]
    >>> parse_decimal_column(["1", "nan"], Fraction(1)) is None
    True
    """
    encoded = [t.encode("utf-8") for t in texts]
    ends = np.cumsum([len(b) + 1 for b in encoded], dtype=np.int64) - 1
    buf = np.frombuffer(b"\n".join(encoded), np.uint8)
    values, bad = reals(buf, ends - [len(b) for b in encoded], ends, factor)
    return None if bad.any() or not np.all(np.isfinite(values)) else values
