"""Length units of CAD files and robot descriptions (the ``units`` setting), and the one
unit receptance and compliance are shown in."""

from __future__ import annotations

__all__ = ["LENGTH_UNITS", "length_factor", "RECEPTANCE_UNIT", "RECEPTANCE_SCALE"]

#: unit name -> metres per unit
LENGTH_UNITS: dict[str, float] = {"m": 1.0, "mm": 1e-3, "cm": 1e-2, "in": 0.0254}

#: Receptance and compliance on plots and in tables: mm/kN (= µm/N), ``RECEPTANCE_SCALE``
#: times the SI value [m/N]; files keep m/N.
RECEPTANCE_UNIT, RECEPTANCE_SCALE = "mm/kN", 1e6


def length_factor(units: str) -> float:
    """Metres per ``units`` (``"m"``, ``"mm"``, ``"cm"``, ``"in"``).

    Examples
    --------
    >>> length_factor("mm")
    0.001
    """
    try:
        return LENGTH_UNITS[units]
    except KeyError:
        raise ValueError(f"unknown units {units!r}; expected one of "
                         f"{', '.join(map(repr, LENGTH_UNITS))}") from None
