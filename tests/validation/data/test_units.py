"""Unit suffixes and exact SI conversion (flexarm/validation/units.py)."""

from __future__ import annotations

import math
import re
from fractions import Fraction

import numpy as np
import pytest

from flexarm.validation import read_static
from flexarm.validation.data.units import (
    QUANTITIES,
    accepted_units,
    format_values,
    parse_quantity,
    parse_values,
    si_factor,
    split_column,
    unit_factor,
)


@pytest.mark.parametrize(("quantity", "unit", "factor"), [
    ("length", "um", 1e-6), ("length", "in", 0.0254), ("length", "cm", 0.01),
    ("force", "kN", 1e3), ("angle", "rad", 1.0), ("angle", "deg", math.pi / 180),
    ("angle", "urad", 1e-6), ("moment", "kNm", 1e3), ("frequency", "kHz", 1e3),
    ("receptance", "mm_per_N", 1e-3),
])
def test_si_factor(quantity, unit, factor):
    assert si_factor(quantity, unit) == factor


def test_suffixes_are_case_insensitive_and_accept_micro_signs():
    assert unit_factor("force", "KN") == ("kN", Fraction(1000))
    assert unit_factor("frequency", "hz") == ("Hz", Fraction(1))
    assert unit_factor("length", "\u00b5m")[0] == "um"
    assert unit_factor("length", "\u03bcm")[0] == "um"
    assert unit_factor("length", "ft") is None
    with pytest.raises(ValueError, match="unknown length unit 'ft' "
                                         r"\(accepted: m, mm, um, cm, in\)"):
        si_factor("length", "ft")


def test_every_quantity_has_its_si_unit_and_unique_lowercase_symbols():
    for quantity, units in QUANTITIES.items():
        assert 1 in units.values(), quantity
        assert len({u.lower() for u in units}) == len(units)
        assert accepted_units(quantity) == list(units)


def test_split_column():
    assert split_column("dx_mm") == ("dx", "mm")
    assert split_column("im_um_per_N") == ("im", "um_per_N")
    assert split_column("pose") == ("pose", None)


def test_parse_is_one_correct_rounding():
    # "1.5" mm is the double nearest to 1.5e-3, i.e. float("0.0015")
    texts = ["1.5", "0.1", "-7e-3", "123456.789", ".5", "3."]
    got = parse_values(texts, Fraction(1, 1000))
    assert got.tolist() == [0.0015, 0.0001, -7e-06, 123.456789, 0.0005, 0.003]
    assert parse_values(["170", "-90"], QUANTITIES["angle"]["deg"]).tolist() == \
        np.deg2rad([170.0, -90.0]).tolist()


@pytest.mark.parametrize("quantity", sorted(QUANTITIES))
def test_format_then_parse_is_bit_exact(quantity):
    rng = np.random.default_rng(7)
    values = rng.normal(size=400) * 10.0 ** rng.integers(-9, 4, size=400)
    values = np.r_[values, 0.0, 1.0, -2.5, 1e-300]
    for factor in QUANTITIES[quantity].values():
        back = parse_values(format_values(values, factor), factor)
        assert np.array_equal(back, values)


def test_format_is_short_for_round_numbers():
    assert format_values([0.0015, 0.2, 0.0], Fraction(1, 1000)) == ["1.5", "200.0", "0.0"]
    assert format_values(np.deg2rad([52.0, -19.0]), QUANTITIES["angle"]["deg"]) == \
        ["52.0", "-19.0"]


def test_file_units_are_converted_to_si(tmp_path):
    path = tmp_path / "units.csv"
    path.write_text(
        "series, step, q1_rad, q2_deg, q3_mrad, q4_urad, q5_deg, q6_deg, fx_kN, fy_N, fz_kN,"
        " dx_um, dy_cm, dz_in, mx_kNm, my_Nm, mz_Nm, rx_urad, ry_rad, rz_mrad, sigma_um\n"
        "s, 0, 0.5, 90, 10, 20, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 15\n"
        "s, 1, 0.5, 90, 10, 20, 0, 0, 0.8, 5, -1.5, 150, 0.02, 0.001, 0.25, 3, 0, 40, 1e-4, 0.1,"
        " 15\n"
    )
    d = read_static(path)
    assert d.q[0, :4].tolist() == [0.5, float(np.deg2rad(90.0)), 0.01, 2e-05]
    assert d.force[1].tolist() == [800.0, 5.0, -1500.0]
    assert d.disp[1].tolist() == [0.00015, 0.0002, 2.54e-05]
    assert d.moment[1].tolist() == [250.0, 3.0, 0.0]
    assert d.rot[1].tolist() == [4e-05, 0.0001, 0.0001]
    assert d.sigma.tolist() == [1.5e-05, 1.5e-05]


def test_parse_quantity_is_one_rounding_like_a_column():
    # 15 * 1e-6 is one ulp below 1.5e-5; the text reads as the nearest double
    assert parse_quantity("15um") == 1.5e-5 and 15 * 1e-6 != 1.5e-5
    assert parse_quantity(" 0.1 mrad ", "angle") == 1e-4
    assert parse_quantity("170deg", "angle") == float(np.deg2rad(170.0))
    assert parse_quantity("2KN", "force") == 2000.0 and parse_quantity("15µm") == 1.5e-5
    assert parse_quantity("-4.5e-5") == -4.5e-5 and parse_quantity(3e-6) == 3e-6
    assert parse_quantity("0um") == 0.0


@pytest.mark.parametrize(("text", "message"), [
    ("15parsec", "noise 15parsec: unknown length unit 'parsec' (accepted: m, mm, um, cm, in)"),
    ("um", "noise um: not a number (expected e.g. 1.5m; units: m, mm, um, cm, in)"),
    ("1.2.3um", "noise 1.2.3um: not a number"),
    ("nan", "noise nan: not a finite number"),
])
def test_parse_quantity_errors_name_the_value(text, message):
    with pytest.raises(ValueError, match=re.escape(message)):
        parse_quantity(text, "length", what="noise")
