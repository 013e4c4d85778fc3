"""What notebooks need from the result objects: short reprs and pandas tables.

A repr shows the class, counts, units and a few key figures on one line, never whole
arrays; ``to_dataframe()`` methods build their tables through :func:`data_frame`, which
imports pandas only when a table is asked for.
"""

from __future__ import annotations

from collections.abc import Iterable, Mapping

import numpy as np

from .errors import MissingDependencyError

__all__ = ["pandas", "data_frame", "figure", "span", "names"]


def pandas():
    """The ``pandas`` module, or :class:`MissingDependencyError` naming it."""
    try:
        import pandas as pd
    except ImportError:
        raise MissingDependencyError("pandas", "tables (to_dataframe)") from None
    return pd


def data_frame(columns: Mapping[str, Iterable]):
    """A ``pandas.DataFrame`` of equally long columns, in the order given.

    Examples
    --------
    >>> data_frame({"mode": [1, 2], "f_Hz": [7.5, 16.0]}).columns.tolist()
    ['mode', 'f_Hz']
    """
    return pandas().DataFrame({k: np.asarray(v) for k, v in columns.items()})


def figure(value: float, digits: int = 4) -> str:
    """``value`` to ``digits`` significant digits, without an exponent from 1e-4 to 1e7.

    Examples
    --------
    >>> figure(12891.7), figure(7.5751), figure(2.0), figure(3.2e-9)
    ('12890', '7.575', '2', '3.2e-09')
    """
    value = float(value)
    if value == 0 or not 1e-4 <= abs(value) < 1e7:
        return f"{value:.{digits}g}"
    return np.format_float_positional(value, precision=digits, unique=False,
                                      fractional=False, trim="-")


def span(values, unit: str = "", fmt: str | None = None) -> str:
    """``"min–max unit"`` of ``values`` (one value when they are all equal; ``"none"``
    when empty); numbers by :func:`figure` unless ``fmt`` is given.

    Examples
    --------
    >>> span([12.5, 3.0, 7.0], "Hz")
    '3–12.5 Hz'
    >>> span([2.0, 2.0], "N"), span([], "Hz")
    ('2 N', 'none')
    """
    v = np.asarray(values, dtype=float).ravel()
    if v.size == 0:
        return "none"
    text = figure if fmt is None else fmt.format
    lo, hi = text(float(v.min())), text(float(v.max()))
    text = lo if lo == hi else f"{lo}–{hi}"
    return f"{text} {unit}" if unit else text


def names(items: Iterable, limit: int = 4, width: int = 24) -> str:
    """Up to ``limit`` names joined by commas, with ``"… (+k)"`` for the rest; a name
    longer than ``width`` characters is cut with ``"…"``.

    Examples
    --------
    >>> names(["P1", "P2", "P3", "P4", "P5", "P6"])
    'P1, P2, P3, P4, … (+2)'
    >>> names(["a rather long series label"], width=10)
    'a rather …'
    """
    items = [s if len(s) <= width else s[:width - 1] + "…" for s in map(str, items)]
    text = ", ".join(items[:limit])
    return text + (f", … (+{len(items) - limit})" if len(items) > limit else "")
