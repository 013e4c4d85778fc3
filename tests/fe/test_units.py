"""Length units: metres per unit against the SI definitions (1 in = 25.4 mm exactly), and the
message for an unknown unit."""

from __future__ import annotations

import pytest

from flexarm.fe.units import LENGTH_UNITS, length_factor


@pytest.mark.parametrize("unit, metres", [("m", 1.0), ("mm", 1e-3), ("cm", 1e-2),
                                          ("in", 0.0254)])
def test_factors(unit, metres):
    assert length_factor(unit) == metres
    assert LENGTH_UNITS[unit] == metres


def test_conversions_are_consistent():
    assert 1000 * length_factor("mm") == pytest.approx(length_factor("m"), rel=1e-15)
    assert 10 * length_factor("mm") == pytest.approx(length_factor("cm"), rel=1e-15)
    assert length_factor("in") / length_factor("mm") == pytest.approx(25.4, rel=1e-15)
    assert set(LENGTH_UNITS) == {"m", "mm", "cm", "in"}


def test_unknown_unit():
    with pytest.raises(ValueError, match="^unknown units 'ft'; expected one of 'm', 'mm', "
                                         "'cm', 'in'$"):
        length_factor("ft")
