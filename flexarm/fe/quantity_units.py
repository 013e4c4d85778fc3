"""The units of each physical quantity a user may type, with their exact sizes in SI.

:data:`QUANTITIES` is the one table of units: every typed number
(:mod:`flexarm.fe.quantities`) and every measurement column
(:mod:`flexarm.validation.data.units`) is read through it.  Sizes are exact fractions, so a
conversion rounds once; the degree is the double ``math.pi / 180``.
"""

from __future__ import annotations

import math
import re
from fractions import Fraction

__all__ = ["QUANTITIES", "accepted_units", "unit_factor", "si_unit"]

#: quantity -> {unit symbol as written canonically: size of one unit in SI, exact}; the
#: first unit of size 1 is the SI unit.  ``""`` is a plain ratio's (no unit).
QUANTITIES: dict[str, dict[str, Fraction]] = {
    "length": {"m": Fraction(1), "mm": Fraction(1, 10**3), "um": Fraction(1, 10**6),
               "cm": Fraction(1, 10**2), "in": Fraction(254, 10**4)},
    "force": {"N": Fraction(1), "kN": Fraction(10**3)},
    "angle": {"deg": Fraction(math.pi / 180), "rad": Fraction(1),
              "mrad": Fraction(1, 10**3), "urad": Fraction(1, 10**6)},
    "moment": {"Nm": Fraction(1), "kNm": Fraction(10**3)},
    "frequency": {"Hz": Fraction(1), "kHz": Fraction(10**3)},
    "receptance": {"m_per_N": Fraction(1), "mm_per_N": Fraction(1, 10**3),
                   "um_per_N": Fraction(1, 10**6)},
    "compliance": {"m/N": Fraction(1), "mm/N": Fraction(1, 10**3), "um/N": Fraction(1, 10**6)},
    "stiffness": {"N/m": Fraction(1), "kN/m": Fraction(10**3), "N/mm": Fraction(10**3),
                  "N/um": Fraction(10**6), "kN/mm": Fraction(10**6)},
    "torsional stiffness": {"Nm/rad": Fraction(1), "kNm/rad": Fraction(10**3),
                            "Nm/mrad": Fraction(10**3)},
    "time": {"s": Fraction(1), "ms": Fraction(1, 10**3)},
    "speed": {"m/s": Fraction(1), "mm/s": Fraction(1, 10**3)},
    "mass": {"kg": Fraction(1), "g": Fraction(1, 10**3), "t": Fraction(10**3)},
    "ratio": {"": Fraction(1), "%": Fraction(1, 100)},
    "memory": {"B": Fraction(1), "kB": Fraction(2**10), "MB": Fraction(2**20),
               "GB": Fraction(2**30)},
}

_LOOKUP = {q: {sym.lower(): sym for sym in units} for q, units in QUANTITIES.items()}


def accepted_units(quantity: str) -> list[str]:
    """Unit symbols accepted for ``quantity``, canonical spelling.

    Examples
    --------
    >>> accepted_units("force")
    ['N', 'kN']
    """
    return list(QUANTITIES[quantity])


def si_unit(quantity: str) -> str:
    """The SI unit of ``quantity`` (``""`` for a ratio).

    Examples
    --------
    >>> si_unit("angle"), si_unit("stiffness")
    ('rad', 'N/m')
    """
    return next(sym for sym, f in QUANTITIES[quantity].items() if f == 1)


def unit_factor(quantity: str, unit: str) -> tuple[str, Fraction] | None:
    """Canonical symbol and exact SI size of ``unit``, or ``None`` if not accepted.

    Parameters
    ----------
    quantity : str
        A key of :data:`QUANTITIES`.
    unit : str
        The suffix as written (case-insensitive; ``µm`` is ``um``; spaces, ``*`` and
        ``·`` between the parts are ignored: ``N m`` is ``Nm``).

    Examples
    --------
    >>> unit_factor("length", "UM")
    ('um', Fraction(1, 1000000))
    >>> unit_factor("length", "ft") is None
    True
    """
    # the micro sign and Greek mu both read as "u"
    key = re.sub(r"[\s*\u00b7]", "", unit).lower().replace("\u00b5", "u").replace("\u03bc", "u")
    symbol = _LOOKUP[quantity].get(key)
    return None if symbol is None else (symbol, QUANTITIES[quantity][symbol])
