"""Numbers a user types, read once: a text becomes a finite, range-checked float.

Every number typed on the command line, in an ``--effect`` value or in an environment
variable goes through :class:`Quantity` (counts through :func:`parse_count`), so the
same rule holds everywhere:

* A value is ``<number>[<unit>]``: a decimal (``800``, ``-5e5``, ``.5``), then optionally a
  unit of its quantity, with or without a space, case-insensitive (``0.8kN``, ``25 um``,
  ``25µm``, ``400Nm``).  :data:`QUANTITIES` (:mod:`flexarm.fe.quantity_units`) lists
  the units of each quantity.
* A bare number is read in the unit the option states (``--force 800`` is 800 N,
  ``--step 2`` is 2 mm).  Where a bare number would be ambiguous (the lengths and angles of
  ``lab --noise``, ``--ref-noise`` and ``--effect``) a unit is required: ``25`` is
  refused with "give a unit, e.g. 25um"; only ``0`` needs none.
* The value must be finite and inside the quantity's plausible range: ``nan``, ``inf``,
  ``1e30`` N or a negative stiffness are refused with one line naming the option, the
  text and the range (``--force 1e30: outside 0..1e6 N``).

Conversion is exact to one rounding: ``"15um"`` read in metres is the double nearest to
15e-6 (the same double as ``float("1.5e-5")``), as the measurement columns of
:mod:`flexarm.validation.data.units` are read; the degree is the double ``math.pi / 180``.
"""

from __future__ import annotations

import math
import os
import re
from dataclasses import dataclass
from fractions import Fraction

import numpy as np

from .quantity_units import QUANTITIES, accepted_units, si_unit, unit_factor

# the unit table's names are part of this module's interface too (callers import them here)
__all__ = ["QUANTITIES", "Quantity", "accepted_units", "unit_factor", "si_unit",
           "parse_count", "parse_list", "parse_levels", "parse_band", "env_number"]

_NUMBER = re.compile(r"([+-]?(?:[0-9]+\.?[0-9]*|\.[0-9]+)(?:[eE][+-]?[0-9]+)?)\s*(.*)", re.S)
_NOT_FINITE = re.compile(r"[+-]?(?:nan|inf|infinity)", re.I)
_INTEGER = re.compile(r"[+-]?[0-9]+")
#: What a unit starts with: a letter (µ included), ``%``; or nothing.
_UNIT_START = re.compile(r"$|[^\W\d_]|%")
#: Beyond these magnitudes the exact scaling would build huge integers (``1e99999999``):
#: such a value is out of every plausible range anyway, and scaled in floating point.
_EXACT_RANGE = (1e-300, 1e300)
#: Characters of a typed text repeated in a message.
_SHOWN_CHARS = 40


def _num(x: float) -> str:
    """Short text of a number: ``1e6``, ``1e4``, ``1000``, ``0.001``, ``-5e5``."""
    plain = f"{x:.6g}"
    if not math.isfinite(x):
        return plain
    mantissa, _, exponent = f"{x:.5e}".partition("e")
    short = f"{mantissa.rstrip('0').rstrip('.')}e{int(exponent)}"
    return short if "e" in plain or len(short) <= len(plain) - 2 else plain


def _label(what: str | None, text: str) -> str:
    """``--force 1e30``, ``FLEXARM_MEMORY_GB=abc`` (``what`` ending in ``=``), or the text;
    a long text is cut short (the line stays readable)."""
    if len(text) > _SHOWN_CHARS:
        text = text[:_SHOWN_CHARS - 3] + "..."
    if not what:
        return text
    return f"{what}{text}" if what.endswith("=") else f"{what} {text}"


def _scaled(number: str, factor: Fraction) -> float:
    """The decimal ``number`` times ``factor``, rounded once."""
    x = float(number)
    if factor == 1 or x == 0 or not _EXACT_RANGE[0] < abs(x) < _EXACT_RANGE[1]:
        return x * float(factor)
    return float(Fraction(number) * factor)


@dataclass(frozen=True)
class Quantity:
    """What a typed number means: its quantity, its unit, whether it may be bare, its range.

    Attributes
    ----------
    kind : str
        A key of :data:`QUANTITIES` (``"force"``, ``"length"``, ``"ratio"`` ...).
    unit : str or None
        The unit of the range, of a bare number and (unless ``result``) of the value
        returned (default: the SI unit).
    low, high : float
        Plausible range, in ``unit``.
    open_low, open_high : bool
        The bound itself is refused (``open_low`` with ``low = 0``: must be > 0).
    bare : bool
        A number without a unit is read in ``unit``; False: a unit is required (except
        for 0), e.g. for lengths and angles whose unit a reader could mistake.
    result : str or None
        Unit of the returned value (default: ``unit``).
    hint : str or None
        Unit of the example in the "give a unit" message (default: ``unit``).

    Examples
    --------
    >>> force = Quantity("force", "N", 0, 1e6)
    >>> force.parse("800"), force.parse("0.8kN")
    (800.0, 800.0)
    >>> force.parse("1e30", "--force")
    Traceback (most recent call last):
    ...
    ValueError: --force 1e30: outside 0..1e6 N
    >>> Quantity("length", "um", 0, 1e4, bare=False, result="m").parse("15um")
    1.5e-05
    """

    kind: str
    unit: str | None = None
    low: float = -math.inf
    high: float = math.inf
    open_low: bool = False
    open_high: bool = False
    bare: bool = True
    result: str | None = None
    hint: str | None = None

    def __post_init__(self) -> None:
        if self.kind not in QUANTITIES:
            raise ValueError(f"unknown quantity '{self.kind}' (known: {', '.join(QUANTITIES)})")
        for unit in (self.unit, self.result, self.hint):
            if unit is not None and unit not in QUANTITIES[self.kind]:
                raise ValueError(f"unknown {self.kind} unit '{unit}' "
                                 f"(accepted: {self.units_text()})")

    @property
    def shown(self) -> str:
        """The unit of the range and of bare numbers."""
        return si_unit(self.kind) if self.unit is None else self.unit

    def units_text(self) -> str:
        """``N, kN``: the units a value may carry."""
        return ", ".join(u for u in QUANTITIES[self.kind] if u)

    def range_text(self) -> str:
        """``0..1e6 N`` or ``> 0 and <= 10 m``.

        Examples
        --------
        >>> Quantity("length", "m", 0, 10, open_low=True).range_text()
        '> 0 and <= 10 m'
        """
        unit = f" {self.shown}" if self.shown else ""
        if not (self.open_low or self.open_high) and math.isfinite(self.low + self.high):
            return f"{_num(self.low)}..{_num(self.high)}{unit}"
        sides = []
        if math.isfinite(self.low):
            sides.append(f"{'>' if self.open_low else '>='} {_num(self.low)}")
        if math.isfinite(self.high):
            sides.append(f"{'<' if self.open_high else '<='} {_num(self.high)}")
        return " and ".join(sides) + unit

    def _refuse_range(self, value: float, label: str) -> None:
        inside = ((self.low < value if self.open_low else self.low <= value)
                  and (value < self.high if self.open_high else value <= self.high))
        if not inside:
            text = self.range_text()
            raise ValueError(f"{label}: {'outside' if '..' in text else 'must be'} {text}")

    def check(self, value: float, what: str | None = None) -> float:
        """``value`` (already in ``unit``, e.g. from a TOML file) if finite and in range.

        Examples
        --------
        >>> Quantity("mass", "kg", 0, 1e4).check(float("nan"), "links.frame.mass")
        Traceback (most recent call last):
        ...
        ValueError: links.frame.mass nan: not a finite number
        """
        value = float(value)
        label = _label(what, _num(value))
        if not math.isfinite(value):
            raise ValueError(f"{label}: not a finite number")
        self._refuse_range(value, label)
        return value

    def parse(self, text: str | float, what: str | None = None) -> float:
        """The value of ``text`` in ``result`` (default ``unit``), checked.

        Parameters
        ----------
        text : str or float
            ``"<number>[<unit>]"``; a float is taken as already in ``unit``.
        what : str, optional
            Name of the value in messages: an option (``--force``), or a key ending in
            ``=`` (``FLEXARM_MEMORY_GB=``).

        Raises
        ------
        ValueError
            One line naming ``what``, the text and what is wrong with it.
        """
        to = self.result or self.shown
        if not isinstance(text, str):  # already a number in ``unit``
            return self._convert(repr(self.check(text, what)), self.shown, to)
        label = _label(what, text)
        stripped = text.strip()
        if not stripped:
            raise ValueError(f"{_label(what, repr(text))}: empty, expected a number"
                             + (f" ({self.units_text()})" if self.units_text() else ""))
        if _NOT_FINITE.fullmatch(stripped):
            raise ValueError(f"{label}: not a finite number")
        m = _NUMBER.fullmatch(stripped)
        if m is None or not _UNIT_START.match(m.group(2)):  # "1.2.3", "5x"
            units = self.units_text()
            raise ValueError(f"{label}: not a number" + (
                f" (expected e.g. 1.5{self.hint or self.shown or units.split(', ')[0]}; "
                f"units: {units})" if units else ""))
        number, unit = m.groups()
        if not unit:
            if not self.bare and float(number) != 0:
                example = self.hint or self.shown
                raise ValueError(f"{label}: give a unit, e.g. {number}{example} "
                                 f"(accepted: {self.units_text()})")
            symbol = self.shown
        else:
            found = unit_factor(self.kind, unit)
            if found is None or not found[0]:
                raise ValueError(f"{label}: unknown {self.kind} unit '{unit}' "
                                 f"(accepted: {self.units_text()})")
            symbol = found[0]
        self._refuse_range(self._convert(number, symbol, self.shown), label)
        return self._convert(number, symbol, to)

    def _convert(self, number: str, unit: str, to: str) -> float:
        units = QUANTITIES[self.kind]
        return _scaled(number, units[unit] / units[to])


def parse_count(text: str | int, what: str | None = None, low: int = 0,
                high: int = 2**31 - 1) -> int:
    """A whole number ``low <= n <= high`` from ``text``.

    Examples
    --------
    >>> parse_count("24", "--frames", 2, 200)
    24
    >>> parse_count("0", "--frames", 2, 200)
    Traceback (most recent call last):
    ...
    ValueError: --frames 0: outside 2..200
    """
    label = _label(what, str(text) if str(text).strip() else repr(text))
    if isinstance(text, str):
        stripped = text.strip()
        if not _INTEGER.fullmatch(stripped):
            raise ValueError(f"{label}: not a whole number")
        digits = stripped.lstrip("+-")
        if len(digits) > 18:  # beyond any range here (and int() of 4300+ digits refuses)
            raise ValueError(f"{label}: outside {low}..{high}")
        text = int(stripped)
    if not low <= int(text) <= high:
        raise ValueError(f"{label}: outside {low}..{high}")
    return int(text)


def parse_list(text: str, quantity: Quantity, what: str | None = None,
               n: int | None = None) -> list[float]:
    """Comma-separated values of ``quantity``: ``"0,200,400"`` -> ``[0.0, 200.0, 400.0]``.

    Parameters
    ----------
    n : int, optional
        The number of values required (``x,y,z``: 3).

    Examples
    --------
    >>> parse_list("0, 0.2kN", Quantity("force", "N", 0, 1e6))
    [0.0, 200.0]
    """
    fields = text.split(",")
    if not text.strip() or any(not f.strip() for f in fields):
        raise ValueError(f"{_label(what, repr(text))}: expected comma-separated values, "
                         f"none empty" + (f" ({n} of them)" if n else ""))
    if n is not None and len(fields) != n:
        raise ValueError(f"{_label(what, text)}: expected {n} values, got {len(fields)}")
    return [quantity.parse(f.strip(), what) for f in fields]


def parse_levels(text: str, quantity: Quantity, what: str | None = None,
                 max_count: int = 1000) -> np.ndarray:
    """(k,) float: ``"start:stop:step"`` (stop included) or a comma list of ``quantity``.

    Examples
    --------
    >>> parse_levels("0:800:200", Quantity("force", "N", 0, 1e6)).tolist()
    [0.0, 200.0, 400.0, 600.0, 800.0]
    """
    if ":" not in text:
        values = parse_list(text, quantity, what)
        if len(values) > max_count:
            raise ValueError(f"{_label(what, text)}: {len(values)} levels, at most {max_count}")
        return np.array(values, dtype=float)
    parts = text.split(":")
    if len(parts) != 3:
        raise ValueError(f"{_label(what, text)}: expected start:stop:step, e.g. 0:800:100")
    a, b = (quantity.parse(p, what) for p in parts[:2])
    c = quantity.parse(parts[2], what)
    if not c > 0 or b < a:
        raise ValueError(f"{_label(what, text)}: need start <= stop and step > 0")
    count = (b - a) / c + 1  # inf for a subnormal step
    if not count < max_count + 0.5:
        raise ValueError(f"{_label(what, text)}: {_num(round(count, 0))} levels, at most "
                         f"{max_count}")
    return np.arange(a, b + c / 2, c)


def parse_band(text: str, quantity: Quantity, what: str | None = None) -> tuple[float, float]:
    """``"LO:HI"`` -> (lo, hi) of ``quantity`` with lo < hi.

    Examples
    --------
    >>> parse_band("2:160", Quantity("frequency", "Hz", 0, 1e5))
    (2.0, 160.0)
    """
    parts = text.split(":")
    if len(parts) != 2:
        raise ValueError(f"{_label(what, text)}: expected LO:HI, e.g. 2:160")
    lo, hi = (quantity.parse(p, what) for p in parts)
    if not lo < hi:
        raise ValueError(f"{_label(what, text)}: expected LO < HI")
    return lo, hi


def env_number(name: str, quantity: Quantity) -> float | None:
    """The environment variable ``name`` read as ``quantity`` (None when unset or empty);
    a bad value is refused with one line naming the variable.

    Examples
    --------
    >>> env_number("FLEXARM_NO_SUCH_VARIABLE", Quantity("memory", "GB", 0, 1e6)) is None
    True
    """
    text = os.environ.get(name, "")
    return quantity.parse(text, f"{name}=") if text.strip() else None
