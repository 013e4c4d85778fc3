"""Decimal cells of a byte buffer read in bulk, exactly: a million rows in numpy, not in
Python strings.

A cell is the bytes ``buf[start:end]`` (blanks already stripped).  :func:`scan` reads
every cell of a column at once, one byte position at a time across all cells, into an
integer mantissa ``m`` and a decimal exponent ``k`` (the cell is ``±m·10^k``) and says
which cells are not plain decimals (the grammar of the measurement schema:
``[+-]digits[.digits][e[+-]digits]``, no ``_``, no ``nan``).

:func:`reals` turns them into doubles in SI with one rounding, bit for bit what
:func:`~flexarm.validation.data.units.parse_values` gives: ``m`` below 2^53 and ``|k|``
at most 22 are exact doubles, so one multiplication or division by ``10^|k|`` is the
correctly rounded result (Clinger's fast path; a unit that is a power of ten only shifts
``k``).  Other cells, and units that are not powers of ten (degrees), go through the
exact parser once per distinct ``(m, k)``.
"""

from __future__ import annotations

import math
import re
from fractions import Fraction

import numpy as np

from ...fe.typing import FloatArray, IntArray

__all__ = ["REAL", "INTEGER", "scan", "reals", "integers", "cell_text", "decimal_shift"]

#: A plain decimal and an integer cell, as the schemas define them.
REAL = re.compile(r"[+-]?(?:[0-9]+\.?[0-9]*|\.[0-9]+)(?:[eE][+-]?[0-9]+)?")
INTEGER = re.compile(r"[+-]?[0-9]+")

#: Cells of more bytes than this are read one by one (no measurement is written so).
MAX_CELL = 40
#: Rows scanned at a time: the (rows, bytes) work arrays stay a few MB.
_CHUNK = 1 << 16
_DIGITS_U64 = 19  # any 19-digit mantissa fits in uint64
_EXACT = 2**53  # integers up to this are exact doubles
_POW10_U64 = np.array([10**k for k in range(_DIGITS_U64 + 1)], dtype=np.uint64)
_POW10 = np.array([10.0**k for k in range(23)])  # exact doubles
_PLUS, _MINUS, _DOT, _E, _UPPER_E = (ord(c) for c in "+-.eE")


def cell_text(buf: np.ndarray, start: int, end: int) -> str:
    """The cell ``buf[start:end]`` as text (for messages and the exact parser)."""
    return bytes(buf[start:end]).decode("utf-8", errors="replace")


def decimal_shift(factor: Fraction) -> int | None:
    """``k`` if ``factor`` is ``10**k`` (mm: -3, kN: 3, 1: 0), else None.

    Examples
    --------
    >>> decimal_shift(Fraction(1, 1000)), decimal_shift(Fraction(1)), decimal_shift(Fraction(3))
    (-3, 0, None)
    """
    for k in range(-12, 13):
        if factor == Fraction(10) ** k:
            return k
    return None


def scan(buf: np.ndarray, starts: IntArray, ends: IntArray, integer: bool = False):
    """Mantissa, exponent, sign and verdict of every cell.

    Parameters
    ----------
    buf : (b,) uint8
        The bytes holding the cells.
    starts, ends : (n,) int
        Cell ``i`` is ``buf[starts[i]:ends[i]]``, blanks stripped.
    integer : bool
        Integers only (``[+-]digits``).

    Returns
    -------
    m : (n,) uint64
        Mantissa digits (leading zeros and the point dropped); 0 where not ``exact``.
    k : (n,) int64
        Decimal exponent: the cell is ``±m·10^k``.
    negative : (n,) bool
    bad : (n,) bool
        Not a plain decimal (or integer, :data:`REAL`, :data:`INTEGER`): empty, a stray
        character, no digit.
    exact : (n,) bool
        ``m`` and ``k`` are complete (false for a valid cell of more than 19 mantissa
        digits, a 5-digit exponent or more than :data:`MAX_CELL` bytes: read it with
        :func:`cell_text`).

    Examples
    --------
    >>> b = np.frombuffer(b"-1.50e2|.5|1_0|7.", np.uint8)
    >>> m, k, neg, bad, exact = scan(b, np.array([0, 8, 11, 15]), np.array([7, 10, 14, 17]))
    >>> m.tolist(), k.tolist(), neg.tolist(), bad.tolist()
    ([150, 5, 0, 7], [0, -1, 0, 0], [True, False, False, False], [False, False, True, False])
    """
    starts = np.asarray(starts, dtype=np.int64)
    ends = np.asarray(ends, dtype=np.int64)
    n = len(starts)
    out = (np.zeros(n, np.uint64), np.zeros(n, np.int64), np.zeros(n, bool),
           np.zeros(n, bool), np.zeros(n, bool))
    for a in range(0, n, _CHUNK):
        part = _scan_chunk(buf, starts[a:a + _CHUNK], ends[a:a + _CHUNK], integer)
        for whole, piece in zip(out, part, strict=True):
            whole[a:a + _CHUNK] = piece
    return out


def _scan_chunk(buf, starts, ends, integer):
    """:func:`scan` of up to ``_CHUNK`` cells: one pass per byte position, each step over
    the cells' bytes at that position (a small state machine, vectorised)."""
    lens = ends - starts
    n = len(lens)
    width = int(min(lens.max(initial=0), MAX_CELL))
    at = np.arange(width)[:, None]
    c = buf[np.minimum(starts + at, max(len(buf) - 1, 0))] if len(buf) else \
        np.zeros((width, n), np.uint8)
    c = np.where(at < lens, c, np.uint8(0))  # (width, n): byte j of every cell, 0 past its end
    m = np.zeros(n, np.uint64)
    digits, fraction = np.zeros(n, np.int64), np.zeros(n, np.int64)
    e, e_digits, e_at = np.zeros(n, np.int64), np.zeros(n, np.int64), np.full(n, -2, np.int64)
    dot, e_negative, bad = np.zeros(n, bool), np.zeros(n, bool), lens == 0
    negative = c[0] == _MINUS if width else np.zeros(n, bool)
    signed = negative | (c[0] == _PLUS) if width else negative
    exponents = not integer and bool(np.any((c | 32) == _E))  # e or E anywhere
    for j in range(width):
        cj = c[j]
        inside = j < lens
        d = cj - np.uint8(48)  # wraps: a non-digit is >= 10
        is_digit = d < 10
        mant = is_digit if not exponents else is_digit & (e_at < 0)
        ok = mant | ~inside
        if not integer:
            point = cj == _DOT
            if exponents:
                point &= e_at < 0
                new_e = ((cj | 32) == _E) & (e_at < 0) & inside
                in_exp = (e_at >= 0) & inside
                sign = in_exp & (e_at == j - 1) & ((cj == _PLUS) | (cj == _MINUS))
                e_negative |= sign & (cj == _MINUS)
                exp_digit = in_exp & is_digit
                e = np.where(exp_digit, e * 10 + d, e)
                e_digits += exp_digit
                e_at = np.where(new_e, j, e_at)
                ok |= new_e | sign | exp_digit
            bad |= point & dot  # a second point
            dot |= point
            fraction += mant & dot
            ok |= point
        if j == 0:
            ok |= signed
        bad |= ~ok
        m = np.where(mant, m * np.uint64(10) + d, m)
        digits += mant
    bad |= (digits == 0) | ((e_at >= 0) & (e_digits == 0))
    long = np.flatnonzero(lens > MAX_CELL)  # decided cell by cell
    grammar = INTEGER if integer else REAL
    bad[long] = [not grammar.fullmatch(cell_text(buf, starts[i], ends[i])) for i in long]
    exact = ~bad & (digits <= _DIGITS_U64) & (e_digits <= 4) & (lens <= MAX_CELL)
    k = np.where(e_negative, -e, e) - fraction
    return np.where(exact, m, np.uint64(0)), k, negative, bad, exact


def reals(buf: np.ndarray, starts: IntArray, ends: IntArray, factor: Fraction
          ) -> tuple[FloatArray, np.ndarray]:
    """(n,) float: the cells in a unit of size ``factor`` [SI], one rounding; and (n,)
    bool, the cells that are not plain decimals (their value is 0).

    Examples
    --------
    >>> b = np.frombuffer(b"1.5 -2 0.1e-2 x", np.uint8)
    >>> v, bad = reals(b, [0, 4, 7, 14], [3, 6, 13, 15], Fraction(1, 1000))
    >>> v.tolist(), bad.tolist()
    ([0.0015, -0.002, 1e-06, 0.0], [False, False, False, True])
    """
    m, k, negative, bad, exact = scan(buf, starts, ends)
    shift = decimal_shift(factor)
    values = np.zeros(len(m))
    if shift is not None:
        k = k + shift
        fast = exact & (m < np.uint64(_EXACT)) & (np.abs(k) <= 22)
        mf = m[fast].astype(np.float64)
        kf = k[fast]
        scale = _POW10[np.abs(kf)]
        values[fast] = np.where(kf >= 0, mf * scale, mf / scale)
    else:
        # joint angles repeat within a series: the exact product once per run of equal
        # cells, and once per distinct value among the runs
        fast = exact & (np.abs(k) < 400)
        rows = np.flatnonzero(fast)
        new = np.ones(len(rows), bool)
        new[1:] = (m[rows[1:]] != m[rows[:-1]]) | (k[rows[1:]] != k[rows[:-1]])
        known: dict[tuple[int, int], float] = {}
        once = []
        for key in zip(m[rows[new]].tolist(), k[rows[new]].tolist(), strict=True):
            if key not in known:
                known[key] = _scaled(Fraction(key[0]) * Fraction(10) ** key[1], factor)
            once.append(known[key])
        values[rows] = np.repeat(once, np.diff(np.r_[np.flatnonzero(new), len(rows)]))
    values = np.where(negative, -values, values)
    if shift != 0:
        values = values + 0.0  # the exact parser reads "-0" as 0 (a Fraction has no sign)
    starts = np.asarray(starts)
    ends = np.asarray(ends)
    for i in np.flatnonzero(~fast & ~bad):  # long or huge: the exact parser
        text = cell_text(buf, starts[i], ends[i])
        values[i] = float(text) if factor == 1 else _scaled(Fraction(text), factor)
    return values, bad


def _scaled(value: Fraction, factor: Fraction) -> float:
    try:
        return float(value * factor)
    except OverflowError:  # 1e400: infinite, and refused as implausible by the caller
        return math.inf if value > 0 else -math.inf


def integers(buf: np.ndarray, starts: IntArray, ends: IntArray
             ) -> tuple[IntArray, np.ndarray]:
    """(n,) int64 of integer cells and (n,) bool, the cells that are not integers or do
    not fit in 64 bits (a magnitude below 2^63).

    Examples
    --------
    >>> b = np.frombuffer(b"12 -3 4.0", np.uint8)
    >>> v, bad = integers(b, [0, 3, 6], [2, 5, 9])
    >>> v.tolist(), bad.tolist()
    ([12, -3, 0], [False, False, True])
    """
    m, _, negative, bad, exact = scan(buf, starts, ends, integer=True)
    fits = exact & (m < np.uint64(2**63))
    values = np.where(fits, m, 0).astype(np.int64)
    values = np.where(negative, -values, values)
    return values, bad | ~fits
