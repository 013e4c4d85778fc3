"""Typed numbers (flexarm/fe/quantities.py): exact units, ranges, nan/inf, signs, counts,
lists, levels, bands, environment variables and the one-line messages."""

from __future__ import annotations

import math
import re
from decimal import Decimal, localcontext

import numpy as np
import pytest

from flexarm.fe.quantities import (
    QUANTITIES,
    Quantity,
    env_number,
    parse_band,
    parse_count,
    parse_levels,
    parse_list,
    si_unit,
    unit_factor,
)

FORCE = Quantity("force", "N", 0, 1e6)
METRES = Quantity("length", "m")


def exact(message: str) -> str:
    return "^" + re.escape(message) + "$"


def test_decimal_units_scale_with_one_rounding():
    # an independent exact product: Decimal at 60 digits, then one rounding to a double
    rng = np.random.default_rng(3)
    texts = [f"{m:.{d}f}e{e}" for m, d, e in zip(rng.normal(size=300) * 1e3,
                                                 rng.integers(0, 9, 300),
                                                 rng.integers(-12, 12, 300), strict=True)]
    with localcontext() as ctx:
        ctx.prec = 60
        for text in texts:
            assert METRES.parse(f"{text}mm") == float(Decimal(text) * Decimal("0.001"))
            assert METRES.parse(f"{text} um") == float(Decimal(text) * Decimal("1e-6"))
            assert Quantity("force", "N").parse(f"{text}kN") == float(Decimal(text) * 1000)
    # 15 * 1e-6 is one ulp below the double nearest to 15e-6
    assert METRES.parse("15um") == 1.5e-5 != 15 * 1e-6


def test_degrees_are_the_double_pi_over_180():
    rad = Quantity("angle", "rad")
    assert rad.parse("170deg") == float(np.deg2rad(170.0))
    assert Quantity("angle", "deg").parse("0.5rad") == pytest.approx(math.degrees(0.5),
                                                                     rel=1e-15)


def test_bare_numbers_are_in_the_stated_unit_and_suffixes_convert():
    step = Quantity("length", "mm", 0, 1000, open_low=True)
    assert step.parse("2") == 2.0 and step.parse("0.5cm") == 5.0 and step.parse("2mm") == 2.0
    assert FORCE.parse("800") == 800.0 and FORCE.parse("0.8kN") == 800.0
    assert Quantity("ratio", "%").parse("5") == 5.0 and Quantity("ratio").parse("5%") == 0.05
    to_m = Quantity("length", "mm", -1e4, 1e4, result="m")
    assert to_m.parse("1.5") == 0.0015 and to_m.parse("-2cm") == -0.02


def test_spelling_of_units():
    assert METRES.parse("25 UM") == METRES.parse("25\u00b5m") == METRES.parse("25\u03bcm")
    assert Quantity("moment", "Nm").parse("0.4 kN m") == 400.0
    assert Quantity("moment", "Nm").parse("400N*m") == 400.0
    assert Quantity("torsional stiffness").parse("2e7 Nm/rad") == 2e7
    assert Quantity("stiffness").parse("0.5N/um") == 5e5
    assert unit_factor("memory", "gb")[0] == "GB" and si_unit("ratio") == ""


def test_every_unit_symbol_is_unique_and_every_quantity_has_its_si_unit():
    for kind, units in QUANTITIES.items():
        assert si_unit(kind) in units, kind
        assert len({u.lower() for u in units}) == len(units), kind


@pytest.mark.parametrize("text", ["nan", "NaN", "inf", "-inf", "+Infinity", " nan "])
def test_nan_and_inf_are_refused(text):
    with pytest.raises(ValueError, match=exact(f"--force {text}: not a finite number")):
        FORCE.parse(text, "--force")


@pytest.mark.parametrize("text, message", [
    ("1e30", "--force 1e30: outside 0..1e6 N"),
    ("1e999", "--force 1e999: outside 0..1e6 N"),  # read as inf, still out of range
    ("1e99999999", "--force 1e99999999: outside 0..1e6 N"),  # no giant exact integer
    ("-800", "--force -800: outside 0..1e6 N"),
    ("1001kN", "--force 1001kN: outside 0..1e6 N"),
    ("800Nm", "--force 800Nm: unknown force unit 'Nm' (accepted: N, kN)"),
    ("lots", "--force lots: not a number (expected e.g. 1.5N; units: N, kN)"),
    ("1.2.3", "--force 1.2.3: not a number (expected e.g. 1.5N; units: N, kN)"),
    ("", "--force '': empty, expected a number (N, kN)"),
    ("8" * 60, "--force " + "8" * 37 + "...: outside 0..1e6 N"),
])
def test_messages_name_the_option_the_text_and_the_range(text, message):
    with pytest.raises(ValueError, match=exact(message)):
        FORCE.parse(text, "--force")


def test_bounds_are_inclusive_unless_open():
    assert FORCE.parse("0") == 0.0 and FORCE.parse("1e6") == 1e6
    positive = Quantity("length", "m", 0, 10, open_low=True)
    assert positive.parse("1e-300") == 1e-300
    with pytest.raises(ValueError, match=exact("--size 0: must be > 0 and <= 10 m")):
        positive.parse("0", "--size")
    with pytest.raises(ValueError, match=exact("-0.5: must be > -0.5 and < 0.5")):
        Quantity("ratio", "", -0.5, 0.5, open_low=True, open_high=True).parse("-0.5")
    with pytest.raises(ValueError, match=exact("--dt 1e-5 s: must be >= 0.001 s")):
        Quantity("time", "s", 1e-3).parse("1e-5 s", "--dt")


def test_negative_numbers_are_values_where_legal():
    angle = Quantity("angle", "deg", -360, 360)
    assert angle.parse("-1") == -1.0 and angle.parse("-.5") == -0.5
    assert angle.parse("-5e1") == -50.0 and angle.parse("-0.1rad") == pytest.approx(
        -math.degrees(0.1), rel=1e-15)
    with pytest.raises(ValueError, match=exact("--kc -5e5: outside 0..1e10 N/m")):
        Quantity("stiffness", "N/m", 0, 1e10).parse("-5e5", "--kc")


def test_a_required_unit_is_asked_for_except_for_zero():
    noise = Quantity("length", "um", 0, 1e4, bare=False, result="m")
    assert noise.parse("25um") == 2.5e-5 and noise.parse("0") == 0.0
    with pytest.raises(ValueError, match=exact(
            "--noise 25: give a unit, e.g. 25um (accepted: m, mm, um, cm, in)")):
        noise.parse("25", "--noise")
    with pytest.raises(ValueError, match=exact("--noise -25um: outside 0..1e4 um")):
        noise.parse("-25um", "--noise")


def test_check_of_numbers_already_read():
    mass = Quantity("mass", "kg", 0, 1e4, open_low=True)
    assert mass.check(19.0) == 19.0
    with pytest.raises(ValueError, match=exact("lumped.mass 1.9e9: must be > 0 and <= 1e4 kg")):
        mass.check(1.9e9, "lumped.mass")
    with pytest.raises(ValueError, match=exact("lumped.mass -inf: not a finite number")):
        mass.check(-math.inf, "lumped.mass")
    assert Quantity("length", "mm", result="m").parse(1.5) == 0.0015  # a float is in mm


def test_a_quantity_with_an_unknown_unit_is_a_programming_error():
    with pytest.raises(ValueError, match="unknown force unit 'lbf'"):
        Quantity("force", "lbf")
    with pytest.raises(ValueError, match="unknown quantity 'power'"):
        Quantity("power")


@pytest.mark.parametrize("text, message", [
    ("0", "--frames 0: outside 2..200"),
    ("2.5", "--frames 2.5: not a whole number"),
    ("1e3", "--frames 1e3: not a whole number"),
    ("nan", "--frames nan: not a whole number"),
    ("-3", "--frames -3: outside 2..200"),
    ("9" * 30, "--frames " + "9" * 30 + ": outside 2..200"),
    ("", "--frames '': not a whole number"),
])
def test_counts(text, message):
    assert parse_count(" +24 ", "--frames", 2, 200) == 24 and parse_count(7) == 7
    with pytest.raises(ValueError, match=exact(message)):
        parse_count(text, "--frames", 2, 200)


def test_lists():
    pivot = Quantity("length", "mm", -1e4, 1e4)
    assert parse_list("10, -5,0.1cm", pivot, "--pivot", n=3) == [10.0, -5.0, 1.0]
    with pytest.raises(ValueError, match=exact("--pivot 1,2: expected 3 values, got 2")):
        parse_list("1,2", pivot, "--pivot", n=3)
    with pytest.raises(ValueError, match=exact(
            "--loads '0,,8': expected comma-separated values, none empty")):
        parse_list("0,,8", FORCE, "--loads")
    with pytest.raises(ValueError, match=exact("--loads nan: not a finite number")):
        parse_list("0,nan", FORCE, "--loads")


def test_levels_match_arange_and_are_capped():
    assert parse_levels("0:800:100", FORCE).tolist() == np.arange(0, 850, 100.0).tolist()
    assert parse_levels("0,0.2kN", FORCE).tolist() == [0.0, 200.0]
    assert parse_levels("0:0.8kN:200", FORCE).tolist() == [0, 200, 400, 600, 800]
    for text, message in [
        ("0:800:1e-9", "--loads 0:800:1e-9: 8e11 levels, at most 1000"),
        ("0:800:1e-320", "--loads 0:800:1e-320: inf levels, at most 1000"),
        ("800:0:100", "--loads 800:0:100: need start <= stop and step > 0"),
        ("0:800:0", "--loads 0:800:0: need start <= stop and step > 0"),
        ("0:800", "--loads 0:800: expected start:stop:step, e.g. 0:800:100"),
    ]:
        with pytest.raises(ValueError, match=exact(message)):
            parse_levels(text, FORCE, "--loads")


def test_bands():
    hz = Quantity("frequency", "Hz", 0, 1e5)
    assert parse_band("2:0.16kHz", hz) == (2.0, 160.0)
    with pytest.raises(ValueError, match=exact("--band 160:2: expected LO < HI")):
        parse_band("160:2", hz, "--band")
    with pytest.raises(ValueError, match=exact("--band 1:2:3: expected LO:HI, e.g. 2:160")):
        parse_band("1:2:3", hz, "--band")


def test_environment_variables_name_themselves(monkeypatch):
    gb = Quantity("memory", "GB", 0, 1e6, open_low=True, result="B")
    monkeypatch.setenv("FLEXARM_MEMORY_GB", "2")
    assert env_number("FLEXARM_MEMORY_GB", gb) == 2 * 1024.0**3
    monkeypatch.setenv("FLEXARM_MEMORY_GB", "512MB")
    assert env_number("FLEXARM_MEMORY_GB", gb) == 512 * 1024.0**2
    monkeypatch.setenv("FLEXARM_MEMORY_GB", " ")
    assert env_number("FLEXARM_MEMORY_GB", gb) is None
    for text, why in [("abc", "not a number"), ("-1", "must be > 0 and <= 1e6 GB"),
                      ("nan", "not a finite number")]:
        monkeypatch.setenv("FLEXARM_MEMORY_GB", text)
        with pytest.raises(ValueError, match=re.escape(f"FLEXARM_MEMORY_GB={text}: {why}")):
            env_number("FLEXARM_MEMORY_GB", gb)
